# `cmake --install <build> --prefix P`: the binaries, the static libraries, the public headers
# (include/clipray/, from harness/include/clipray/) and two ways to find them:
#   CMake       find_package(clipray 0.1 REQUIRED) -> clipray::core, clipray::gl
#               (lib/cmake/clipray/clipray-config.cmake, -config-version.cmake, -targets.cmake)
#   pkg-config  pkg-config --cflags --libs clipray (lib/pkgconfig/clipray.pc)
# tests/consumer/ builds a separate project against such an install; docs/library.md.
include(CMakePackageConfigHelpers)

set(clipray_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/clipray)

# clipray_glad goes with clipray_gl: a static clipray_gl needs it at link time (clipray::glad,
# link only; its headers stay in the build tree).
install(TARGETS clipray_core clipray_gl clipray_glad EXPORT clipray-targets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS clipray RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# Found by clipray as ../share/clipray/ from its bin/ (trace/CaptureFileCheck.cpp).
install(PROGRAMS ${PROJECT_SOURCE_DIR}/harness/renderdoc/clipray-capture-reader.py
        DESTINATION ${CMAKE_INSTALL_DATADIR}/clipray)
if(TARGET clipray-pick)
  install(TARGETS clipray-pick RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
# The public headers only: the internal ones stay in the source tree.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/harness/include/clipray/
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/clipray
        FILES_MATCHING PATTERN "*.hpp")

install(EXPORT clipray-targets NAMESPACE clipray:: FILE clipray-targets.cmake
        DESTINATION ${clipray_cmake_dir})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/clipray-config.cmake.in
                              ${PROJECT_BINARY_DIR}/clipray-config.cmake
                              INSTALL_DESTINATION ${clipray_cmake_dir})
# 0.x: a minor version may break the API, so 0.1 accepts 0.1.z only.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/clipray-config-version.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/clipray-config.cmake
              ${PROJECT_BINARY_DIR}/clipray-config-version.cmake
        DESTINATION ${clipray_cmake_dir})

# clipray.pc finds the prefix from its own place (${pcfiledir}), so the install can be moved.
set(clipray_pc_libdir ${CMAKE_INSTALL_FULL_LIBDIR})
set(clipray_pc_includedir ${CMAKE_INSTALL_FULL_INCLUDEDIR})
if(NOT IS_ABSOLUTE ${CMAKE_INSTALL_LIBDIR} AND NOT IS_ABSOLUTE ${CMAKE_INSTALL_INCLUDEDIR})
  file(RELATIVE_PATH clipray_pc_up /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
  string(REGEX REPLACE "/$" "" clipray_pc_up ${clipray_pc_up})
  set(clipray_pc_prefix "\${pcfiledir}/${clipray_pc_up}")
  set(clipray_pc_libdir "\${prefix}/${CMAKE_INSTALL_LIBDIR}")
  set(clipray_pc_includedir "\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}")
else()
  set(clipray_pc_prefix ${CMAKE_INSTALL_PREFIX})
endif()
set(clipray_pc_dl_libs "")
foreach(lib IN LISTS CMAKE_DL_LIBS)
  string(APPEND clipray_pc_dl_libs " -l${lib}")
endforeach()
configure_file(${CMAKE_CURRENT_LIST_DIR}/clipray.pc.in ${PROJECT_BINARY_DIR}/clipray.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/clipray.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
