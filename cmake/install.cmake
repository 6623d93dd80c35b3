# install() and the exported package: find_package(ahdpack) → ahdpack::ahd, ahdpack::ahd_io,
# ahdpack::ahd_sample (static libraries, public headers <ahd/…>), the ahdpack command, and
# ahdpack_add_lightmaps (cmake/ahdpack_lightmaps.cmake: lightmaps cooked by the build).
include(CMakePackageConfigHelpers)

install(TARGETS ahd ahd_io ahd_sample EXPORT ahdpackTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ahd DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT ahdpackTargets NAMESPACE ahdpack:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ahdpack)
configure_package_config_file(${CMAKE_CURRENT_SOURCE_DIR}/cmake/ahdpackConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/ahdpackConfig.cmake INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ahdpack
  PATH_VARS CMAKE_INSTALL_BINDIR CMAKE_INSTALL_DATADIR)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/ahdpackConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/ahdpackConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/ahdpackConfigVersion.cmake
  ${CMAKE_CURRENT_SOURCE_DIR}/cmake/ahdpack_lightmaps.cmake DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ahdpack)
if(AHD_BUILD_CLI)
  install(TARGETS ahdpack RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/formats/ DESTINATION ${CMAKE_INSTALL_DATADIR}/ahdpack/formats)
  # three.js (MIT) for the 3D view of `ahdpack preview`, from the lockfile-pinned npm package that
  # scripts/setup.sh installs; the installed tool finds it at <formats>/../three (preview_3d.h).
  # Without it the preview page is the static one with a note.
  set(AHD_THREE_DIR ${CMAKE_CURRENT_SOURCE_DIR}/tests/tools/node_modules/three)
  if(EXISTS ${AHD_THREE_DIR}/build/three.module.js)
    install(FILES ${AHD_THREE_DIR}/build/three.core.js ${AHD_THREE_DIR}/build/three.module.js
      DESTINATION ${CMAKE_INSTALL_DATADIR}/ahdpack/three/build)
    install(FILES ${AHD_THREE_DIR}/LICENSE ${AHD_THREE_DIR}/package.json DESTINATION ${CMAKE_INSTALL_DATADIR}/ahdpack/three)
  endif()
endif()
