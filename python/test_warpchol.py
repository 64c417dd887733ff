"""Tests of the Python module warpchol (python/warpchol_module.cc), against SciPy.

Solutions equal SciPy's spsolve on CSC and CSR matrices with both triangles stored or
one, unsorted or int64 indices, one or several right-hand sides; a partial
refactorization recomputes part of the factor and equals a fresh factorization; update()
and downdate() by C in any SciPy format equal a fresh factorization of A + C C^T and A,
a downdate to an indefinite matrix raises NotPositiveDefinite and leaves the factor as it
was; a matrix whose pattern is a subset of the analyzed one (explicit zeros dropped) gives
the factor of the full pattern with explicit zeros, to the bit; bad input raises the
module's exceptions with one-line messages (a NaN, an infinity and an entry outside the
analyzed pattern each its own, naming the entry as the user stores it); the inverse as a
SciPy LinearOperator; every call documented; the snippets of the README and doc/python.md
run and print what the pages show.

    PYTHONPATH=build/python python3 python/test_warpchol.py    (ctest -R python/warpchol)

python/install_venv.sh runs it again in a virtual environment that pip installed the
package into (ctest -R python/install_venv).
"""

import contextlib
import io
import os
import re
import unittest

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import warpchol


def laplacian(k, shift=0.01):
    """The 2D Laplacian on a k x k grid plus shift * I: symmetric positive definite, CSC."""
    t = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(k, k))
    eye = sp.eye(k)
    return (sp.kron(t, eye) + sp.kron(eye, t) + shift * sp.eye(k * k)).tocsc()


def scaled_block(a, columns, factor):
    """a with the entries (i, j), i and j both in columns, multiplied by factor (same pattern)."""
    a = a.tocsc(copy=True)
    rows = a.indices
    cols = np.repeat(np.arange(a.shape[1]), np.diff(a.indptr))
    inside = np.isin(rows, columns) & np.isin(cols, columns)
    a.data[inside] *= factor
    return a


def relative_error(x, reference):
    return np.abs(x - reference).max() / np.abs(reference).max()


def penalty_and_edge_columns(a, dofs, edges, seed=1):
    """C (n x k): a column sqrt(a[i, i]) e_i per dof i, and one of random values on each
    edge (i, j) of the grid (coupled in a, hence in its factor)."""
    rng = np.random.default_rng(seed)
    n = a.shape[0]
    diagonal = a.diagonal()
    rows, columns, values = [], [], []
    for t, i in enumerate(dofs):
        rows.append(i)
        columns.append(t)
        values.append(np.sqrt(diagonal[i]))
    for t, (i, j) in enumerate(edges, start=len(dofs)):
        for row in (i, j):
            rows.append(row)
            columns.append(t)
            values.append(rng.uniform(-1, 1) * np.sqrt(diagonal[row]))
    return sp.coo_matrix((values, (rows, columns)), shape=(n, len(dofs) + len(edges)))


class Solve(unittest.TestCase):
    def setUp(self):
        self.a = laplacian(30)
        self.b = np.sin(np.arange(self.a.shape[0]) * 0.37) + 1.0
        self.reference = spla.spsolve(self.a, self.b)

    def check_solves(self, matrix, storage):
        solver = warpchol.SparseCholesky()
        solver.analyze(matrix)
        solver.factorize(matrix)
        self.assertEqual(solver.storage, storage)
        self.assertLess(relative_error(solver.solve(self.b), self.reference), 1e-10)

    def test_formats_and_triangles(self):
        a = self.a
        for name, matrix, storage in [
            ("csc full", a, "full"),
            ("csr full", a.tocsr(), "full"),
            ("csc lower", sp.tril(a, format="csc"), "lower"),
            ("csr lower", sp.tril(a, format="csr"), "lower"),
            ("csc upper", sp.triu(a, format="csc"), "lower"),
            ("csr upper", sp.triu(a, format="csr"), "lower"),
        ]:
            with self.subTest(name):
                self.check_solves(matrix, storage)

    def test_unsorted_and_int64_indices(self):
        unsorted = self.a.copy()
        for j in range(unsorted.shape[1]):  # reverse each column's entries
            begin, end = unsorted.indptr[j], unsorted.indptr[j + 1]
            unsorted.indices[begin:end] = unsorted.indices[begin:end][::-1].copy()
            unsorted.data[begin:end] = unsorted.data[begin:end][::-1].copy()
        unsorted.has_sorted_indices = False
        self.check_solves(unsorted, "full")
        wide = self.a.copy()
        wide.indptr = wide.indptr.astype(np.int64)
        wide.indices = wide.indices.astype(np.int64)
        self.check_solves(wide, "full")

    def test_several_right_hand_sides(self):
        solver = warpchol.SparseCholesky()
        solver.factorize(self.a)
        rhs = np.column_stack([self.b, 2 * self.b, np.ones_like(self.b)])
        for order in ("C", "F"):
            with self.subTest(order):
                x = solver.solve(np.array(rhs, order=order))
                self.assertEqual(x.shape, rhs.shape)
                self.assertLess(relative_error(x, spla.spsolve(self.a, rhs)), 1e-10)

    def test_methods_and_orderings(self):
        for method, ordering in [("left", "amd"), ("up", "natural"), ("supernodal", "amd")]:
            with self.subTest(method=method, ordering=ordering):
                solver = warpchol.SparseCholesky(method=method, ordering=ordering)
                solver.factorize(self.a)
                self.assertLess(relative_error(solver.solve(self.b), self.reference), 1e-10)


class Refactorize(unittest.TestCase):
    def test_partial_equals_fresh(self):
        a = laplacian(40)
        b = np.ones(a.shape[0])
        changed = np.arange(810, 830)
        a2 = scaled_block(a, changed, 3.0)
        for method in ("supernodal", "left"):
            with self.subTest(method):
                solver = warpchol.SparseCholesky(method=method)
                solver.factorize(a)
                self.assertEqual(solver.flops_recomputed, solver.flops)
                solver.refactorize(a2, changed)
                self.assertLess(0, solver.columns_recomputed)
                self.assertLess(solver.columns_recomputed, solver.n)
                self.assertLess(solver.flops_recomputed, solver.flops)
                fresh = warpchol.SparseCholesky(method=method)
                fresh.factorize(a2)
                x = solver.solve(b)
                self.assertLess(relative_error(x, fresh.solve(b)), 1e-12)
                self.assertLess(relative_error(x, spla.spsolve(a2, b)), 1e-10)

    def factored_and_changed(self):
        """A 20 x 20 grid's Laplacian factored, and the same with the block of unknowns 100-109 doubled."""
        a = laplacian(20)
        solver = warpchol.SparseCholesky()
        solver.factorize(a)
        return solver, np.ones(a.shape[0]), scaled_block(a, np.arange(100, 110), 2.0)

    def test_unlisted_change_is_found(self):
        solver, b, a2 = self.factored_and_changed()
        solver.refactorize(a2, [])
        self.assertGreaterEqual(solver.columns_recomputed, 10)
        self.assertLess(relative_error(solver.solve(b), spla.spsolve(a2, b)), 1e-10)

    def test_complete_listing_reads_only_those_columns(self):
        solver, b, a2 = self.factored_and_changed()
        solver.refactorize(a2, np.arange(100, 110), complete=True)
        self.assertLess(relative_error(solver.solve(b), spla.spsolve(a2, b)), 1e-10)
        # A change left out of a complete listing is not read.
        a3 = scaled_block(a2, np.arange(200, 205), 3.0)
        solver.refactorize(a3, [], complete=True)
        self.assertLess(relative_error(solver.solve(b), spla.spsolve(a2, b)), 1e-10)
        solver.refactorize(a3, [])
        self.assertLess(relative_error(solver.solve(b), spla.spsolve(a3, b)), 1e-10)

    def test_statistics_and_timings(self):
        solver = warpchol.SparseCholesky()
        solver.factorize(laplacian(20))
        solver.solve(np.ones(400))
        statistics = solver.statistics
        self.assertEqual(statistics["n"], 400)
        self.assertGreater(statistics["nnz_l"], statistics["nnz_a"])
        self.assertEqual(statistics["flops"], solver.flops)
        self.assertEqual(set(solver.timings), {"analyze", "factorize", "refactorize", "solve"})
        self.assertGreater(solver.timings["factorize"], 0)
        self.assertGreater(solver.timings["solve"], 0)


class Errors(unittest.TestCase):
    def expect(self, exception, pattern, action):
        with self.assertRaises(exception) as raised:
            action()
        message = str(raised.exception)
        self.assertNotIn("\n", message)
        self.assertRegex(message, pattern)

    def test_bad_input(self):
        a = laplacian(5)
        solver = warpchol.SparseCholesky()
        asymmetric = a.tolil()
        asymmetric[0, 1] = 5.0
        self.expect(warpchol.MatrixError, r"not symmetric: A\(", lambda: solver.factorize(asymmetric.tocsc()))
        indefinite = a.copy()
        indefinite.data *= -1
        self.expect(warpchol.NotPositiveDefinite, r"pivot of column \d+ is -",
                    lambda: warpchol.SparseCholesky().factorize(indefinite))
        self.expect(warpchol.MatrixError, "not square: 5x4",
                    lambda: warpchol.SparseCholesky().factorize(sp.random(5, 4, 0.5, format="csc")))
        self.expect(TypeError, "coo format", lambda: warpchol.SparseCholesky().factorize(a.tocoo()))
        self.expect(TypeError, "expected a SciPy sparse matrix", lambda: warpchol.SparseCholesky().factorize(3))
        # refactorize() before analyze() analyzes and factors in full, as factorize() does.
        fresh = warpchol.SparseCholesky()
        self.assertEqual(fresh.state, "empty")
        fresh.refactorize(a, [0])
        self.assertEqual(fresh.state, "factorized")
        self.assertLess(abs(a @ fresh.solve(np.ones(25)) - 1).max(), 1e-12)
        self.assertRaises(warpchol.NotPositiveDefinite, fresh.factorize, indefinite)
        self.assertEqual(fresh.state, "analyzed")  # a refused matrix leaves the pattern, no factor
        self.expect(warpchol.Error, r"solve\(\) called before analyze\(\)",
                    lambda: warpchol.SparseCholesky().solve(np.ones(25)))
        analyzed_only = warpchol.SparseCholesky()
        analyzed_only.analyze(a)
        self.expect(warpchol.Error, r"solve\(\) called without a valid factorization",
                    lambda: analyzed_only.solve(np.ones(25)))
        duplicated = sp.csc_matrix((np.ones(4), np.array([1, 0, 0, 1]), np.array([0, 3, 4])), shape=(2, 2))
        self.expect(warpchol.MatrixError, r"twice", lambda: warpchol.SparseCholesky().factorize(duplicated))

        solver = warpchol.SparseCholesky()
        solver.factorize(a)
        self.expect(warpchol.MatrixError, r"matrix is 36x36, the analyzed one 25x25",
                    lambda: solver.refactorize(laplacian(6), [0]))
        solver.factorize(a.tocsr())  # the same arrays: for a symmetric matrix, the same matrix
        self.expect(warpchol.InputError, r"changed column 25 out of range \[0, 25\)",
                    lambda: solver.refactorize(a, [25]))
        self.expect(ValueError, r"shape \(24\), expected \(25,\)", lambda: solver.solve(np.ones(24)))
        nan = a.copy()
        nan.data[3] = np.nan
        self.expect(warpchol.MatrixError, r"^matrix entry A\(\d+,\d+\) is NaN$", lambda: solver.refactorize(nan, [0]))
        # The failed load dropped the factor; the next refactorization factors in full.
        self.expect(warpchol.Error, "without a valid factorization", lambda: solver.solve(np.ones(25)))
        solver.refactorize(a, [0])
        self.assertEqual(solver.columns_recomputed, 25)
        self.assertLess(relative_error(solver.solve(np.ones(25)), spla.spsolve(a, np.ones(25))), 1e-10)


class SubsetPattern(unittest.TestCase):
    """A matrix that lost explicit zeros (SciPy's arithmetic drops them) is the analyzed
    pattern with zeros there; an entry outside it, a NaN and an infinity are refused, each
    with its own one-line message naming the entry as the user stores it."""

    expect = Errors.expect

    def setUp(self):
        self.a = laplacian(20)
        self.b = np.sin(np.arange(self.a.shape[0]) * 0.37) + 1.0
        # The analyzed pattern: a's, with explicit zeros at the couplings of 10 with 11 (their
        # values cancelled) and of 200 with 243 (not yet assembled).
        self.a.eliminate_zeros()
        entries = self.a.tocoo()
        values = entries.data.copy()
        values[((entries.row == 10) & (entries.col == 11)) | ((entries.row == 11) & (entries.col == 10))] = 0.0
        self.full = sp.csc_matrix((np.append(values, [0.0, 0.0]),
                                   (np.append(entries.row, [200, 243]), np.append(entries.col, [243, 200]))),
                                  shape=self.a.shape)
        self.assertEqual(self.full.nnz, self.a.nnz + 2)
        self.assertEqual(np.count_nonzero(self.full.data == 0.0), 4)
        self.a = self.full.copy()
        self.a.eliminate_zeros()

    def subset(self, matrix, format):
        """matrix in format, without its stored zeros, as SciPy's arithmetic leaves it."""
        subset = matrix.asformat(format, copy=True)
        subset.eliminate_zeros()
        return subset

    def test_subset_gives_the_factor_of_the_full_pattern(self):
        # A + D with a diagonal D: SciPy drops the explicit zeros on the way.
        d = sp.diags(np.linspace(0.1, 1.0, self.a.shape[0]))
        summed = (self.full + d).tocsc()
        self.assertEqual(summed.nnz, self.full.nnz - 4)
        with_zeros = self.full.copy()
        with_zeros.setdiag(with_zeros.diagonal() + d.diagonal())
        self.assertEqual(with_zeros.nnz, self.full.nnz)
        for format, triangle in [("csc", None), ("csr", None), ("csc", "lower"), ("csr", "upper")]:
            with self.subTest(format=format, triangle=triangle):
                cut = {None: lambda m: m, "lower": sp.tril, "upper": sp.triu}[triangle]
                analyzed = cut(self.full).asformat(format)
                reference = warpchol.SparseCholesky()
                reference.analyze(analyzed)
                reference.factorize(cut(with_zeros).asformat(format))
                solver = warpchol.SparseCholesky()
                solver.analyze(analyzed)
                given = self.subset(cut(summed), format)
                self.assertEqual(given.nnz, analyzed.nnz - (4 if triangle is None else 2))
                solver.factorize(given)
                x = solver.solve(self.b)
                np.testing.assert_array_equal(x, reference.solve(self.b))
                self.assertLess(relative_error(x, spla.spsolve(with_zeros, self.b)), 1e-10)
                # refactorize() takes a subset too: the same factor, to the bit, as the same
                # calls on the full pattern with explicit zeros. auto chooses by measured
                # rates, which differ from one run to the next: its reference is made by the
                # method it chose.
                columns = np.arange(150, 160)
                changed = scaled_block(summed, columns, 2.0)
                changed_with_zeros = scaled_block(with_zeros, columns, 2.0)
                for change_method in ("recompute", "update", "flops", "auto"):
                    partial = warpchol.SparseCholesky(change_method=change_method)
                    partial.analyze(analyzed)
                    partial.factorize(given)
                    partial.refactorize(self.subset(cut(changed), format), columns)
                    self.assertLess(partial.columns_recomputed, partial.n)
                    chosen = partial.statistics["method"]
                    self.assertIn(chosen, ("update", "partial"))
                    if change_method == "auto":
                        change_method = {"update": "update", "partial": "recompute"}[chosen]
                    reference = warpchol.SparseCholesky(change_method=change_method)
                    reference.analyze(analyzed)
                    reference.factorize(cut(with_zeros).asformat(format))
                    reference.refactorize(cut(changed_with_zeros).asformat(format), columns)
                    self.assertEqual(reference.statistics["method"], chosen)
                    x = partial.solve(self.b)
                    np.testing.assert_array_equal(x, reference.solve(self.b))
                    self.assertLess(relative_error(x, spla.spsolve(changed_with_zeros, self.b)), 1e-10)

    def test_entry_outside_the_pattern(self):
        solver = warpchol.SparseCholesky()
        solver.factorize(self.a)
        outside = self.a.tolil()
        outside[3, 250] = outside[250, 3] = 0.5
        outside = outside.tocsc()
        self.expect(warpchol.MatrixError,
                    r"^matrix entry A\((3,250|250,3)\) lies outside the analyzed pattern \(analyze the new pattern first\)$",
                    lambda: solver.factorize(outside))
        lower = warpchol.SparseCholesky()
        lower.factorize(sp.tril(self.a, format="csr"))
        # As the user stores it: row 250, column 3 of a CSR lower triangle.
        self.expect(warpchol.MatrixError, r"^matrix entry A\(250,3\) lies outside the analyzed pattern",
                    lambda: lower.refactorize(sp.tril(outside, format="csr"), [3]))
        upper = warpchol.SparseCholesky()
        upper.factorize(sp.triu(self.a, format="csc"))
        self.expect(warpchol.MatrixError, r"^matrix entry A\(3,250\) lies outside the analyzed pattern",
                    lambda: upper.factorize(sp.triu(outside, format="csc")))
        # After a refused matrix, the analyzed pattern still takes a subset of it.
        solver.factorize(self.subset(self.full, "csc"))
        self.assertLess(relative_error(solver.solve(self.b), spla.spsolve(self.a, self.b)), 1e-10)

    def test_nan_and_infinity_named_as_such(self):
        for format in ("csc", "csr"):
            for value, what in [(np.nan, "NaN"), (np.inf, r"infinite \(inf\)"), (-np.inf, r"infinite \(-inf\)")]:
                for i, j in [(5, 5), (5, 6), (6, 5), (25, 5)]:
                    with self.subTest(format=format, value=value, entry=(i, j)):
                        solver = warpchol.SparseCholesky()
                        solver.analyze(self.full)
                        bad = self.full.asformat(format, copy=True)
                        bad[i, j] = value
                        # Not "not symmetric": the bad value is named as what it is.
                        self.expect(warpchol.MatrixError, rf"^matrix entry A\({i},{j}\) is {what}$",
                                    lambda: solver.factorize(bad))
                        solver.factorize(self.full)
                        self.expect(warpchol.MatrixError, rf"^matrix entry A\({i},{j}\) is {what}$",
                                    lambda: solver.refactorize(bad, [i, j]))
        # In a subset pattern too.
        solver = warpchol.SparseCholesky()
        solver.analyze(self.full)
        bad = self.subset(self.full, "csc")
        bad[7, 7] = np.nan
        self.expect(warpchol.MatrixError, r"^matrix entry A\(7,7\) is NaN$", lambda: solver.factorize(bad))


class ScipyInterface(unittest.TestCase):
    """What a SciPy or scikit-sparse user reaches for: cholesky(A), factor(b), the inverse
    as a LinearOperator, documentation on every call."""

    def setUp(self):
        self.a = laplacian(15)
        self.b = np.cos(np.arange(self.a.shape[0]) * 0.1)

    def test_cholesky_and_call(self):
        solver = warpchol.cholesky(self.a, ordering="amd")
        self.assertIsInstance(solver, warpchol.SparseCholesky)
        self.assertEqual(solver.shape, self.a.shape)
        np.testing.assert_array_equal(solver(self.b), solver.solve(self.b))
        self.assertLess(relative_error(solver(self.b), spla.spsolve(self.a, self.b)), 1e-10)

    def test_inverse_operator(self):
        solver = warpchol.cholesky(self.a)
        inverse = solver.inverse_operator()
        self.assertIsInstance(inverse, spla.LinearOperator)
        self.assertEqual(inverse.shape, self.a.shape)
        self.assertEqual(inverse.dtype, np.float64)
        np.testing.assert_array_equal(inverse @ self.b, solver.solve(self.b))
        np.testing.assert_array_equal(inverse.rmatvec(self.b), solver.solve(self.b))
        block = np.column_stack([self.b, 2 * self.b])
        np.testing.assert_array_equal(inverse @ block, solver.solve(block))
        # As a preconditioner: CG on a nearby matrix converges in a few iterations.
        nearby = (self.a + sp.diags(np.full(self.a.shape[0], 0.05))).tocsc()
        iterations = []
        x, info = spla.cg(nearby, self.b, M=inverse, callback=lambda xk: iterations.append(1), tol=1e-10, atol=0.0)
        self.assertEqual(info, 0)
        self.assertLess(len(iterations), 15)
        self.assertLess(relative_error(x, spla.spsolve(nearby, self.b)), 1e-8)
        # Shift-invert: the smallest eigenvalue of A.
        smallest = spla.eigsh(spla.aslinearoperator(self.a), k=1, sigma=0, OPinv=inverse, which="LM")[0][0]
        self.assertAlmostEqual(smallest, np.linalg.eigvalsh(self.a.toarray())[0], places=8)

    def test_documented(self):
        self.assertIn("refactorize", warpchol.__doc__)
        self.assertIn("scikit-sparse", warpchol.__doc__)
        for name in warpchol.__all__:
            self.assertTrue(getattr(warpchol, name).__doc__, name)
            self.assertEqual(getattr(warpchol, name).__module__, "warpchol", name)
        for name in ("analyze", "factorize", "refactorize", "update", "downdate", "solve", "__call__",
                     "inverse_operator", "n", "shape", "storage", "flops", "flops_recomputed",
                     "columns_recomputed", "timings", "statistics"):
            with self.subTest(name):
                documentation = getattr(warpchol.SparseCholesky, name).__doc__
                self.assertTrue(documentation and len(documentation.strip()) > 10, name)
        text = io.StringIO()
        with contextlib.redirect_stdout(text):
            help(warpchol)
        for name in ("SparseCholesky", "cholesky", "update", "downdate", "inverse_operator", "NotPositiveDefinite"):
            self.assertIn(name, text.getvalue())

    def test_stubs_name_every_call(self):
        stubs = os.path.join(os.path.dirname(warpchol.__file__), "_warpchol.pyi")
        with open(stubs) as file:
            text = file.read()
        for name in ("analyze", "factorize", "refactorize", "update", "downdate", "solve", "__call__",
                     "inverse_operator", "n", "shape", "storage", "flops", "flops_recomputed",
                     "columns_recomputed", "timings", "statistics"):
            self.assertRegex(text, rf"def {name}\(self", name)
        for name in warpchol.__all__:
            if name != "cholesky":
                self.assertRegex(text, rf"class {name}\b", name)
        self.assertTrue(os.path.isfile(os.path.join(os.path.dirname(warpchol.__file__), "py.typed")))


class UpdateDowndate(unittest.TestCase):
    expect = Errors.expect

    def setUp(self):
        self.a = laplacian(30)
        self.b = np.sin(np.arange(self.a.shape[0]) * 0.37) + 1.0
        self.c = penalty_and_edge_columns(self.a, [40, 41, 450], [(100, 101), (600, 630)])

    def fresh_solve(self, matrix):
        fresh = warpchol.SparseCholesky()
        fresh.factorize(matrix)
        return fresh.solve(self.b)

    def test_update_then_downdate_equal_fresh(self):
        updated = (self.a + self.c @ self.c.T).tocsc()
        for name, c in [("coo", self.c), ("csc", self.c.tocsc()), ("csr", self.c.tocsr()),
                        ("lil", self.c.tolil()), ("csc array", sp.csc_array(self.c))]:
            with self.subTest(name):
                solver = warpchol.SparseCholesky()
                solver.factorize(self.a)
                solver.update(c)
                statistics = solver.statistics
                self.assertEqual(statistics["method"], "update")
                self.assertEqual(statistics["n_updates"], 1)
                x = solver.solve(self.b)
                self.assertLess(relative_error(x, self.fresh_solve(updated)), 1e-12)
                self.assertLess(relative_error(x, spla.spsolve(updated, self.b)), 1e-10)
                solver.downdate(c)
                self.assertLess(relative_error(solver.solve(self.b), self.fresh_solve(self.a)), 1e-12)
                self.assertEqual(solver.statistics["n_updates"], 2)

    def test_duplicates_and_stored_zeros(self):
        # The penalty on dof 40 given as two halves (summed), and a stored zero on a far row.
        c = sp.coo_matrix(([np.sqrt(self.a[40, 40]) / 2, np.sqrt(self.a[40, 40]) / 2, 0.0],
                           ([40, 40, 899], [0, 0, 0])), shape=(900, 1))
        solver = warpchol.SparseCholesky()
        solver.factorize(self.a)
        solver.update(c)
        single = sp.csc_matrix(([np.sqrt(self.a[40, 40])], ([40], [0])), shape=(900, 1))
        self.assertLess(relative_error(solver.solve(self.b), self.fresh_solve((self.a + single @ single.T).tocsc())),
                        1e-12)

    def test_indefinite_downdate_leaves_the_factor(self):
        solver = warpchol.SparseCholesky()
        solver.factorize(self.a)
        before = solver.solve(self.b)
        j = 450
        c = sp.csc_matrix(([np.sqrt(2 * self.a[j, j])], ([j], [0])), shape=(900, 1))
        with self.assertRaises(warpchol.NotPositiveDefinite) as raised:
            solver.downdate(c)
        message = str(raised.exception)
        self.assertNotIn("\n", message)
        self.assertRegex(message, r"downdate would leave the matrix not positive definite: the pivot of column "
                                  r"450 would be -.*stays that of the matrix before")
        # The columns it changed recomputed from A: the solution as before, to rounding.
        self.assertLess(relative_error(solver.solve(self.b), before), 1e-13)
        self.assertLess(relative_error(before, spla.spsolve(self.a, self.b)), 1e-10)
        # ... and takes a downdate that keeps A positive definite.
        half = sp.csc_matrix(([np.sqrt(0.5 * self.a[j, j])], ([j], [0])), shape=(900, 1))
        solver.downdate(half)
        downdated = (self.a - half @ half.T).tocsc()
        self.assertLess(relative_error(solver.solve(self.b), self.fresh_solve(downdated)), 1e-12)

    def test_refactorize_statistics(self):
        solver = warpchol.SparseCholesky()
        solver.factorize(self.a)
        statistics = solver.statistics
        for key in ("method", "update_rank", "update_flops", "partial_flops", "predicted_update_seconds",
                    "predicted_partial_seconds", "predicted_full_seconds", "update_fell_back", "n_updates"):
            self.assertIn(key, statistics)
        self.assertEqual(statistics["method"], "full")
        penalty = penalty_and_edge_columns(self.a, [300, 301, 302], [])
        changed = (self.a + penalty @ penalty.T).tocsc()
        solver.refactorize(changed, [300, 301, 302])
        statistics = solver.statistics
        self.assertIn(statistics["method"], ("update", "partial"))
        self.assertEqual(statistics["update_rank"], 3)
        for key in ("predicted_update_seconds", "predicted_partial_seconds", "predicted_full_seconds"):
            self.assertGreater(statistics[key], 0)
        self.assertFalse(statistics["update_fell_back"])
        self.assertLess(relative_error(solver.solve(self.b), self.fresh_solve(changed)), 1e-12)

    def test_bad_input(self):
        solver = warpchol.SparseCholesky()
        solver.factorize(self.a)
        expect = self.expect
        expect(TypeError, "expected C as a SciPy sparse matrix", lambda: solver.update(np.ones((900, 1))))
        expect(warpchol.InputError, "C has 899 rows, the matrix 900",
               lambda: solver.update(sp.csc_matrix((899, 1))))
        far = sp.csc_matrix(([1.0, 1.0], ([0, 899], [0, 0])), shape=(900, 1))
        expect(warpchol.InputError, r"entries in rows \d+ and \d+, which the factor's structure does not couple",
               lambda: solver.update(far))
        nan = sp.csc_matrix(([np.nan], ([3], [0])), shape=(900, 1))
        expect(warpchol.MatrixError, "not finite", lambda: solver.downdate(nan))
        left = warpchol.SparseCholesky(method="left")
        left.factorize(self.a)
        expect(warpchol.InputError, "needs the supernodal method", lambda: left.update(self.c))
        expect(warpchol.Error, "before analyze", lambda: warpchol.SparseCholesky().update(self.c))
        # None of it changed the factor.
        self.assertLess(relative_error(solver.solve(self.b), spla.spsolve(self.a, self.b)), 1e-10)


class ReadmeSnippet(unittest.TestCase):
    """The Python snippets of the README and of doc/python.md run and print what the page
    shows (numbers aside)."""

    readme = os.environ.get("WARPCHOL_README",
                            os.path.join(os.path.dirname(__file__), "..", "README.md"))

    def check_snippet(self, page, heading):
        with open(page) as file:
            text = file.read()
        section = text[text.index(heading):]
        snippet = re.search(r"```python\n(.*?)```", section, re.S).group(1)
        shown = re.search(r"```python\n.*?```\n.*?```text\n(.*?)```", section, re.S).group(1)
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            exec(compile(snippet, os.path.basename(page), "exec"), {})

        def shape(output):
            return re.sub(r"[0-9][0-9.e+-]*", "#", output).strip()

        self.assertEqual(shape(printed.getvalue()), shape(shown))

    def test_snippet(self):
        self.check_snippet(self.readme, "## From other programs")

    def test_python_page_snippet(self):
        self.check_snippet(os.path.join(os.path.dirname(self.readme), "doc", "python.md"),
                           "## A tour")


if __name__ == "__main__":
    unittest.main(verbosity=2)
