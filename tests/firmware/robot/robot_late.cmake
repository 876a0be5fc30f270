# Boots syrof-robot-mps2 alone for one second of guest time, once as an
# initial member and once named late (`late 0`: switched on later, as the
# emulated swarm's joiners are), and checks its first report line: an
# initial member starts as a MEMBER, a late robot as a joiner (member=0).
#   cmake -DQEMU=... -DIMAGE=... -P robot_late.cmake
function(first_round_line words out)
  execute_process(
    COMMAND ${QEMU} -M mps2-an386 -nographic -monitor none -semihosting-config enable=on,target=native
            -icount shift=4 -serial stdio -serial null -kernel ${IMAGE}
            -append "id 0 swarm 4 seconds 1 report 1 ${words}"
    OUTPUT_VARIABLE output
    ERROR_VARIABLE errors
    RESULT_VARIABLE result
    TIMEOUT 60)
  if(NOT result STREQUAL "0")
    message(FATAL_ERROR "syrof-robot-mps2 with '${words}' exited with ${result}:\n${output}${errors}")
  endif()
  if(NOT output MATCHES "R t_ms=0 [^\n]*")
    message(FATAL_ERROR "no report line at t_ms=0 with '${words}':\n${output}")
  endif()
  set(${out} "${CMAKE_MATCH_0}" PARENT_SCOPE)
endfunction()

first_round_line("" initial)
if(NOT initial MATCHES " member=1 ")
  message(FATAL_ERROR "an initial member did not start as a MEMBER: ${initial}")
endif()
first_round_line("late 3 late 0" late)
if(NOT late MATCHES " member=0 ")
  message(FATAL_ERROR "a robot named late started as a MEMBER: ${late}")
endif()
