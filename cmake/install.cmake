# install() and the exported package: find_package(ahdpack) → ahdpack::ahd, ahdpack::ahd_sample
# (static, or shared with BUILD_SHARED_LIBS; public headers <ahd/…>), ahdpack::bakers and
# ahdpack::cook (shared: libahd_bakers.so, libahd_cook.so, with the OpenImageIO module they load
# for images other than EXR), the shared libahd.so and
# libahd_sample.so for FFI callers (static builds install them too, not exported to CMake), and the
# ahdpack command with its data (share/ahdpack/formats). ahd_io and ahd_lab are not installed
# ahdpack_add_lightmaps (cmake/ahdpack_lightmaps.cmake: lightmaps cooked by the build).
include(CMakePackageConfigHelpers)

install(TARGETS ahd ahd_sample ahd_bakers ahd_cook EXPORT ahdpackTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
if(NOT BUILD_SHARED_LIBS)
  install(TARGETS ahd_shared ahd_sample_shared LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
endif()
install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ahd DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/generated/include/ahd/version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/ahd)
install(EXPORT ahdpackTargets NAMESPACE ahdpack:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ahdpack)
configure_package_config_file(${CMAKE_CURRENT_SOURCE_DIR}/cmake/ahdpackConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/ahdpackConfig.cmake INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ahdpack
  PATH_VARS CMAKE_INSTALL_BINDIR CMAKE_INSTALL_DATADIR)
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/ahdpackConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/ahdpackConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/ahdpackConfigVersion.cmake
  ${CMAKE_CURRENT_SOURCE_DIR}/cmake/ahdpack_lightmaps.cmake DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ahdpack)
# The modules, opened relative to ahdpack's bin/ folder or to libahd_bakers.so's lib/ folder
# (files/modules.cpp).
if(AHD_MODULE_TARGETS)
  install(TARGETS ${AHD_MODULE_TARGETS} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/ahdpack)
endif()
# The profiles and layout presets, found the same way (files/paths.cpp).
install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/formats/ DESTINATION ${CMAKE_INSTALL_DATADIR}/ahdpack/formats)
if(AHD_BUILD_CLI)
  install(TARGETS ahdpack RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
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
