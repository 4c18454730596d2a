# cmake -DCOMMAND=<exe> -DARGS=<a;b;c> -DEXPECT_CODE=<n> -DEXPECT_TEXT=<regex> -P expect_failure.cmake
# Runs the command; fails unless it exits with EXPECT_CODE and its stderr matches EXPECT_TEXT.
execute_process(COMMAND ${COMMAND} ${ARGS} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL EXPECT_CODE)
  message(FATAL_ERROR "exit code ${code}, expected ${EXPECT_CODE}\nstdout: ${out}\nstderr: ${err}")
endif()
if(NOT err MATCHES "${EXPECT_TEXT}")
  message(FATAL_ERROR "stderr does not match '${EXPECT_TEXT}':\n${err}")
endif()
