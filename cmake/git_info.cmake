# Run at build time (cmake -P): writes OUTPUT with the source tree's commit and whether it has
# local changes. configure_file leaves OUTPUT untouched when the text is unchanged, so only a
# new commit or a change of the clean/dirty state recompiles the files that record it.
# Inputs: -DSOURCE_DIR=... -DOUTPUT=... -DTEMPLATE=... [-DGIT_EXECUTABLE=...]
set(PBDVAL_GIT_COMMIT "unknown")
set(PBDVAL_GIT_DIRTY "unknown")
if(GIT_EXECUTABLE)
  execute_process(COMMAND ${GIT_EXECUTABLE} rev-parse HEAD WORKING_DIRECTORY ${SOURCE_DIR}
                  OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE
                  RESULT_VARIABLE result ERROR_QUIET)
  if(result EQUAL 0)
    set(PBDVAL_GIT_COMMIT "${commit}")
    execute_process(COMMAND ${GIT_EXECUTABLE} status --porcelain --untracked-files=no
                    WORKING_DIRECTORY ${SOURCE_DIR} OUTPUT_VARIABLE status ERROR_QUIET)
    if(status STREQUAL "")
      set(PBDVAL_GIT_DIRTY "clean")
    else()
      set(PBDVAL_GIT_DIRTY "local changes")
    endif()
  endif()
endif()
configure_file(${TEMPLATE} ${OUTPUT} @ONLY)
