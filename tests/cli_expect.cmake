# Runs the aeroflock program and checks what it did.
#   -DAEROFLOCK=exe -DARGS="run;x.toml" -DEXPECT_RC=0|nonzero
#   [-DEXPECT_STDERR=regex] [-DSUMMARY=file.json: must exist with every summary key]
string(REPLACE "," ";" args "${ARGS}")
if(SUMMARY)
  file(REMOVE "${SUMMARY}")
endif()
execute_process(COMMAND "${AEROFLOCK}" ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                ERROR_VARIABLE err)
message("rc: ${rc}\nstdout:\n${out}\nstderr:\n${err}")
if(EXPECT_RC STREQUAL "0" AND NOT rc EQUAL 0)
  message(FATAL_ERROR "expected exit status 0")
elseif(EXPECT_RC STREQUAL "nonzero" AND (rc EQUAL 0 OR NOT rc MATCHES "^[0-9]+$"))
  message(FATAL_ERROR "expected a non-zero exit status (and no crash)")
endif()
if(DEFINED EXPECT_STDERR AND NOT err MATCHES "${EXPECT_STDERR}")
  message(FATAL_ERROR "stderr does not match: ${EXPECT_STDERR}")
endif()
if(SUMMARY)
  file(READ "${SUMMARY}" json)
  foreach(key backend device scenario birds steps dt steps_per_frame sim_seconds wall_seconds
              bird_steps_per_second nan_birds centroid mean_speed targets_reached perched flying)
    string(JSON value ERROR_VARIABLE missing GET "${json}" ${key})
    if(missing)
      message(FATAL_ERROR "${SUMMARY}: no key ${key}")
    endif()
  endforeach()
endif()
