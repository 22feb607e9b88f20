# FindSuiteSparse — imported targets for the SuiteSparse components flexrod uses.
# Debian 12 ships SuiteSparse 5.12 without a CMake package configuration, so the
# headers and libraries are located here. Creates SuiteSparse::<comp> for each of
# CHOLMOD, UMFPACK, KLU (plus their dependencies AMD, COLAMD, CAMD, CCOLAMD, BTF, config).
include(FindPackageHandleStandardArgs)

find_path(SuiteSparse_INCLUDE_DIR NAMES cholmod.h
          PATH_SUFFIXES suitesparse
          PATHS /usr/include /usr/local/include)

set(_ss_all config amd camd colamd ccolamd btf cholmod umfpack klu)
foreach(_c IN LISTS _ss_all)
  if(_c STREQUAL "config")
    set(_libname suitesparseconfig)
  else()
    set(_libname ${_c})
  endif()
  string(TOUPPER ${_c} _C)
  find_library(SuiteSparse_${_C}_LIBRARY NAMES ${_libname})
endforeach()

find_package_handle_standard_args(SuiteSparse
  REQUIRED_VARS SuiteSparse_INCLUDE_DIR SuiteSparse_CHOLMOD_LIBRARY SuiteSparse_UMFPACK_LIBRARY
                SuiteSparse_KLU_LIBRARY SuiteSparse_AMD_LIBRARY SuiteSparse_COLAMD_LIBRARY
                SuiteSparse_BTF_LIBRARY SuiteSparse_CONFIG_LIBRARY
  REASON_FAILURE_MESSAGE "install the Debian package libsuitesparse-dev")

if(SuiteSparse_FOUND)
  foreach(_c IN LISTS _ss_all)
    string(TOUPPER ${_c} _C)
    if(SuiteSparse_${_C}_LIBRARY AND NOT TARGET SuiteSparse::${_c})
      add_library(SuiteSparse::${_c} UNKNOWN IMPORTED)
      set_target_properties(SuiteSparse::${_c} PROPERTIES
        IMPORTED_LOCATION "${SuiteSparse_${_C}_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${SuiteSparse_INCLUDE_DIR}")
    endif()
  endforeach()
  target_link_libraries(SuiteSparse::amd INTERFACE SuiteSparse::config)
  target_link_libraries(SuiteSparse::colamd INTERFACE SuiteSparse::config)
  target_link_libraries(SuiteSparse::cholmod INTERFACE SuiteSparse::amd SuiteSparse::colamd
                        SuiteSparse::camd SuiteSparse::ccolamd SuiteSparse::config)
  target_link_libraries(SuiteSparse::umfpack INTERFACE SuiteSparse::cholmod SuiteSparse::amd
                        SuiteSparse::config)
  target_link_libraries(SuiteSparse::klu INTERFACE SuiteSparse::btf SuiteSparse::amd
                        SuiteSparse::colamd SuiteSparse::config)
endif()
