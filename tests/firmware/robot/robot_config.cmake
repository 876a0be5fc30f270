# The configuration block on syrof-robot-mps2 (firmware/robot
# config_block.h), the flash-time path a Teensy takes, under qemu:
# syrof-firmware-config (the host build's) writes robot 2's block from a
# scenario into a copy of the image; the robot boots with that id, swarm
# and inputs (its "config" line names every value read, its status line
# counts them) and no id or inputs on its command line. A command line that
# contradicts the block (another robot's id, another scenario, inputs of its
# own), a block whose checksum does not match, one with an input missing (the
# checksum made right again here) and an image without the block's section
# are each refused by name, with exit status 2 and no start.
# A drone's block (DRONE_SCENARIO's robot 2) runs the image as a drone, its
# status line ending kind=drone; kind words on the command line may only
# confirm the block's, and a block naming a kind the image does not know is
# refused by name.
#   cmake -DQEMU=... -DIMAGE=... -DTOOL=... -DSCENARIO=... -DDRONE_SCENARIO=... -DWORK=... [-DBARE_IMAGE=...]
#         -P robot_config.cmake
if(NOT EXISTS "${TOOL}")
  message("SKIPPED: no syrof-firmware-config at ${TOOL} (the host build's: cmake --build build --target "
          "syrof-firmware-config; make test-m4 builds it)")
  return()
endif()
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")

function(run_image image words out_result out_output)
  execute_process(
    COMMAND ${QEMU} -M mps2-an386 -nographic -monitor none -semihosting-config enable=on,target=native
            -icount shift=4 -serial stdio -serial null -kernel ${image}
            -append "seconds 1 ${words}"
    OUTPUT_VARIABLE output
    ERROR_VARIABLE errors
    RESULT_VARIABLE result
    TIMEOUT 60)
  set(${out_result} "${result}" PARENT_SCOPE)
  set(${out_output} "${output}${errors}" PARENT_SCOPE)
endfunction()

function(expect_refused image words pattern what)
  run_image("${image}" "${words}" result output)
  if(NOT result STREQUAL "2" OR NOT output MATCHES "${pattern}" OR output MATCHES "status t_ms")
    message(FATAL_ERROR "${what} was not refused by name with exit status 2 and no start (exit ${result}):\n${output}")
  endif()
endfunction()

# CRC-32 (IEEE) of the bytes in `hex` (two hex digits a byte), bit by bit.
function(crc32 hex out)
  string(LENGTH "${hex}" length)
  math(EXPR last "${length} - 2")
  set(crc 4294967295)
  foreach(i RANGE 0 ${last} 2)
    string(SUBSTRING "${hex}" ${i} 2 byte)
    math(EXPR crc "${crc} ^ 0x${byte}")
    foreach(bit RANGE 1 8)
      math(EXPR crc "(${crc} >> 1) ^ (3988292384 & (0 - (${crc} & 1)))")
    endforeach()
  endforeach()
  math(EXPR crc "${crc} ^ 4294967295")
  set(${out} ${crc} PARENT_SCOPE)
endfunction()

# Writes the bytes `values` (decimal, 0-255) into `file` at `offset`.
function(poke file offset values)
  set(escaped "")
  foreach(value ${values})
    math(EXPR high "${value} / 64")
    math(EXPR middle "(${value} / 8) % 8")
    math(EXPR low "${value} % 8")
    string(APPEND escaped "\\${high}${middle}${low}")
  endforeach()
  execute_process(COMMAND sh -c "printf '${escaped}' | dd of='${file}' bs=1 seek=${offset} conv=notrunc status=none"
                  RESULT_VARIABLE result)
  if(NOT result STREQUAL "0")
    message(FATAL_ERROR "could not write ${file}")
  endif()
endfunction()

# The block's offset in `file`: its magic and version 1, "SYCF" 01 00.
function(block_offset file out)
  file(READ "${file}" hex HEX)
  string(FIND "${hex}" "535943460100" at)
  math(EXPR odd "${at} % 2")
  if(at LESS 0 OR odd)
    message(FATAL_ERROR "no configuration block in ${file}")
  endif()
  math(EXPR at "${at} / 2")
  set(${out} ${at} PARENT_SCOPE)
endfunction()

# Robot 2 of four_robots.yaml: charge 791, key 1/3.
execute_process(COMMAND ${TOOL} --scenario ${SCENARIO} --robot 2 --image ${IMAGE} --out ${WORK}/robot2.elf
                OUTPUT_VARIABLE written ERROR_VARIABLE errors RESULT_VARIABLE result)
if(NOT result STREQUAL "0" OR NOT written MATCHES "robot 2 of 4, kind omni, scenario four_robots \\(id ([0-9a-f]+)\\), 2 inputs: charge=791, key=0.3333333333333333; block at 0x")
  message(FATAL_ERROR "syrof-firmware-config did not write robot 2's image (exit ${result}):\n${written}${errors}")
endif()
set(scenario_id "${CMAKE_MATCH_1}")

run_image(${WORK}/robot2.elf "" result output)
if(NOT result STREQUAL "0"
   OR NOT output MATCHES "config robot=2/4 kind=omni swarm_kinds=omni scenario=${scenario_id} inputs=2 charge=791 key=0.3333333333333333 \\(the configuration block\\)"
   OR NOT output MATCHES "status t_ms=[0-9]+ board=mps2-an386 robot=2/4 [^\n]* inputs=2 kind=omni[\r\n]")
  message(FATAL_ERROR "robot 2's flashed image did not boot as robot 2 of 4 with its two inputs (exit ${result}):\n${output}")
endif()
# A command line that says the same as the block runs.
run_image(${WORK}/robot2.elf "id 2 swarm 4 scenario ${scenario_id}" result output)
if(NOT result STREQUAL "0" OR NOT output MATCHES "status t_ms=[0-9]+ board=mps2-an386 robot=2/4 [^\n]* inputs=2")
  message(FATAL_ERROR "a command line that agrees with the block was refused (exit ${result}):\n${output}")
endif()

expect_refused(${WORK}/robot2.elf "id 1"
               "the configuration block was written for robot 2; the command line says id 1"
               "a block for another robot")
expect_refused(${WORK}/robot2.elf "swarm 5"
               "the configuration block was written for a swarm of 4; the command line says swarm 5"
               "a block for another swarm")
expect_refused(${WORK}/robot2.elf "scenario 0123456789abcdef"
               "the configuration block was written for scenario ${scenario_id}; the command line expects scenario 0123456789abcdef"
               "a block for another scenario")
expect_refused(${WORK}/robot2.elf "inputs 2:1 input charge=3"
               "the command line gives inputs words and the configuration block holds robot 2's inputs too"
               "inputs on the command line of a flashed image")
expect_refused(${IMAGE} "scenario ${scenario_id}"
               "the command line expects a configuration block \\(scenario word\\) and the image has none"
               "a scenario word on an image without a block")

# A damaged block: one byte of its words changed ("id 2" -> "id 3").
block_offset(${WORK}/robot2.elf offset)
file(COPY_FILE ${WORK}/robot2.elf ${WORK}/damaged.elf)
math(EXPR at "${offset} + 20 + 3")
poke(${WORK}/damaged.elf ${at} "51")
expect_refused(${WORK}/damaged.elf ""
               "the configuration block's checksum is 0x[0-9a-f]+ but its contents give 0x[0-9a-f]+ \\(the block is damaged: write it again\\)"
               "a block whose checksum does not match")

# The block at `offset` in `file`, its checksum made right for its words
# again (after a poke): what a block written wrong, not damaged, looks like.
function(make_checksum_right file offset)
  file(READ ${file} header LIMIT 16 OFFSET ${offset} HEX)
  math(EXPR length_offset "${offset} + 6")
  file(READ ${file} length_hex LIMIT 2 OFFSET ${length_offset} HEX)
  string(SUBSTRING "${length_hex}" 0 2 low)
  string(SUBSTRING "${length_hex}" 2 2 high)
  math(EXPR length "0x${high} * 256 + 0x${low}")
  math(EXPR words_offset "${offset} + 20")
  file(READ ${file} words LIMIT ${length} OFFSET ${words_offset} HEX)
  crc32("${header}${words}" crc)
  math(EXPR b0 "${crc} & 255")
  math(EXPR b1 "(${crc} >> 8) & 255")
  math(EXPR b2 "(${crc} >> 16) & 255")
  math(EXPR b3 "(${crc} >> 24) & 255")
  math(EXPR at "${offset} + 16")
  poke(${file} ${at} "${b0};${b1};${b2};${b3}")
endfunction()

# An input missing: "inputs 2:2" -> "inputs 2:3", with the checksum made right.
file(COPY_FILE ${WORK}/robot2.elf ${WORK}/missing.elf)
math(EXPR at "${offset} + 20 + 22")  # "id 2 swarm 4 inputs 2:" is 22 bytes
poke(${WORK}/missing.elf ${at} "51")
make_checksum_right(${WORK}/missing.elf ${offset})
expect_refused(${WORK}/missing.elf ""
               "the configuration block: inputs 2:3 announced 3 inputs; 2 came \\(an input is missing\\)"
               "a block with an input missing")

# A drone: robot 2 of drone_among_omni.yaml (three omni robots and a drone,
# charge 791). Its block carries `kind drone swarm_kinds omni,drone`, the
# words the swarm host writes on a boot line, and the image runs as a drone
# with no kind word on its command line.
execute_process(COMMAND ${TOOL} --scenario ${DRONE_SCENARIO} --robot 2 --image ${IMAGE} --out ${WORK}/drone2.elf
                OUTPUT_VARIABLE written ERROR_VARIABLE errors RESULT_VARIABLE result)
if(NOT result STREQUAL "0" OR NOT written MATCHES "robot 2 of 4, kind drone \\(swarm_kinds omni,drone\\), scenario drone_among_omni \\(id ([0-9a-f]+)\\), 1 input: charge=791; block at 0x")
  message(FATAL_ERROR "syrof-firmware-config did not write the drone's image (exit ${result}):\n${written}${errors}")
endif()
set(drone_scenario_id "${CMAKE_MATCH_1}")
run_image(${WORK}/drone2.elf "" result output)
if(NOT result STREQUAL "0"
   OR NOT output MATCHES "config robot=2/4 kind=drone swarm_kinds=omni,drone scenario=${drone_scenario_id} inputs=1 charge=791 \\(the configuration block\\)"
   OR NOT output MATCHES "status t_ms=[0-9]+ board=mps2-an386 robot=2/4 [^\n]* inputs=1 kind=drone[\r\n]")
  message(FATAL_ERROR "the drone's flashed image did not boot as a drone (exit ${result}):\n${output}")
endif()
run_image(${WORK}/drone2.elf "id 2 kind drone swarm_kinds omni,drone" result output)
if(NOT result STREQUAL "0" OR NOT output MATCHES "status t_ms=[0-9]+ board=mps2-an386 robot=2/4 [^\n]* kind=drone[\r\n]")
  message(FATAL_ERROR "kind words that agree with the drone's block were refused (exit ${result}):\n${output}")
endif()
expect_refused(${WORK}/drone2.elf "kind rover"
               "the configuration block was written for a drone robot; the command line says kind rover"
               "another kind than the block's")
expect_refused(${WORK}/drone2.elf "kind drone swarm_kinds drone"
               "the configuration block was written for a swarm of kinds omni,drone; the command line says swarm_kinds drone"
               "other swarm kinds than the block's")
expect_refused(${WORK}/robot2.elf "kind drone"
               "the configuration block was written for an omni robot; the command line says kind drone"
               "a kind word on an omni robot's block")
# A kind the image does not know ("kind drone" -> "kind xrone"), the
# checksum made right: refused by name, no start.
block_offset(${WORK}/drone2.elf drone_offset)
file(COPY_FILE ${WORK}/drone2.elf ${WORK}/xrone.elf)
math(EXPR at "${drone_offset} + 20 + 18")  # "id 2 swarm 4 kind " is 18 bytes
poke(${WORK}/xrone.elf ${at} "120")
make_checksum_right(${WORK}/xrone.elf ${drone_offset})
expect_refused(${WORK}/xrone.elf ""
               "the configuration block's word 6 'kind': 'xrone' is not a value it takes \\(a robot kind this image knows: omni, rover or drone"
               "a block with a kind the image does not know")

# The Intel HEX a Teensy is flashed with, from the same tool.
execute_process(COMMAND ${TOOL} --scenario ${SCENARIO} --robot 0 --image ${IMAGE} --out ${WORK}/robot0.hex
                OUTPUT_VARIABLE written ERROR_VARIABLE errors RESULT_VARIABLE result)
file(READ ${WORK}/robot0.hex hex_text)
file(READ ${WORK}/robot0.hex hex_bytes HEX)  # to see the line ends: objcopy's \r\n
if(NOT result STREQUAL "0" OR NOT hex_text MATCHES "^:020000040000FA"
   OR NOT hex_bytes MATCHES "0d0a3a303030303030303146460d0a$")
  message(FATAL_ERROR "syrof-firmware-config did not write robot 0's Intel HEX (exit ${result}):\n${written}${errors}")
endif()

# An image without the block's section (an M4 test image): refused by name.
if(BARE_IMAGE)
  execute_process(COMMAND ${TOOL} --scenario ${SCENARIO} --robot 0 --image ${BARE_IMAGE} --out ${WORK}/bare.elf
                  OUTPUT_VARIABLE written ERROR_VARIABLE errors RESULT_VARIABLE result)
  if(NOT result STREQUAL "2" OR NOT errors MATCHES "the image has no .syrof_config section \\(the configuration block\\)")
    message(FATAL_ERROR "an image without the block's section was not refused (exit ${result}):\n${written}${errors}")
  endif()
endif()
