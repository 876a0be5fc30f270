# Runs the layering check (cmake/CheckLayers.cmake) on the planted tree in
# fixtures/planted and asserts that it fails and names every planted
# violation by file and line, and nothing else.
#
#   cmake -DSYROF_SOURCE_DIR=<repo> -P tests/architecture/planted_test.cmake
cmake_minimum_required(VERSION 3.25)

set(fixture ${CMAKE_CURRENT_LIST_DIR}/fixtures/planted)
execute_process(
  COMMAND ${CMAKE_COMMAND} -DSYROF_ROOT=${fixture} -P ${SYROF_SOURCE_DIR}/cmake/CheckLayers.cmake
  RESULT_VARIABLE status
  OUTPUT_VARIABLE out
  ERROR_VARIABLE err)
set(output "${out}${err}")

if(status EQUAL 0)
  message(FATAL_ERROR "the check passed a tree with planted violations:\n${output}")
endif()

set(expected
  "core/wire/src/planted_wire.cpp:5: includes \"syrof/runtime/robot.h\": core/wire (layer 1) may not include core/runtime (layer 7): above it"
  "queries/src/planted_query.cpp:4: includes \"syrof/lab/world/world.h\": queries (layer 1) may not include lab/world (layer 10): above it"
  "core/base/src/planted_cgal.cpp:3: includes \"CGAL/config.h\": only queries may include CGAL/ headers"
  "core/sync/src/planted_sibling.cpp:5: includes \"syrof/estimation/estimator.h\": core/sync (layer 4) may not include core/estimation/tasks (layer 4): a sibling in the same layer"
  "core/estimation/src/planted_math.cpp:4: includes \"syrof/pubsub/broker.h\": core/estimation (layer 1) may not include core/pubsub (layer 3): above it"
  "lab/apps/src/planted_board.cpp:3: includes \"syrof/board/cycles.h\": only firmware may include syrof/board/ headers"
  # The cross-compiled firmware may use nothing of lab, nor its own host
  # tool; the emulated swarm's host (firmware/swarm) is a module above lab,
  # beside the DDS runtime; only the process module starts a process.
  "firmware/robot/src/planted_lab.cpp:4: includes \"syrof/lab/base/error.h\": firmware (layer 8) may not include lab/base (layer 8): a sibling in the same layer"
  "firmware/robot/src/planted_lab.cpp:5: includes \"syrof/firmware/swarm/swarm_host.h\": firmware (layer 8) may not include firmware/swarm (layer 17): above it"
  "firmware/swarm/include/syrof/firmware/swarm/swarm_host.h:9: includes \"syrof/sim_dds/dds_world.h\": firmware/swarm (layer 17) may not include sim_dds (layer 17): a sibling in the same layer"
  # syrof-firmware-config's module reads scenarios and the firmware's block
  # and runs nothing: the engine and the swarm's host are above it.
  "firmware/config/src/planted_config.cpp:5: includes \"syrof/lab/sim/engine.h\": firmware/config (layer 12) may not include lab/sim (layer 13): above it"
  "firmware/config/src/planted_config.cpp:6: includes \"syrof/firmware/swarm/swarm_host.h\": firmware/config (layer 12) may not include firmware/swarm (layer 17): above it"
  "grader/src/planted_spawn.cpp:3: includes \"spawn.h\": only app_host/process may include spawn.h headers, and this file is in grader")
foreach(line IN LISTS expected)
  string(FIND "${output}" "${line}" at)
  if(at LESS 0)
    message(FATAL_ERROR "the check did not report\n  ${line}\nIt said:\n${output}")
  endif()
endforeach()
if(NOT output MATCHES "layering: 12 violation\\(s\\)")
  message(FATAL_ERROR "expected exactly 12 violations (the allowed includes must pass); the check said:\n${output}")
endif()
message("the check failed the planted tree and named all 12 violations")
