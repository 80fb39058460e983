# Project-wide compiler settings: warnings, sanitizers, floating-point rules.

if(PBDVAL_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

# Determinism: no fused multiply-add contraction, so the same source gives the same bits
# whatever the optimiser decides (Jolt's rule); no -march=native, so results do not depend on
# the machine that built them.
add_compile_options(-ffp-contract=off)

# Warnings for our own targets (third-party headers come in as system includes).
function(pbdval_warnings target)
  target_compile_options(${target} PRIVATE
    -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Woverloaded-virtual
    -Wcast-align -Wunused -Wmissing-declarations -Wformat=2 -Wimplicit-fallthrough)
  if(PBDVAL_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
