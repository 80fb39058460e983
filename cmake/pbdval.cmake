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

# Build metadata recorded with every result file (commit, compiler, flags). The commit is read
# at configure time; touching .git/HEAD or the current branch's ref re-runs the configure step.
find_package(Git QUIET)
set(PBDVAL_GIT_COMMIT "unknown")
set(PBDVAL_GIT_DIRTY "unknown")
if(GIT_FOUND)
  execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse HEAD WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                  OUTPUT_VARIABLE PBDVAL_GIT_COMMIT OUTPUT_STRIP_TRAILING_WHITESPACE
                  RESULT_VARIABLE git_result ERROR_QUIET)
  if(NOT git_result EQUAL 0)
    set(PBDVAL_GIT_COMMIT "unknown")
  else()
    execute_process(COMMAND ${GIT_EXECUTABLE} status --porcelain --untracked-files=no
                    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR} OUTPUT_VARIABLE git_status ERROR_QUIET)
    if(git_status STREQUAL "")
      set(PBDVAL_GIT_DIRTY "clean")
    else()
      set(PBDVAL_GIT_DIRTY "local changes")
    endif()
    execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse --git-path HEAD WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                    OUTPUT_VARIABLE git_head_file OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
    if(EXISTS "${PROJECT_SOURCE_DIR}/${git_head_file}")
      set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${PROJECT_SOURCE_DIR}/${git_head_file}")
    elseif(EXISTS "${git_head_file}")
      set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${git_head_file}")
    endif()
  endif()
endif()
string(TOUPPER "${CMAKE_BUILD_TYPE}" build_type_upper)
set(PBDVAL_CXX_FLAGS "${CMAKE_CXX_FLAGS} ${CMAKE_CXX_FLAGS_${build_type_upper}} -ffp-contract=off")
string(STRIP "${PBDVAL_CXX_FLAGS}" PBDVAL_CXX_FLAGS)
configure_file(${CMAKE_CURRENT_LIST_DIR}/build_info.h.in ${PROJECT_BINARY_DIR}/generated/pbdval/build_info.h @ONLY)
