# Embeds GLSL files from shaders/ into a generated C++ source as raw string literals, verbatim.
# Each file becomes `extern const char* const clipray::shaders::<name>` with its repository path in
# `<name>_file`. The renderer compiles a shader from several files as separate source strings, each
# opened by `#line <l> <n>`, and maps the info log's source numbers back to these paths, so a
# compile error names the file and line (harness/clipray/gl/Renderer.cpp, compileShaderFiles).
function(clipray_embed_shaders target)
  cmake_parse_arguments(ARG "" "" "SHADERS" ${ARGN})
  set(out_cpp ${PROJECT_BINARY_DIR}/generated/EmbeddedShaders.cpp)
  set(script ${CMAKE_CURRENT_FUNCTION_LIST_DIR}/EmbedShadersScript.cmake)
  add_custom_command(
    OUTPUT ${out_cpp}
    COMMAND ${CMAKE_COMMAND} -DOUT=${out_cpp} "-DSHADERS=${ARG_SHADERS}" -P ${script}
    DEPENDS ${ARG_SHADERS} ${script}
    COMMENT "Embedding GLSL shaders"
    VERBATIM)
  target_sources(${target} PRIVATE ${out_cpp})
endfunction()
