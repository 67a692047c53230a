# The packaging test (ctest: clipray_package_consumer), run with cmake -P:
#   1. cmake --install <CLIPRAY_BUILD_DIR> --prefix <WORK_DIR>/prefix
#   2. configure, build and run this folder's project against it (find_package(clipray 0.1))
#   3. pkg-config --cflags --libs clipray from that prefix, and the same sources compiled with
#      those flags alone (and GoogleTest's), and one of their tests run
# Variables: CLIPRAY_BUILD_DIR, WORK_DIR, VERSION (expected
# from pkg-config), LIBDIR (CMAKE_INSTALL_LIBDIR), GENERATOR, MAKE_PROGRAM, CXX, BUILD_TYPE,
# PKG_CONFIG, RENDERDOC_LIBRARY (librenderdoc.so, for the capture tests; empty: none), and
# EXTRA_FLAGS (the sanitizer flags a sanitized clipray needs at compile and link
# time; space-separated). The consumer's own CMake and compiler processes run unsanitized.
cmake_minimum_required(VERSION 3.25)

foreach(var CLIPRAY_BUILD_DIR WORK_DIR VERSION LIBDIR GENERATOR CXX PKG_CONFIG)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "run-consumer-test.cmake: -D${var}=... is required")
  endif()
endforeach()

set(prefix ${WORK_DIR}/prefix)
set(build ${WORK_DIR}/build)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

function(step what)
  message(STATUS "consumer test: ${what}")
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "consumer test: ${what}: failed (${result})")
  endif()
endfunction()

step("install into ${prefix}" ${CMAKE_COMMAND} --install ${CLIPRAY_BUILD_DIR} --prefix ${prefix})
foreach(file ${LIBDIR}/cmake/clipray/clipray-config.cmake
             ${LIBDIR}/cmake/clipray/clipray-config-version.cmake
             ${LIBDIR}/pkgconfig/clipray.pc include/clipray/Reconcile.hpp include/clipray/gtest.hpp
             bin/clipray)
  if(NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "consumer test: the install has no ${file}")
  endif()
endforeach()
# Only the public headers: clipray's internal ones (clipray/<part>/*.hpp) stay in its sources.
file(GLOB_RECURSE installed_headers RELATIVE ${prefix}/include ${prefix}/include/*)
foreach(header IN LISTS installed_headers)
  if(header MATCHES "^clipray/[^/]+/")
    message(FATAL_ERROR "consumer test: the install has an internal header: ${header}")
  endif()
endforeach()

# find_package, from this prefix only (no user or system package registry).
set(flags "${EXTRA_FLAGS}")
separate_arguments(extra_flags UNIX_COMMAND "${EXTRA_FLAGS}")
set(configure ${CMAKE_COMMAND} -S ${CMAKE_CURRENT_LIST_DIR} -B ${build} -G ${GENERATOR}
    -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=${BUILD_TYPE} -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF
    "-DCMAKE_CXX_FLAGS=${flags}" "-DCMAKE_EXE_LINKER_FLAGS=${flags}")
if(MAKE_PROGRAM)
  list(APPEND configure -DCMAKE_MAKE_PROGRAM=${MAKE_PROGRAM})
endif()
step("configure the consumer (find_package)" ${configure})
file(STRINGS ${build}/CMakeCache.txt found_dir REGEX "^clipray_DIR:")
if(NOT found_dir STREQUAL "clipray_DIR:PATH=${prefix}/${LIBDIR}/cmake/clipray")
  message(FATAL_ERROR "consumer test: found another clipray: ${found_dir}")
endif()
step("build the consumer" ${CMAKE_COMMAND} --build ${build})
step("run the consumer's tests" ${build}/clipray_consumer)
# The captures of failing frames (ReconcileOptions::renderDocCaptures): the RenderDocCapture
# tests again under RenderDoc, then the kept capture read by the installed clipray. Not with a
# sanitized build: the sanitizer runtime must come first in the process, before any preload.
if(RENDERDOC_LIBRARY AND EXTRA_FLAGS STREQUAL "")
  set(captures ${WORK_DIR}/captures)
  step("run the consumer's capture tests under RenderDoc"
       ${CMAKE_COMMAND} -E env LD_PRELOAD=${RENDERDOC_LIBRARY} CLIPRAY_CONSUMER_CAPTURES=${captures}
       ${build}/clipray_consumer --gtest_filter=RenderDocCapture.*)
  execute_process(COMMAND ${prefix}/bin/clipray reconcile --capture
                          ${captures}/direct3d-app-main-zo-upper-left-32f.rdc
                          --out ${WORK_DIR}/capture-report
                  RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE errors)
  if(NOT result EQUAL 1 OR NOT output MATCHES "INCONSISTENT direct3d-app-main-zo-upper-left-32f/")
    message(FATAL_ERROR "consumer test: reconcile --capture of the kept frame: exit ${result}, "
                        "expected 1 (inconsistent): ${output}${errors}")
  endif()
  message(STATUS "consumer test: the kept capture reconciles: ${output}")
else()
  message(STATUS "consumer test: no RenderDoc capture tests (RENDERDOC_LIBRARY \"${RENDERDOC_LIBRARY}\", "
                 "sanitizer flags \"${EXTRA_FLAGS}\")")
endif()

# pkg-config, from this prefix.
set(ENV{PKG_CONFIG_PATH} ${prefix}/${LIBDIR}/pkgconfig)
execute_process(COMMAND ${PKG_CONFIG} --modversion clipray OUTPUT_VARIABLE pc_version
                OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE result)
if(NOT result EQUAL 0 OR NOT pc_version STREQUAL VERSION)
  message(FATAL_ERROR "consumer test: pkg-config --modversion clipray: '${pc_version}' "
                      "(${result}), expected ${VERSION}")
endif()
execute_process(COMMAND ${PKG_CONFIG} --cflags --libs clipray OUTPUT_VARIABLE pc_flags
                OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "consumer test: pkg-config --cflags --libs clipray failed (${result})")
endif()
message(STATUS "consumer test: pkg-config --cflags --libs clipray: ${pc_flags}")
separate_arguments(pc_flags UNIX_COMMAND "${pc_flags}")
step("compile and link the consumer with pkg-config's flags"
     ${CXX} -std=c++20 -O2 ${extra_flags} ${CMAKE_CURRENT_LIST_DIR}/ConsumerTest.cpp
     ${CMAKE_CURRENT_LIST_DIR}/App.cpp -o ${WORK_DIR}/clipray_consumer_pc ${pc_flags}
     -lgtest_main -lgtest -pthread)
# The same sources ran in full above: one test shows the flags build a working program.
step("run the pkg-config consumer's test" ${WORK_DIR}/clipray_consumer_pc
     --gtest_filter=AppRenderingAndPicking.AgreeWithEachOther)
message(STATUS "consumer test: passed")
