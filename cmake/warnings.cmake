# Warnings per target, not as global flags.
function(ffd_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
    -Woverloaded-virtual -Wformat=2 -Wimplicit-fallthrough -Wcast-align -Wmissing-declarations)
endfunction()
