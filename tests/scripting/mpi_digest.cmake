# SPDX-License-Identifier: MIT
# Runs SCRIPT serially and under `MPIEXEC -n 2`, and passes only if both succeed and every
# rank prints the same "digest: <hex>" line as the serial run (talus.map gives every rank the
# whole result list, identical to the serial loop's).
#   cmake -DTALUS=<talus> -DMPIEXEC=<mpirun> -DSCRIPT=<script> -P mpi_digest.cmake
execute_process(COMMAND ${TALUS} run ${SCRIPT}
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "serial run failed (${status})\nstdout: ${out}\nstderr: ${err}")
endif()
string(REGEX MATCH "digest: ([0-9a-f]+)" _ "${out}")
set(serial "${CMAKE_MATCH_1}")
if(serial STREQUAL "")
  message(FATAL_ERROR "no digest in the serial output:\n${out}")
endif()

execute_process(COMMAND ${MPIEXEC} -n 2 ${TALUS} run ${SCRIPT}
                RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "mpirun -n 2 failed (${status})\nstdout: ${out}\nstderr: ${err}")
endif()
string(REGEX MATCHALL "digest: [0-9a-f]+ \\(rank [0-9]+ of [0-9]+\\)" lines "${out}")
list(LENGTH lines count)
if(NOT count EQUAL 2)
  message(FATAL_ERROR "expected 2 digest lines from 2 ranks, got ${count}:\n${out}\n${err}")
endif()
foreach(line ${lines})
  if(NOT line MATCHES "digest: ${serial} \\(rank [01] of 2\\)")
    message(FATAL_ERROR "rank digest differs from the serial ${serial}: ${line}")
  endif()
endforeach()
message(STATUS "serial and both ranks: digest ${serial}")
