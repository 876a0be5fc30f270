# The activation model's boot words on syrof-robot-mps2 (boot_words.h):
# the image reads them (its status line names the model), stops with exit
# status 2 naming a word whose value it does not take, and the board stops
# on a command line with more words than it reads, rather than run without
# the rest.
#   cmake -DQEMU=... -DIMAGE=... -P robot_activation.cmake
function(run_image words out_result out_output)
  execute_process(
    COMMAND ${QEMU} -M mps2-an386 -nographic -monitor none -semihosting-config enable=on,target=native
            -icount shift=4 -serial stdio -serial null -kernel ${IMAGE}
            -append "id 0 swarm 4 seconds 1 ${words}"
    OUTPUT_VARIABLE output
    ERROR_VARIABLE errors
    RESULT_VARIABLE result
    TIMEOUT 60)
  set(${out_result} "${result}" PARENT_SCOPE)
  set(${out_output} "${output}${errors}" PARENT_SCOPE)
endfunction()

run_image("activation ssync schedule scripted seed 7 active 1:1,3:6" result output)
if(NOT result STREQUAL "0" OR NOT output MATCHES "status t_ms=[0-9]+ [^\n]* activation=ssync inactive=0")
  message(FATAL_ERROR "an SSYNC image did not run and say so (exit ${result}):\n${output}")
endif()
run_image("" result output)
if(NOT result STREQUAL "0" OR NOT output MATCHES " activation=fsync ")
  message(FATAL_ERROR "an image without activation words is not FSYNC (exit ${result}):\n${output}")
endif()
run_image("activation ssync schedule random fair_within 0" result output)
if(NOT result STREQUAL "2" OR NOT output MATCHES "'fair_within': '0' is not a value it takes")
  message(FATAL_ERROR "fair_within 0 was not refused by name (exit ${result}):\n${output}")
endif()
run_image("activation ssync schedule scripted active 3:1,2:1" result output)
if(NOT result STREQUAL "2" OR NOT output MATCHES "'active': '3:1,2:1' is not a value it takes")
  message(FATAL_ERROR "a script out of order was not refused by name (exit ${result}):\n${output}")
endif()
set(many "")
foreach(i RANGE 40)
  string(APPEND many " late 3")
endforeach()
run_image("${many}" result output)
if(result STREQUAL "0" OR NOT output MATCHES "more words than")
  message(FATAL_ERROR "a command line of more words than the board reads ran (exit ${result}):\n${output}")
endif()
