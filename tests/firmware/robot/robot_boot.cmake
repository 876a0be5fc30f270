# Boots syrof-robot-mps2 alone (robot 0 of 4, its radio UART on null) for
# SECONDS of guest time and checks the last status line it prints on UART0:
# every robot task stepped at its rate (round 20 Hz, Kalman and motion
# 100 Hz; the radio-link task runs only when a byte arrives, and none does),
# no deadline was missed, the image exited 0.
#   cmake -DQEMU=... -DIMAGE=... -DSECONDS=5 -P robot_boot.cmake
# -icount shift=4, as the emulated swarm runs it (docs/firmware.md): guest
# time follows executed instructions (16 ns each) and the host's clock while
# the robot sleeps on WFI, so the run takes about SECONDS of wall time.
# (With sleep=off, which skips the sleeps, the robot missed deadlines once
# its radio's receive interrupt was routed: not understood yet.)
execute_process(
  COMMAND ${QEMU} -M mps2-an386 -nographic -monitor none -semihosting-config enable=on,target=native
          -icount shift=4 -serial stdio -serial null -kernel ${IMAGE}
          -append "id 0 swarm 4 seconds ${SECONDS}"
  OUTPUT_VARIABLE output
  ERROR_VARIABLE errors
  RESULT_VARIABLE result
  TIMEOUT 60)
message(STATUS "syrof-robot-mps2 said:\n${output}${errors}")
if(NOT result STREQUAL "0")
  message(FATAL_ERROR "syrof-robot-mps2 exited with ${result}")
endif()
string(REGEX MATCHALL "status t_ms=[^\n]*" lines "${output}")
list(LENGTH lines count)
if(count LESS 3)
  message(FATAL_ERROR "expected a status line a second, got ${count}")
endif()
list(GET lines -1 last)

# A task's steps from the last line, at least `minimum`.
function(expect_steps task minimum)
  if(NOT last MATCHES " ${task}=([0-9]+)")
    message(FATAL_ERROR "no steps of ${task} in: ${last}")
  endif()
  if(CMAKE_MATCH_1 LESS minimum)
    message(FATAL_ERROR "${task} stepped ${CMAKE_MATCH_1} times in ${SECONDS} s, expected at least ${minimum}: ${last}")
  endif()
endfunction()
math(EXPR rounds "${SECONDS} * 20")
math(EXPR hundred_hz "${SECONDS} * 100")
expect_steps(runtime.round ${rounds})
expect_steps(estimation.kalman ${hundred_hz})
expect_steps(runtime.motion ${hundred_hz})
if(NOT last MATCHES " overruns=0 ")
  message(FATAL_ERROR "a task missed a deadline: ${last}")
endif()
if(NOT last MATCHES "t_ms=${SECONDS}[0-9][0-9][0-9] ")
  message(FATAL_ERROR "the last line is not at ${SECONDS} s: ${last}")
endif()
# Alone, the robot runs epochs on its own: the synchronizer stepped.
if(NOT last MATCHES " sync=MEMBER epoch=([0-9]+) " OR CMAKE_MATCH_1 LESS 2)
  message(FATAL_ERROR "the synchronizer ran no epochs: ${last}")
endif()
