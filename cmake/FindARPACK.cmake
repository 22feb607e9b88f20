# FindARPACK — ARPACK-NG through pkg-config (Debian: libarpack2-dev). Creates ARPACK::ARPACK.
include(FindPackageHandleStandardArgs)
find_package(PkgConfig QUIET)
if(PKG_CONFIG_FOUND)
  pkg_check_modules(PC_ARPACK QUIET arpack)
endif()
find_library(ARPACK_LIBRARY NAMES arpack HINTS ${PC_ARPACK_LIBRARY_DIRS})
find_package_handle_standard_args(ARPACK REQUIRED_VARS ARPACK_LIBRARY
  REASON_FAILURE_MESSAGE "install the Debian package libarpack2-dev")
if(ARPACK_FOUND AND NOT TARGET ARPACK::ARPACK)
  add_library(ARPACK::ARPACK UNKNOWN IMPORTED)
  set_target_properties(ARPACK::ARPACK PROPERTIES IMPORTED_LOCATION "${ARPACK_LIBRARY}")
endif()
