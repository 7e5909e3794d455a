# Runs `aeroflock view ...` in a virtual X display and checks that it exits 0 with no Vulkan
# validation error; prints SKIPPED (the test's SKIP_REGULAR_EXPRESSION) without xvfb-run.
#   -DAEROFLOCK=exe -DARGS="view,fig16-circling-eagle,--frames,30"
find_program(XVFB_RUN xvfb-run)
if(NOT XVFB_RUN)
  message("SKIPPED: xvfb-run is not installed (Debian: apt-get install xvfb)")
  return()
endif()
string(REPLACE "," ";" args "${ARGS}")
execute_process(COMMAND "${XVFB_RUN}" -a -s "-screen 0 1280x720x24" "${AEROFLOCK}" ${args}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("rc: ${rc}\nstdout:\n${out}\nstderr:\n${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "expected exit status 0")
endif()
if(err MATCHES "validation error")
  message(FATAL_ERROR "the Vulkan validation layer reported errors")
endif()
if(NOT out MATCHES "[0-9]+ frames in")
  message(FATAL_ERROR "no frame count on stdout")
endif()
