# Compile options shared by every symdyn target.
#   symdyn_set_compile_options(<target>)
# adds the warning set (-Wall -Wextra -Wpedantic, -Werror with SYMDYN_WERROR)
# and the sanitizers with SYMDYN_SANITIZE.
function(symdyn_set_compile_options target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic
    $<$<BOOL:${SYMDYN_WERROR}>:-Werror>)
  if(SYMDYN_SANITIZE)
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer
      -fno-sanitize-recover=undefined)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
endfunction()
