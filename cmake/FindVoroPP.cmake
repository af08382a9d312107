# Finds voro++ (Debian voro++-dev: headers and library, no CMake config of its own) and
# defines the imported target VoroPP::VoroPP.
find_path(VoroPP_INCLUDE_DIR voro++.hh PATH_SUFFIXES voro++)
find_library(VoroPP_LIBRARY NAMES voro++)
include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(VoroPP REQUIRED_VARS VoroPP_LIBRARY VoroPP_INCLUDE_DIR)
if(VoroPP_FOUND AND NOT TARGET VoroPP::VoroPP)
  add_library(VoroPP::VoroPP UNKNOWN IMPORTED)
  set_target_properties(VoroPP::VoroPP PROPERTIES IMPORTED_LOCATION "${VoroPP_LIBRARY}"
                        INTERFACE_INCLUDE_DIRECTORIES "${VoroPP_INCLUDE_DIR}")
endif()
mark_as_advanced(VoroPP_INCLUDE_DIR VoroPP_LIBRARY)
