# Finds SuiteSparse's UMFPACK (Debian libsuitesparse-dev 5.x ships no CMake config) for
# Eigen's UmfPackSupport and defines the imported target UMFPACK::UMFPACK.
find_path(UMFPACK_INCLUDE_DIR umfpack.h PATH_SUFFIXES suitesparse)
find_library(UMFPACK_LIBRARY NAMES umfpack)
find_library(UMFPACK_AMD_LIBRARY NAMES amd)
find_library(UMFPACK_CHOLMOD_LIBRARY NAMES cholmod)
find_library(UMFPACK_CONFIG_LIBRARY NAMES suitesparseconfig)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(UMFPACK REQUIRED_VARS UMFPACK_LIBRARY UMFPACK_AMD_LIBRARY
                                  UMFPACK_CHOLMOD_LIBRARY UMFPACK_CONFIG_LIBRARY UMFPACK_INCLUDE_DIR)
if(UMFPACK_FOUND AND NOT TARGET UMFPACK::UMFPACK)
  add_library(UMFPACK::UMFPACK UNKNOWN IMPORTED)
  set_target_properties(UMFPACK::UMFPACK PROPERTIES IMPORTED_LOCATION "${UMFPACK_LIBRARY}"
                        INTERFACE_INCLUDE_DIRECTORIES "${UMFPACK_INCLUDE_DIR}"
                        INTERFACE_LINK_LIBRARIES
                        "${UMFPACK_CHOLMOD_LIBRARY};${UMFPACK_AMD_LIBRARY};${UMFPACK_CONFIG_LIBRARY}")
endif()
mark_as_advanced(UMFPACK_INCLUDE_DIR UMFPACK_LIBRARY UMFPACK_AMD_LIBRARY UMFPACK_CHOLMOD_LIBRARY
                 UMFPACK_CONFIG_LIBRARY)
