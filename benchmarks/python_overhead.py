"""What the Python module adds to the C++ calls it makes (issue 21: under 5 % at 10k unknowns).

    build/warpchol-torus-matrix --dofs 10000 --output output/benchmarks/torus_10000.mtx
    PYTHONPATH=build/python python3 benchmarks/python_overhead.py output/benchmarks/torus_10000.mtx \
        [--format csc|csr] [--lower] [--repeat R] [--changed-fraction F]

For each call (analyze, factorize, refactorize after a change in 1 % of the columns, solve)
it measures, --repeat times, the wall-clock time of the Python call (time.perf_counter
around it) and the time SparseCholesky spent inside it (the module's timings, which the
C++ solver measures itself: the C++ call a C++ program would make on a CSC matrix). The
difference is the module's work: reading SciPy's arrays, comparing the pattern, copying
the values into the solver's CSC form, the result array, pybind11's dispatch. Printed:
the medians of both and the median of (Python / C++ - 1) per call.

One thread for BLAS, as the C++ benchmarks run (OPENBLAS_NUM_THREADS=1 unless set).
"""

import argparse
import os
import statistics
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_THREAD_LIMIT", "1")

import numpy as np  # noqa: E402  (after the thread settings, which OpenBLAS reads at load)
import scipy.io  # noqa: E402
import scipy.sparse as sp  # noqa: E402

import warpchol  # noqa: E402


def scaled_block(a, columns, factor):
    """a with the entries (i, j), i and j both in columns, multiplied by factor (same pattern)."""
    a = a.copy()
    rows = a.indices
    cols = np.repeat(np.arange(a.shape[1]), np.diff(a.indptr))
    inside = np.isin(rows, columns) & np.isin(cols, columns)
    a.data[inside] *= factor
    return a


def measure(call, cpp_seconds, repeat):
    """Medians of the Python call's seconds, the C++ call's, and of their relative difference."""
    python, cpp, overhead = [], [], []
    for _ in range(repeat):
        start = time.perf_counter()
        call()
        python.append(time.perf_counter() - start)
        cpp.append(cpp_seconds())
        overhead.append(python[-1] / cpp[-1] - 1)
    return statistics.median(python), statistics.median(cpp), statistics.median(overhead)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("matrix", help="a symmetric positive definite Matrix Market file")
    parser.add_argument("--repeat", type=int, default=20)
    parser.add_argument("--changed-fraction", type=float, default=0.01)
    parser.add_argument("--format", choices=["csc", "csr"], default="csc")
    parser.add_argument("--lower", action="store_true", help="store the lower triangle only")
    arguments = parser.parse_args()

    a = scipy.io.mmread(arguments.matrix).tocsc()
    a.sort_indices()
    n = a.shape[0]
    # A block of consecutive columns (whole vertices of 3 dofs), its couplings stiffened.
    n_changed = max(3, int(arguments.changed_fraction * n) // 3 * 3)
    changed = np.arange(n // 2 // 3 * 3, n // 2 // 3 * 3 + n_changed)
    matrices = [a, scaled_block(a, changed, 1.5)]
    if arguments.lower:
        matrices = [sp.tril(m, format="csc") for m in matrices]
    if arguments.format == "csr":
        matrices = [m.tocsr() for m in matrices]
    b = np.ones(n)

    solver = warpchol.SparseCholesky()
    solver.factorize(matrices[0])
    step = [0]

    def refactorize():
        step[0] += 1
        solver.refactorize(matrices[step[0] % 2], changed)

    refactorize()
    rows = [
        ("analyze", lambda: solver.analyze(matrices[0]), "analyze", max(3, arguments.repeat // 4)),
        ("factorize", lambda: solver.factorize(matrices[0]), "factorize", arguments.repeat),
        ("refactorize", refactorize, "refactorize", arguments.repeat),
        ("solve", lambda: solver.solve(b), "solve", arguments.repeat),
    ]
    stored = matrices[0]
    print(f"{os.path.basename(arguments.matrix)}: n = {n}, {stored.nnz} entries stored ({arguments.format}, "
          f"{solver.storage}, int{stored.indices.itemsize * 8} indices), nnz(L) = {solver.statistics['nnz_l']}")
    results = []
    for name, call, timing, repeat in rows:
        call()  # warm up
        results.append((name,) + measure(call, lambda timing=timing: solver.timings[timing], repeat))
        if name == "refactorize":
            fraction = solver.flops_recomputed / solver.flops
            print(f"refactorize: {len(changed)} columns changed ({100 * len(changed) / n:.1f} %), "
                  f"{solver.columns_recomputed} recomputed, {100 * fraction:.1f} % of the flops")
        if name == "analyze":
            solver.factorize(matrices[0])
    print(f"{'call':<12} {'Python ms':>10} {'C++ ms':>10} {'overhead':>9}")
    for name, python, cpp, overhead in results:
        print(f"{name:<12} {1e3 * python:>10.3f} {1e3 * cpp:>10.3f} {100 * overhead:>8.2f} %")


if __name__ == "__main__":
    main()
