# A video lasts as long as the simulated run at the frame rate chosen (ffprobe).
#   -DAEROFLOCK=exe -DARGS="run;...;--video;FILE" -DVIDEO=FILE -DSECONDS=simulated -DFPS=rate
string(REPLACE "," ";" args "${ARGS}")
file(REMOVE "${VIDEO}")
find_program(FFPROBE ffprobe)
if(NOT FFPROBE)
  message(FATAL_ERROR "ffprobe is not installed (tools/install-deps.sh installs ffmpeg)")
endif()
execute_process(COMMAND "${AEROFLOCK}" ${args} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message("rc: ${rc}\nstdout:\n${out}\nstderr:\n${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "expected exit status 0")
endif()
execute_process(COMMAND "${FFPROBE}" -v error -select_streams v:0 -count_frames
                        -show_entries format=duration:stream=nb_read_frames,r_frame_rate -of json "${VIDEO}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE probe ERROR_VARIABLE err)
message("ffprobe:\n${probe}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "ffprobe could not read ${VIDEO}")
endif()
string(JSON duration GET "${probe}" format duration)
string(JSON frames GET "${probe}" streams 0 nb_read_frames)
# Frames: one for every 1/FPS of simulated time, so the video is short of it by less than a frame.
execute_process(COMMAND awk "BEGIN { d = ${duration} - ${SECONDS}; if (d < 0) d = -d;
                                     f = int(${SECONDS} * ${FPS} + 1e-6);
                                     print (d <= 1.0 / ${FPS} + 1e-3) ? \"ok\" : \"bad\", f }"
                OUTPUT_VARIABLE verdict OUTPUT_STRIP_TRAILING_WHITESPACE)
string(REPLACE " " ";" verdict "${verdict}")
list(GET verdict 0 duration_ok)
list(GET verdict 1 expected_frames)
message("duration ${duration} s against ${SECONDS} s simulated; ${frames} frames against ${expected_frames}")
if(NOT duration_ok STREQUAL "ok")
  message(FATAL_ERROR "the video lasts ${duration} s, the run ${SECONDS} s (at ${FPS} frames/s)")
endif()
if(NOT frames EQUAL expected_frames)
  message(FATAL_ERROR "${frames} frames, expected ${expected_frames}")
endif()
