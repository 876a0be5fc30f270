# Helpers shared by every module's CMakeLists.txt.

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
  if(ARG_SOURCES)
    add_library(${ARG_NAME} STATIC ${ARG_SOURCES})
    target_include_directories(${ARG_NAME} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/${ARG_INCLUDE_DIR})
    target_link_libraries(${ARG_NAME} PUBLIC ${ARG_PUBLIC} PRIVATE ${ARG_PRIVATE})
    syrof_set_warnings(${ARG_NAME})
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

# syrof_add_test(NAME <name> SOURCES ... [LIBS ...] [LABELS ...] [HOST_ONLY])
# One GoogleTest executable (name it test_<module>_<unit>), registered with CTest. On the host each TEST()
# becomes its own CTest entry. In a Cortex-M4 build (SYROF_M4_TESTS) the same
# sources are linked into a bare-metal image run under qemu, unless HOST_ONLY
# (tests that need threads, files or other host services).
function(syrof_add_test)
  cmake_parse_arguments(ARG "HOST_ONLY" "NAME" "SOURCES;LIBS;LABELS" ${ARGN})
  if(SYROF_TARGET_MCU)
    if(NOT ARG_HOST_ONLY)
      syrof_add_m4_test(NAME ${ARG_NAME} SOURCES ${ARG_SOURCES} LIBS ${ARG_LIBS} LABELS ${ARG_LABELS})
    endif()
    return()
  endif()
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_LIBS} GTest::gtest_main GTest::gmock)
  syrof_set_warnings(${ARG_NAME})
  include(GoogleTest)
  gtest_discover_tests(${ARG_NAME} PROPERTIES LABELS "${ARG_LABELS}" DISCOVERY_TIMEOUT 60)
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
