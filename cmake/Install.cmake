# `cmake --install build/release --prefix <p>`: mfv as a library for code outside its tree.
#   <p>/bin/mfv                          the command line (exports its symbols to plugins)
#   <p>/lib/libmfv_*.a                   one static library per layer
#   <p>/include/mfv/<layer>/...hpp       the headers, included as "methods/kernels/kernel.hpp"
#   <p>/lib/cmake/mfv/                   the CMake package: find_package(mfv CONFIG) gives
#                                        mfv::base, mfv::methods, mfv::reports, mfv::engines,
#                                        mfv::problems, mfv::analyses, mfv::verify, mfv::app
#                                        (link one for your own driver), mfv::plugin (compile a
#                                        plugin library) and mfv::mfv (the executable)
#   <p>/share/mfv/suites/                the manifests and the baseline
#   <p>/share/mfv/solvers/               the external solvers' files and adapters (mfv finds
#                                        them beside bin/mfv)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(mfv_layers base methods reports engines problems analyses verify app)
foreach(layer IN LISTS mfv_layers)
  set_target_properties(mfv_${layer} PROPERTIES EXPORT_NAME ${layer})
endforeach()
set_target_properties(mfv_plugin PROPERTIES EXPORT_NAME plugin)
list(TRANSFORM mfv_layers PREPEND mfv_ OUTPUT_VARIABLE mfv_layer_targets)
install(TARGETS ${mfv_layer_targets} mfv_plugin mfv
        EXPORT mfvTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/mfv)
install(DIRECTORY methods reports dynamics stability problems analyses verify apps
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/mfv
        FILES_MATCHING PATTERN "*.hpp")
install(DIRECTORY suites DESTINATION ${CMAKE_INSTALL_DATADIR}/mfv)
install(DIRECTORY solvers DESTINATION ${CMAKE_INSTALL_DATADIR}/mfv)

set(mfv_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/mfv)
install(EXPORT mfvTargets NAMESPACE mfv:: DESTINATION ${mfv_cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/mfvConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/mfvConfig.cmake
                              INSTALL_DESTINATION ${mfv_cmake_dir})
# A plugin must match the mfv it loads into (MFV_PLUGIN_ABI), so the package accepts only its
# own major.minor.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/mfvConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/mfvConfig.cmake ${PROJECT_BINARY_DIR}/mfvConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/FindVoroPP.cmake
              ${PROJECT_SOURCE_DIR}/cmake/FindUMFPACK.cmake
        DESTINATION ${mfv_cmake_dir})
