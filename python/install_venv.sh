#!/bin/sh
# The package installs offline into a fresh virtual environment and works there:
#   install_venv.sh PYTHON SOURCE_DIR BUILD_DIR WORK_DIR
# makes WORK_DIR/venv (--system-site-packages: Debian's NumPy and SciPy), pip installs
# SOURCE_DIR/python into it with no index and no build isolation (nothing downloaded),
# the extension module taken from BUILD_DIR's target warpchol_python (setup.py,
# WARPCHOL_CMAKE_BUILD_DIR) or, with BUILD_DIR "", built from nothing in WORK_DIR as a
# user's pip install builds it (about 2 minutes on two cores); then, from WORK_DIR, checks
# that warpchol is imported from the environment with its stubs, solves, and runs
# python/test_warpchol.py there.
set -eu
python=$1 source_dir=$2 build_dir=$3 work=$4
rm -rf "$work"
mkdir -p "$work"
unset PYTHONPATH PIP_INDEX_URL PIP_EXTRA_INDEX_URL PIP_FIND_LINKS WARPCHOL_CMAKE_BUILD_DIR
"$python" -m venv --system-site-packages "$work/venv"
if [ -n "$build_dir" ]; then
  export WARPCHOL_CMAKE_BUILD_DIR="$build_dir"
fi
WARPCHOL_BUILD_BASE=$work/setuptools \
  "$work/venv/bin/python" -m pip install --isolated --no-build-isolation --no-index --no-cache-dir \
  --disable-pip-version-check --no-input "$source_dir/python"
cd "$work"
"$work/venv/bin/python" - "$work/venv" <<'PYTHON'
import os, sys
import numpy as np, scipy.sparse as sp
import warpchol
venv = os.path.realpath(sys.argv[1])
package = os.path.dirname(os.path.realpath(warpchol.__file__))
assert package.startswith(venv + os.sep), f"warpchol imported from {package}, not from {venv}"
for name in ("py.typed", "_warpchol.pyi", "__init__.py"):
    assert os.path.isfile(os.path.join(package, name)), f"{name} not installed"
a = sp.diags([-1.0, 2.5, -1.0], [-1, 0, 1], shape=(5, 5), format="csc")
x = warpchol.cholesky(a)(np.ones(5))
assert np.allclose(a @ x, 1.0)
print(f"warpchol {warpchol.__version__} from {package}: A x = b solved, residual {np.abs(a @ x - 1).max():.1e}")
PYTHON
WARPCHOL_README=$source_dir/README.md "$work/venv/bin/python" "$source_dir/python/test_warpchol.py"
