# Generates a GL 4.5 core loader with Debian's python3-glad at build time.
# --reproducible uses the Khronos XML bundled with the package: no network.
find_program(GLAD_EXECUTABLE glad PATHS /usr/bin NO_DEFAULT_PATH)
find_program(GLAD_EXECUTABLE glad)
if(NOT GLAD_EXECUTABLE)
  message(FATAL_ERROR "glad not found: install Debian's python3-glad (harness/install-deps.sh)")
endif()

# The loader is a static library of its own; a static clipray_gl installs and exports it beside
# itself (clipray::glad, link only: consumers get no glad headers from clipray).
function(clipray_generate_glad target)
  set(out ${PROJECT_BINARY_DIR}/glad)
  add_custom_command(
    OUTPUT ${out}/src/gl.c ${out}/include/glad/gl.h ${out}/include/KHR/khrplatform.h
    COMMAND ${GLAD_EXECUTABLE} --api gl:core=4.5 --out-path ${out} --reproducible --quiet c
    COMMENT "glad: generating the GL 4.5 core loader"
    VERBATIM)
  add_library(${target} STATIC ${out}/src/gl.c)
  target_include_directories(${target} SYSTEM PUBLIC $<BUILD_INTERFACE:${out}/include>)
  set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON EXPORT_NAME glad)
endfunction()
