# Project-wide compiler settings: warnings, sanitizers, floating-point rules.

if(PBDVAL_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
  # GCC 12 at -O1 with the sanitizers reports libstdc++'s own <regex> internals (std::function
  # members of its NFA states) as maybe-uninitialized: a false positive, GCC bug 107138 family.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    add_compile_options(-Wno-maybe-uninitialized)
  endif()
endif()

# Fuzzing (docs/fuzzing.md): coverage instrumentation and both sanitizers on all our code; the
# fuzz_* programs add libFuzzer's main (tests/fuzz/CMakeLists.txt).
if(PBDVAL_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "PBDVAL_FUZZ needs clang (libFuzzer): use the preset 'fuzz'")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()

# Determinism: no fused multiply-add contraction, so the same source gives the same bits
# whatever the optimiser decides (Jolt's rule); no -march=native, so results do not depend on
# the machine that built them.
add_compile_options(-ffp-contract=off)
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
  add_compile_options(-fno-semantic-interposition)
endif()

# Warnings for our own targets (third-party headers come in as system includes).
function(pbdval_warnings target)
  target_compile_options(${target} PRIVATE
    -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Woverloaded-virtual
    -Wcast-align -Wunused -Wmissing-declarations -Wformat=2 -Wimplicit-fallthrough)
  if(PBDVAL_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# Build metadata recorded with every result file (commit, compiler, flags). Compiler and
# flags are fixed at configure time; the commit is read at every build by cmake/git_info.cmake,
# so a result never names a commit older than the code that produced it.
find_package(Git QUIET)
add_custom_target(pbdval_git_info
  COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${PROJECT_SOURCE_DIR}
          -DOUTPUT=${PROJECT_BINARY_DIR}/generated/pbdval/git_info.h
          -DTEMPLATE=${CMAKE_CURRENT_LIST_DIR}/git_info.h.in
          -DGIT_EXECUTABLE=${GIT_EXECUTABLE} -P ${CMAKE_CURRENT_LIST_DIR}/git_info.cmake
  BYPRODUCTS ${PROJECT_BINARY_DIR}/generated/pbdval/git_info.h
  COMMENT "Recording the git commit"
  VERBATIM)
string(TOUPPER "${CMAKE_BUILD_TYPE}" build_type_upper)
set(PBDVAL_CXX_FLAGS "${CMAKE_CXX_FLAGS} ${CMAKE_CXX_FLAGS_${build_type_upper}} -ffp-contract=off -fPIC -fno-semantic-interposition")
string(STRIP "${PBDVAL_CXX_FLAGS}" PBDVAL_CXX_FLAGS)
configure_file(${CMAKE_CURRENT_LIST_DIR}/build_info.h.in ${PROJECT_BINARY_DIR}/generated/pbdval/build_info.h @ONLY)
