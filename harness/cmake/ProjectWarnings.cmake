# Warnings for project code only (generated glad code and third-party headers are exempt).
function(clipray_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                           -Wno-sign-conversion)
  if(CLIPRAY_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
