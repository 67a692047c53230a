# Embeds GLSL files from shaders/ into a generated C++ source as raw string literals.
# Each file becomes `extern const char* const clipray::shaders::<name>` and is prefixed with a
# `#line 1 <n>` directive after #version so compile errors point at the right line; the file name
# is recorded in clipray::shaders::fileNames so the info log can name it.
function(clipray_embed_shaders target)
  cmake_parse_arguments(ARG "" "" "SHADERS" ${ARGN})
  set(out_cpp ${CMAKE_BINARY_DIR}/generated/EmbeddedShaders.cpp)
  set(script ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/EmbedShadersScript.cmake)
  add_custom_command(
    OUTPUT ${out_cpp}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out_cpp} "-DSHADERS=${ARG_SHADERS}" -P ${script}
    DEPENDS ${ARG_SHADERS} ${script}
    COMMENT "Embedding GLSL shaders"
    VERBATIM)
  target_sources(${target} PRIVATE ${out_cpp})
endfunction()
