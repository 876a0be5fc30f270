# Helpers shared by every module's CMakeLists.txt.

# The layering (one list, cmake/SyrofLayers.cmake): syrof_layer_rank_<module>
# is the index of the module's group, for syrof_add_library's check.
include(${CMAKE_CURRENT_LIST_DIR}/SyrofLayers.cmake)
set(_syrof_rank 0)
foreach(_syrof_group IN LISTS SYROF_LAYERS)
  string(REPLACE " " ";" _syrof_members "${_syrof_group}")
  foreach(_syrof_module IN LISTS _syrof_members)
    set(syrof_layer_rank_${_syrof_module} ${_syrof_rank})
  endforeach()
  math(EXPR _syrof_rank "${_syrof_rank} + 1")
endforeach()
unset(_syrof_rank)
unset(_syrof_group)
unset(_syrof_members)
unset(_syrof_module)

# The layering module of the current source folder: core/<m> and lab/<m> (a
# port folder such as core/os/sim belongs to core/os), else the top folder.
function(_syrof_current_module out)
  file(RELATIVE_PATH relative "${PROJECT_SOURCE_DIR}" "${CMAKE_CURRENT_SOURCE_DIR}")
  foreach(nested IN LISTS SYROF_NESTED_MODULES)
    if(relative STREQUAL nested OR relative MATCHES "^${nested}/")
      set(${out} "${nested}" PARENT_SCOPE)
      return()
    endif()
  endforeach()
  if(relative MATCHES "^(core|lab)/([^/]+)")
    set(${out} "${CMAKE_MATCH_1}/${CMAKE_MATCH_2}" PARENT_SCOPE)
  elseif(relative MATCHES "^([^/]+)")
    set(${out} "${CMAKE_MATCH_1}" PARENT_SCOPE)
  else()
    set(${out} "" PARENT_SCOPE)
  endif()
endfunction()

# Refuses (at configure time) a link dependency of `target` (in `module`) on
# a SyROF library of a module that is not strictly below it. Only libraries
# declared before are known (queries, for one, is added after core because it
# needs core/base while core/app needs it), so this catches what it can; the
# include check (cmake/CheckLayers.cmake, ctest label architecture) is the
# complete one.
function(_syrof_check_link_layers target module)
  if(NOT DEFINED syrof_layer_rank_${module})
    message(FATAL_ERROR "syrof_add_library(${target}): module ${module} is not in cmake/SyrofLayers.cmake")
  endif()
  foreach(dependency IN LISTS ARGN)
    get_property(dependency_module GLOBAL PROPERTY SYROF_MODULE_OF_${dependency})
    if(NOT dependency_module OR dependency_module STREQUAL module)
      continue()
    endif()
    if(NOT syrof_layer_rank_${dependency_module} LESS syrof_layer_rank_${module})
      message(FATAL_ERROR "syrof_add_library(${target}): ${module} (layer ${syrof_layer_rank_${module}}) may not "
                          "depend on ${dependency} of ${dependency_module} (layer "
                          "${syrof_layer_rank_${dependency_module}}); the order is in cmake/SyrofLayers.cmake")
    endif()
  endforeach()
endfunction()

option(SYROF_WERROR "Treat compiler warnings as errors in SyROF's own targets" ON)

# Compile options for SyROF's own code (not third-party code).
function(syrof_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow)
  if(SYROF_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  # GCC 12 at -O3 (Release) reports -Wrestrict inside libstdc++'s inlined
  # std::string concatenation (`"a" + std::to_string(n)` becomes an insert at
  # 0 whose memcpy it misjudges): GCC bugs 105329 and 105651, fixed in 13.
  # The diagnostic is about the standard library's code, not ours, and would
  # fail every Release build with warnings as errors, so it is off for GCC 12.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_GREATER_EQUAL 12
     AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    target_compile_options(${target} PRIVATE $<$<COMPILE_LANGUAGE:CXX>:-Wno-restrict>)
  endif()
endfunction()

# SYROF_DEBUG_INFO (empty by default): the debug-information option of the
# build types that have one (Debug, RelWithDebInfo) in place of CMake's -g.
# CI uses -g1 (line tables: backtraces and sanitizer reports keep file:line):
# full -g costs GCC a fifth to a third of the compile time of Eigen-, CGAL-,
# CLI11- and gtest-heavy sources, and GCC is made to generate the same code
# at every -g level, so warnings and test results should not change
# (docs/building.md, "CI").
set(SYROF_DEBUG_INFO "" CACHE STRING "Debug-information option replacing -g in Debug and RelWithDebInfo (e.g. -g1)")
if(SYROF_DEBUG_INFO)
  if(NOT SYROF_DEBUG_INFO MATCHES "^-g[0-3]?$")
    message(FATAL_ERROR "SYROF_DEBUG_INFO must be -g, -g0, -g1, -g2 or -g3, not '${SYROF_DEBUG_INFO}'")
  endif()
  foreach(language C CXX)
    foreach(config DEBUG RELWITHDEBINFO)
      string(REGEX REPLACE "(^| )-g( |$)" "\\1${SYROF_DEBUG_INFO}\\2"
             CMAKE_${language}_FLAGS_${config} "${CMAKE_${language}_FLAGS_${config}}")
    endforeach()
  endforeach()
endif()

# Determinism: no fused multiply-add contraction anywhere, so the same source
# computes the same bits on x86-64 and on the Cortex-M4 soft-float build.
add_compile_options(-ffp-contract=off)

# ASan and TSan cannot share a process: one sanitizer build at a time.
if(SYROF_SANITIZE AND SYROF_TSAN)
  message(FATAL_ERROR "SYROF_SANITIZE and SYROF_TSAN are exclusive: configure one build directory for each")
endif()
if(SYROF_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
# ThreadSanitizer for the tests where threads meet (`make tsan`: the POSIX
# port, the broker across threads, the robot's receive edge).
if(SYROF_TSAN)
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  add_link_options(-fsanitize=thread)
endif()

# syrof_add_library(NAME <target> [SOURCES ...] [INCLUDE_DIR <dir>]
#                   [PUBLIC <targets>...] [PRIVATE <targets>...])
# One module library: public headers in INCLUDE_DIR (default include/, under
# include/syrof/<module>/), sources in src/. PUBLIC lists what the module's
# public headers include (users inherit it); PRIVATE what only its sources
# use. Header-only modules pass no SOURCES and become INTERFACE libraries,
# where every dependency is PUBLIC. Every module of the tree is declared
# through this function, and its place in the layering (cmake/SyrofLayers.cmake)
# is checked against the include graph.
function(syrof_add_library)
  cmake_parse_arguments(ARG "" "NAME;INCLUDE_DIR" "SOURCES;PUBLIC;PRIVATE" ${ARGN})
  if(ARG_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "syrof_add_library(${ARG_NAME}): unknown arguments ${ARG_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT ARG_INCLUDE_DIR)
    set(ARG_INCLUDE_DIR include)
  endif()
  _syrof_current_module(module)
  _syrof_check_link_layers(${ARG_NAME} "${module}" ${ARG_PUBLIC} ${ARG_PRIVATE})
  set_property(GLOBAL PROPERTY SYROF_MODULE_OF_${ARG_NAME} "${module}")
  if(ARG_SOURCES)
    add_library(${ARG_NAME} STATIC ${ARG_SOURCES})
    target_include_directories(${ARG_NAME} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/${ARG_INCLUDE_DIR})
    target_link_libraries(${ARG_NAME} PUBLIC ${ARG_PUBLIC} PRIVATE ${ARG_PRIVATE})
    syrof_set_warnings(${ARG_NAME})
    # On the host a library's sources compile as one translation unit (a
    # unity build): the heavy headers (Eigen, yaml-cpp, nlohmann-json, fmt,
    # CGAL, Cyclone DDS) are parsed once per library, not once per file,
    # which halves the compile time of a fresh build (docs/building.md,
    # "Unity builds"). Names at file scope, anonymous namespaces included,
    # must therefore be unique across a library's files. The bare-metal
    # builds keep a unit per file. -DSYROF_UNITY_LIBRARIES=OFF for a unit per
    # file (quicker rebuilds after a one-file change).
    if(SYROF_UNITY_LIBRARIES AND NOT CMAKE_CROSSCOMPILING)
      set_target_properties(${ARG_NAME} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 0)
    endif()
  else()
    if(ARG_PRIVATE)
      message(FATAL_ERROR "syrof_add_library(${ARG_NAME}): a header-only module has no PRIVATE dependencies")
    endif()
    add_library(${ARG_NAME} INTERFACE)
    target_include_directories(${ARG_NAME} INTERFACE ${CMAKE_CURRENT_SOURCE_DIR}/${ARG_INCLUDE_DIR})
    target_link_libraries(${ARG_NAME} INTERFACE ${ARG_PUBLIC})
  endif()
  add_library(syrof::${ARG_NAME} ALIAS ${ARG_NAME})
endfunction()

# syrof_add_test(NAME <name> SOURCES ... [LIBS ...] [LABELS ...] [HOST_ONLY] [DISCOVER_AT_TEST_TIME] [RUN_SERIAL])
# One GoogleTest executable (name it test_<module>_<unit>), registered with CTest. On the host each TEST()
# becomes its own CTest entry. In a Cortex-M4 build (SYROF_M4_TESTS) the same
# sources are linked into a bare-metal image run under qemu, unless HOST_ONLY
# (tests that need threads, files or other host services).
function(syrof_add_test)
  cmake_parse_arguments(ARG "HOST_ONLY;DISCOVER_AT_TEST_TIME;RUN_SERIAL" "NAME" "SOURCES;LIBS;LABELS" ${ARGN})
  if(SYROF_TARGET_MCU)
    if(NOT ARG_HOST_ONLY)
      syrof_add_m4_test(NAME ${ARG_NAME} SOURCES ${ARG_SOURCES} LIBS ${ARG_LIBS} LABELS ${ARG_LABELS})
    endif()
    return()
  endif()
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_LIBS} GTest::gtest_main GTest::gmock)
  syrof_set_warnings(${ARG_NAME})
  # A test executable's own sources compile as one translation unit (a unity
  # build): GoogleTest's and gmock's headers are parsed once per executable
  # instead of once per file (docs/building.md, "CI"). Sources from outside
  # tests/ (the exploration's copy of core) keep their own units. Names at
  # file scope must therefore be unique across one executable's test files.
  set_target_properties(${ARG_NAME} PROPERTIES UNITY_BUILD ${SYROF_UNITY_TESTS} UNITY_BUILD_BATCH_SIZE 0)
  foreach(source IN LISTS ARG_SOURCES)
    get_filename_component(absolute ${source} ABSOLUTE)
    if(NOT absolute MATCHES "^${PROJECT_SOURCE_DIR}/tests/.*\\.cpp$")
      set_source_files_properties(${source} PROPERTIES SKIP_UNITY_BUILD_INCLUSION ON)
    endif()
  endforeach()
  # tests_<label> builds every test executable with that label, so a build
  # folder that runs only some labels (make asan) builds only what they need.
  foreach(label IN LISTS ARG_LABELS)
    if(NOT TARGET tests_${label})
      add_custom_target(tests_${label})
    endif()
    add_dependencies(tests_${label} ${ARG_NAME})
  endforeach()
  include(GoogleTest)
  # DISCOVER_AT_TEST_TIME: for tests whose list comes from files read at run
  # time (a folder per case), listed when ctest starts rather than when the
  # executable is linked, so a new folder needs no relink.
  set(discovery_mode POST_BUILD)
  if(ARG_DISCOVER_AT_TEST_TIME)
    set(discovery_mode PRE_TEST)
  endif()
  # RUN_SERIAL: wall-clock tests whose outcome a loaded machine can change
  # (the lab against real robot processes): ctest runs them alone.
  set(serial FALSE)
  if(ARG_RUN_SERIAL)
    set(serial TRUE)
  endif()
  gtest_discover_tests(${ARG_NAME} PROPERTIES LABELS "${ARG_LABELS}" RUN_SERIAL ${serial} DISCOVERY_TIMEOUT 60
    DISCOVERY_MODE ${discovery_mode})
endfunction()

# syrof_add_bench(NAME <name> SOURCES ... [LIBS ...])
# A benchmark program that prints its figures. Names start with bench_;
# `make bench` runs every build/bin/bench_* program.
function(syrof_add_bench)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;LIBS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_LIBS})
  syrof_set_warnings(${ARG_NAME})
endfunction()
