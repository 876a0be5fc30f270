# Runs two instances of uart_echo_check joined by a Unix socket on UART1:
# the ping side listens (server, wait=on: its guest starts only once the
# peer is connected, so nothing it sends is lost), the echo side connects
# (reconnect=1: retrying each second until the socket exists; it only sends
# what it has received). Both must exit 0.
#   cmake -DQEMU=... -DIMAGE=... -DSOCKET=... -P uart_echo.cmake
set(common -M mps2-an386 -nographic -monitor none -semihosting-config enable=on,target=native
           -icount shift=0 -kernel ${IMAGE} -serial null)
file(REMOVE ${SOCKET})
# execute_process runs its COMMANDs at the same time (as a pipeline; the
# images print through semihosting, so the pipe carries nothing that matters).
execute_process(
  COMMAND ${QEMU} ${common} -chardev socket,id=link,path=${SOCKET},server=on,wait=on -serial chardev:link
          -append "ping"
  COMMAND ${QEMU} ${common} -chardev socket,id=link,path=${SOCKET},reconnect=1 -serial chardev:link
          -append "echo 256"
  RESULTS_VARIABLE results
  TIMEOUT 60)
file(REMOVE ${SOCKET})
message(STATUS "exit statuses (ping;echo): ${results}")
if(NOT results STREQUAL "0;0")
  message(FATAL_ERROR "uart echo through a socket failed: ${results}")
endif()
