## The libraries warpchol's solver links that deal.II does not hand over as targets:
## SuiteSparse (CHOLMOD, the peer; AMD, an ordering; SuiteSparse_config), METIS (the
## nested-dissection ordering), BLAS/LAPACK (OpenBLAS: our supernodal kernels and
## CHOLMOD's) and Google Highway (the choice, at run time, of the SIMD target of our own
## kernels: base/simd.h). Found here, as the imported targets warpchol::suitesparse,
## warpchol::metis, warpchol::blas and warpchol::highway, both by warpchol's own build (CMakeLists.txt) and by the installed
## package (warpcholConfig.cmake), so that the exported library names the same targets in
## both places and no path of the building machine is written into the package.
##
## Sets WARPCHOL_MISSING_DEPENDENCIES to the list of what was not found (empty if all
## were); the caller decides whether that is fatal.

set(WARPCHOL_MISSING_DEPENDENCIES "")

find_path(SUITESPARSE_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse)
find_library(CHOLMOD_LIBRARY cholmod)
find_library(AMD_LIBRARY amd)
find_library(SUITESPARSECONFIG_LIBRARY suitesparseconfig)
find_path(METIS_INCLUDE_DIR metis.h)
find_library(METIS_LIBRARY metis)
# OpenBLAS (selected by .ci/setup through update-alternatives, pinned to one thread per
# call at run time) is the BLAS/LAPACK of both our supernodal kernels and CHOLMOD:
# comparisons use the same BLAS.
find_library(OPENBLAS_LIBRARY openblas)
# Highway (Debian: libhwy-dev): its foreach_target compiles each kernel file once per SIMD
# target, and its runtime dispatch picks the best one the CPU has.
find_path(HWY_INCLUDE_DIR hwy/highway.h)
find_library(HWY_LIBRARY hwy)

foreach(variable SUITESPARSE_INCLUDE_DIR CHOLMOD_LIBRARY AMD_LIBRARY SUITESPARSECONFIG_LIBRARY
                 METIS_INCLUDE_DIR METIS_LIBRARY OPENBLAS_LIBRARY
                 HWY_INCLUDE_DIR HWY_LIBRARY)
  if(NOT ${variable})
    list(APPEND WARPCHOL_MISSING_DEPENDENCIES ${variable})
  endif()
endforeach()

# An imported target warpchol::NAME with these include directories and libraries, unless
# it exists (the package found twice).
function(warpchol_imported_target name include_directories libraries)
  if(NOT TARGET warpchol::${name})
    add_library(warpchol::${name} INTERFACE IMPORTED)
    set_target_properties(warpchol::${name} PROPERTIES
      INTERFACE_INCLUDE_DIRECTORIES "${include_directories}" INTERFACE_LINK_LIBRARIES "${libraries}")
  endif()
endfunction()

if(NOT WARPCHOL_MISSING_DEPENDENCIES)
  warpchol_imported_target(suitesparse "${SUITESPARSE_INCLUDE_DIR}"
    "${CHOLMOD_LIBRARY};${AMD_LIBRARY};${SUITESPARSECONFIG_LIBRARY}")
  warpchol_imported_target(metis "${METIS_INCLUDE_DIR}" "${METIS_LIBRARY}")
  warpchol_imported_target(blas "" "${OPENBLAS_LIBRARY}")
  warpchol_imported_target(highway "${HWY_INCLUDE_DIR}" "${HWY_LIBRARY}")
endif()
