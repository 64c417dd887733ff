#!/bin/sh
# The installed package, as another project uses it: install this build into an empty
# prefix, configure examples/step-8-partial against that prefix only (find_package
# (warpchol) must find the package there, not this build), build the example (one file:
# the library is the installed one) and run it. The example fails (exit 1) if a partial
# refactorization's solution differs from a fresh factorization's by more than 1e-12.
#
#   install_example.sh BUILD_DIR EXAMPLE_DIR WORK_DIR CXX_COMPILER BUILD_TYPE
set -eu
build=$1 example=$2 work=$3 compiler=$4 build_type=$5

rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
for installed in lib/libwarpchol.a include/warpchol/lac/sparse_direct_cholesky.h \
                 lib/cmake/warpchol/warpcholConfig.cmake lib/cmake/warpchol/warpcholTargets.cmake; do
  test -f "$work/prefix/$installed" || { echo "not installed: $installed"; exit 1; }
done

cmake -S "$example" -B "$work/example" -DCMAKE_BUILD_TYPE="$build_type" \
      -DCMAKE_CXX_COMPILER="$compiler" -DCMAKE_PREFIX_PATH="$work/prefix" > "$work/configure.log"
grep -q "^warpchol_DIR:PATH=$work/prefix/lib/cmake/warpchol\$" "$work/example/CMakeCache.txt" ||
  { echo "find_package(warpchol) did not find the installed package"; exit 1; }
cmake --build "$work/example" > "$work/build.log" ||
  { cat "$work/build.log"; exit 1; }
if ! "$work/example/step-8-partial" > "$work/output.txt" 2>&1; then
  cat "$work/output.txt"
  exit 1
fi
cat "$work/output.txt"
# Five steps, each refactorized in part (fewer flops than a full factorization).
test "$(grep -c "partial refactorization: .* % of the flops" "$work/output.txt")" -eq 5
! grep -q "100.0 % of the flops" "$work/output.txt"
