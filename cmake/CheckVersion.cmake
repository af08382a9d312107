# mfv_check_version(<header> <version>): the MFV_API_VERSION a plugin is checked against
# (apps/plugin.hpp) must be the project(VERSION); a release that bumps one and not the other
# would load plugins built for another mfv, or refuse its own.
function(mfv_check_version header version)
  file(STRINGS "${header}" line REGEX "^#define MFV_API_VERSION \"[^\"]*\"")
  string(REGEX REPLACE ".*\"([^\"]*)\".*" "\\1" found "${line}")
  if(NOT found STREQUAL version)
    message(FATAL_ERROR "${header} says MFV_API_VERSION \"${found}\", CMakeLists.txt's "
                        "project(VERSION) is ${version}: make them equal")
  endif()
endfunction()
