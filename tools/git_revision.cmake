# Run at build time (cmake -DSOURCE_DIR=... -DOUTPUT=... -P git_revision.cmake): writes
# AEROFLOCK_GIT_REVISION, the short hash of HEAD, "-dirty" with uncommitted changes ("unknown" outside a git checkout), to OUTPUT,
# touching the file only when it changes.
execute_process(COMMAND git describe --always --dirty --abbrev=7
                WORKING_DIRECTORY "${SOURCE_DIR}"
                OUTPUT_VARIABLE revision RESULT_VARIABLE status
                OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT status EQUAL 0 OR revision STREQUAL "")
  set(revision unknown)
endif()
file(CONFIGURE OUTPUT "${OUTPUT}" CONTENT "#define AEROFLOCK_GIT_REVISION \"${revision}\"\n" @ONLY)
