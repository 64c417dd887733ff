"""warpchol: a sparse Cholesky solver that refactorizes in part, on SciPy sparse matrices.

A = P L L^T P^T for a symmetric positive definite SciPy sparse matrix (CSC or CSR, both
triangles stored or one), with a supernodal left-looking factorization whose
refactorize(A, changed_columns) recomputes only the columns of L that depend on the
changed entries (or updates the factor by the change, where that is cheaper), and
update(C) / downdate(C) for the factor of A +- C C^T in place.

    import numpy as np, scipy.sparse as sp, warpchol
    solver = warpchol.cholesky(A)          # analyze + factorize (SparseCholesky(); factorize(A))
    x = solver(b)                          # or solver.solve(b); b of shape (n,) or (n, k)
    solver.refactorize(A2, [3, 4, 5])      # A2: new values in columns (and rows) 3, 4, 5
    solver.update(C); solver.downdate(C)   # the factor of A2 + C C^T, then of A2 again
    M = solver.inverse_operator()          # A^-1 as a scipy.sparse.linalg.LinearOperator

factorize() and refactorize() take the analyzed pattern or a subset of it (the entries a
matrix leaves out are zeros: SciPy's arithmetic drops explicit zeros); an entry outside
it, a NaN or an infinity raise MatrixError naming the entry, in one line.

For a scikit-sparse (CHOLMOD) user: cholesky(A) -> warpchol.cholesky(A); factor(b) ->
solver(b); factor.cholesky_inplace(A) -> solver.factorize(A) (or refactorize(A,
changed_columns), which recomputes less); factor.update_inplace(C) -> solver.update(C),
update_inplace(C, subtract=True) -> solver.downdate(C). For a SciPy user: factorized(A) and
splu(A).solve -> warpchol.cholesky(A).solve, for a symmetric positive definite A.

Errors: Error, and beneath it InputError, MatrixError and NotPositiveDefinite (a
MatrixError naming the column and its pivot). Sizes, flops and timings: the solver's
statistics and timings properties.
"""

from ._warpchol import (
    Error,
    InputError,
    MatrixError,
    NotPositiveDefinite,
    SparseCholesky,
    __version__,
)

__all__ = [
    "SparseCholesky",
    "cholesky",
    "Error",
    "InputError",
    "MatrixError",
    "NotPositiveDefinite",
]


def cholesky(A, method: str = "supernodal", ordering: str = "metis", threads: int = 1,
             change_method: str = "auto") -> SparseCholesky:
    """A SparseCholesky with the given settings, analyzed and factorized for A (as
    scikit-sparse's cholesky(A)): warpchol.cholesky(A)(b) solves A x = b. Raises as
    SparseCholesky.factorize() does."""
    solver = SparseCholesky(method=method, ordering=ordering, threads=threads, change_method=change_method)
    solver.factorize(A)
    return solver
