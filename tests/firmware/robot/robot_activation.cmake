# The activation model's, the private inputs' and the robot kind's boot words on
# syrof-robot-mps2 (boot_words.h):
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

# The robot's private inputs (boot_words.h): read into its table (the
# status line counts them); a line written for another robot, one input
# short of its count, or a value that is no finite number stops the image
# with a report line and exit status 2, before it starts.
run_image("inputs 0:2 input charge=734 input key=0.3" result output)
if(NOT result STREQUAL "0" OR NOT output MATCHES "status t_ms=[0-9]+ [^\n]* inputs=2")
  message(FATAL_ERROR "an image with two inputs did not run and count them (exit ${result}):\n${output}")
endif()
run_image("" result output)
if(NOT result STREQUAL "0" OR NOT output MATCHES " inputs=0")
  message(FATAL_ERROR "an image without input words has inputs (exit ${result}):\n${output}")
endif()
run_image("inputs 2:1 input charge=734" result output)
if(NOT result STREQUAL "2" OR NOT output MATCHES "the inputs were written for robot 2; this is robot 0"
   OR output MATCHES "status t_ms")
  message(FATAL_ERROR "inputs for another robot were not refused by name (exit ${result}):\n${output}")
endif()
run_image("inputs 0:2 input charge=734" result output)
if(NOT result STREQUAL "2" OR NOT output MATCHES "announced 2 inputs; 1 came \\(an input is missing\\)")
  message(FATAL_ERROR "a missing input was not refused by name (exit ${result}):\n${output}")
endif()
run_image("inputs 0:1 input charge=nan" result output)
if(NOT result STREQUAL "2" OR NOT output MATCHES "'input': 'charge=nan' is not a value it takes")
  message(FATAL_ERROR "a value that is no finite number was not refused by name (exit ${result}):\n${output}")
endif()

# The robot's kind (boot_words.h): `kind drone` runs the drone's motion
# layer (the status line names it), no word an omni robot; a kind the image
# does not know, or a kind outside its swarm_kinds, stops the image with a
# report line and exit status 2 before it starts.
run_image("kind drone" result output)
if(NOT result STREQUAL "0" OR NOT output MATCHES "status t_ms=[0-9]+ [^\n]* kind=drone[\r\n]")
  message(FATAL_ERROR "a drone image did not run and say so (exit ${result}):\n${output}")
endif()
run_image("" result output)
if(NOT result STREQUAL "0" OR NOT output MATCHES " kind=omni[\r\n]")
  message(FATAL_ERROR "an image without kind words is no omni robot (exit ${result}):\n${output}")
endif()
run_image("kind tank" result output)
if(NOT result STREQUAL "2" OR NOT output MATCHES "'kind': 'tank' is not a value it takes \\(a robot kind this image knows"
   OR output MATCHES "status t_ms")
  message(FATAL_ERROR "an unknown kind was not refused by name (exit ${result}):\n${output}")
endif()
run_image("kind drone swarm_kinds omni,rover" result output)
if(NOT result STREQUAL "2" OR NOT output MATCHES "kind drone is not among its swarm_kinds" OR output MATCHES "status t_ms")
  message(FATAL_ERROR "a kind outside its swarm_kinds was not refused by name (exit ${result}):\n${output}")
endif()
