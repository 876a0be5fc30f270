# cmake -DRUN_COMMAND=<command;with;arguments> -P run_twice.cmake
# Runs a command twice; fails unless both runs succeed and print the same
# output. Used to show that a qemu image under -icount is deterministic.
foreach(run first second)
  execute_process(COMMAND ${RUN_COMMAND}
                  OUTPUT_VARIABLE output_${run} ERROR_VARIABLE output_${run}
                  RESULT_VARIABLE status_${run})
  message("${run} run (exit status ${status_${run}}):\n${output_${run}}")
  if(NOT status_${run} EQUAL 0)
    message(FATAL_ERROR "the ${run} run failed")
  endif()
endforeach()
if(NOT output_first STREQUAL output_second)
  message(FATAL_ERROR "the two runs printed different output")
endif()
