# Type stubs of the extension module warpchol._warpchol (python/warpchol_module.cc), which
# the package warpchol re-exports. Keep in step with the bindings there.

from typing import Sequence, Union

import numpy as np
import numpy.typing as npt
import scipy.sparse
from scipy.sparse.linalg import LinearOperator

__version__: str

# A SciPy sparse matrix in CSC or CSR format (csc_matrix, csr_matrix; csc_array and
# csr_array, which SciPy 1.10, Debian 12's, derives from spmatrix).
SparseMatrix = scipy.sparse.spmatrix
# Any SciPy sparse matrix (update() and downdate() convert it to CSC).
AnySparseMatrix = scipy.sparse.spmatrix

class Error(RuntimeError):
    """Base class of warpchol's errors: a one-line message that says what is wrong and where."""

class InputError(Error):
    """An argument the solver cannot use: a column out of range, a C whose rows the factor
    does not couple, a call the method does not offer."""

class MatrixError(Error):
    """A matrix the solver cannot factor, naming the entry: not square, not symmetric, a NaN
    or an infinity, an entry outside the analyzed pattern."""

class NotPositiveDefinite(MatrixError):
    """A matrix that is not positive definite: names the column and its pivot."""

class SparseCholesky:
    """A sparse Cholesky solver, A = P L L^T P^T, that refactorizes in part."""

    def __init__(
        self,
        method: str = "supernodal",
        ordering: str = "metis",
        threads: int = 1,
        change_method: str = "auto",
    ) -> None:
        """method: "supernodal", "left" or "up"; ordering: "metis", "amd" or "natural";
        change_method: "auto", "flops", "recompute" or "update"."""
    def analyze(self, A: SparseMatrix) -> None:
        """Fill-reducing ordering and symbolic analysis of the pattern of A."""
    def factorize(self, A: SparseMatrix) -> None:
        """Numeric factorization of A: the analyzed pattern or a subset of it (missing entries are zeros)."""
    def refactorize(self, A: SparseMatrix, changed_columns: Union[Sequence[int], npt.ArrayLike]) -> None:
        """Partial refactorization after the entries of changed_columns (and the same rows) changed."""
    def update(self, C: AnySparseMatrix) -> None:
        """The factor of A + C C^T, in place (C: n x k)."""
    def downdate(self, C: AnySparseMatrix) -> None:
        """The factor of A - C C^T, in place; NotPositiveDefinite leaves the factor of A."""
    def solve(self, b: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """x with A x = b, for b of shape (n,) or (n, k)."""
    def __call__(self, b: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """solve(b)."""
    def inverse_operator(self) -> LinearOperator:
        """A^-1 as a scipy.sparse.linalg.LinearOperator of shape (n, n), float64."""
    @property
    def n(self) -> int:
        """Rows (and columns) of the analyzed matrix; 0 before analyze()."""
    @property
    def shape(self) -> tuple[int, int]:
        """(n, n)."""
    @property
    def storage(self) -> str:
        """How the analyzed matrix stores its entries: "full" or "lower"."""
    @property
    def flops(self) -> float:
        """Flops of a full factorization by the chosen method."""
    @property
    def flops_recomputed(self) -> float:
        """Flops of the last factorize() or refactorize()."""
    @property
    def columns_recomputed(self) -> int:
        """Columns of L the last factorize() or refactorize() computed."""
    @property
    def state(self) -> str:
        """What the solver holds: "empty", "analyzed" or "factorized"."""
    @property
    def timings(self) -> dict[str, float]:
        """Seconds of the last analyze, factorize, refactorize and solve, inside the solver."""
    @property
    def statistics(self) -> dict[str, Union[int, float, str, bool]]:
        """Sizes, fill, flops and counts of the factorization; how the last change was taken."""
