# SPDX-License-Identifier: MIT
# Runs `talus run <SCRIPT>` and passes only if it fails (non-zero exit) AND its stderr matches
# EXPECT (a regular expression). ctest's PASS_REGULAR_EXPRESSION alone ignores the exit code.
#   cmake -DTALUS=<talus binary> -DSCRIPT=<script> -DEXPECT=<regex> -P expect_failure.cmake
execute_process(COMMAND ${TALUS} run ${SCRIPT}
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(status EQUAL 0)
  message(FATAL_ERROR "expected a failure, but `talus run ${SCRIPT}` exited with 0\nstdout: ${out}\nstderr: ${err}")
endif()
if(err MATCHES "Sanitizer|runtime error:")
  message(FATAL_ERROR "a sanitizer reported an error\nstderr: ${err}")
endif()
if(NOT err MATCHES "${EXPECT}")
  message(FATAL_ERROR "stderr does not match '${EXPECT}'\nexit status: ${status}\nstderr: ${err}")
endif()
if(out MATCHES "not reached")
  message(FATAL_ERROR "the script went on after the error\nstdout: ${out}")
endif()
message(STATUS "failed as expected (exit ${status}): ${err}")
