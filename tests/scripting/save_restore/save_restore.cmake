# SPDX-License-Identifier: MIT
# Bit-identical continuation of one scene (continue.lua): 2N steps straight, or N steps, save,
# restore in a fresh process and N more. The dumps (%a of balls, clumps, contacts and their
# model state, energies) and the CSV histories must be equal byte for byte.
# Variables: TALUS (the binary), SCRIPT (continue.lua), SCENE, DIR (output directory).
file(MAKE_DIRECTORY ${DIR})
foreach(phase straight first second)
  execute_process(COMMAND ${TALUS} run ${SCRIPT} ${SCENE} ${phase} ${DIR}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${phase}: ${out}${err}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${SCENE} ${phase} failed (${rc})")
  endif()
  if(err MATCHES "AddressSanitizer|LeakSanitizer|runtime error:")
    message(FATAL_ERROR "${SCENE} ${phase}: sanitizer report")
  endif()
endforeach()
foreach(pair "straight.txt;restored.txt" "straight.csv;split.csv")
  list(GET pair 0 a)
  list(GET pair 1 b)
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${DIR}/${SCENE}_${a}
                  ${DIR}/${SCENE}_${b} RESULT_VARIABLE differ)
  if(differ)
    message(FATAL_ERROR "${SCENE}: ${SCENE}_${a} and ${SCENE}_${b} differ: the restored run "
                        "did not continue bit-identically")
  endif()
endforeach()
message("${SCENE}: the restored run continued bit-identically")
