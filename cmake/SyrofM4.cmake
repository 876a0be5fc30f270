# Cortex-M4 test harness: GoogleTest tests as bare-metal images for qemu's
# mps2-an386 board, one CTest test per image. Included by the top-level
# CMakeLists.txt in bare-metal (SYROF_TARGET_MCU) builds.
#
# syrof_add_test() (SyrofHelpers.cmake) calls syrof_add_m4_test() when
# SYROF_M4_TESTS is on; syrof_add_m4_program() is for other images run under
# qemu, such as cycle-count benchmarks. The board itself (vector table, reset
# handler, linker script, cycle counter, test main) is firmware/boards/mps2_an386.

if(NOT SYROF_M4_TESTS)
  # A plain cross build (`make cross`) registers no tests.
  function(syrof_add_m4_test)
  endfunction()
  return()
endif()

find_program(SYROF_QEMU_ARM qemu-system-arm REQUIRED)

set(SYROF_M4_TEST_TIMEOUT 120 CACHE STRING "CTest timeout in seconds for one Cortex-M4 test image")

# The qemu command line that runs one image. -icount shift=0 makes virtual time
# advance by 1 ns per instruction, independent of the host, so SysTick (and the
# board's cycle counter) reads the same on every run. Semihosting carries the
# program's output to the terminal and its exit status to qemu's.
set(SYROF_M4_RUN_COMMAND
    ${SYROF_QEMU_ARM} -M mps2-an386 -nographic -monitor none -serial null
    -semihosting-config enable=on,target=native -icount shift=0)

# --- GoogleTest for the Cortex-M4 -----------------------------------------
# Built from Debian's sources with the cross compiler, like SyROF's own code:
# no exceptions, no RTTI, no threads, newlib. GoogleTest's CMake project is not
# used because it forces -fexceptions.
find_path(SYROF_GOOGLETEST_SOURCE_DIR googletest/src/gtest-all.cc
          PATHS /usr/src/googletest NO_CMAKE_FIND_ROOT_PATH NO_DEFAULT_PATH)
if(NOT SYROF_GOOGLETEST_SOURCE_DIR)
  message(FATAL_ERROR "GoogleTest sources not found; install libgtest-dev (Debian puts them in /usr/src/googletest)"
                      " or set SYROF_GOOGLETEST_SOURCE_DIR")
endif()
set(_gtest_dir ${SYROF_GOOGLETEST_SOURCE_DIR}/googletest)
set(_gmock_dir ${SYROF_GOOGLETEST_SOURCE_DIR}/googlemock)

add_library(syrof_m4_gtest STATIC ${_gtest_dir}/src/gtest-all.cc)
target_include_directories(syrof_m4_gtest SYSTEM PUBLIC ${_gtest_dir}/include)
target_include_directories(syrof_m4_gtest PRIVATE ${_gtest_dir})
# Every translation unit that includes gtest.h must see the same configuration,
# so these are PUBLIC. GoogleTest 1.12 does not detect bare metal: threads,
# POSIX regular expressions (it falls back to its simple regex), death tests
# (off by themselves without an OS) and stream redirection are unavailable.
target_compile_definitions(syrof_m4_gtest PUBLIC
    GTEST_HAS_EXCEPTIONS=0 GTEST_HAS_RTTI=0 GTEST_HAS_PTHREAD=0
    GTEST_HAS_POSIX_RE=0 GTEST_HAS_STREAM_REDIRECTION=0 GTEST_HAS_CLONE=0
    # gtest-port.h calls fileno, fdopen and strdup, which newlib declares only
    # for POSIX sources under strict -std=c++20.
    _POSIX_C_SOURCE=200809L)
# gtest-filepath.cc sizes a buffer with PATH_MAX, which newlib defines in a
# limits.h that gcc's own limits.h does not include.
target_compile_definitions(syrof_m4_gtest PRIVATE PATH_MAX=1024)

add_library(syrof_m4_gmock STATIC ${_gmock_dir}/src/gmock-all.cc)
target_include_directories(syrof_m4_gmock SYSTEM PUBLIC ${_gmock_dir}/include)
target_include_directories(syrof_m4_gmock PRIVATE ${_gmock_dir})
target_link_libraries(syrof_m4_gmock PUBLIC syrof_m4_gtest)

# Test CMakeLists may name the host's imported targets in LIBS.
add_library(GTest::gtest ALIAS syrof_m4_gtest)
add_library(GTest::gmock ALIAS syrof_m4_gmock)
unset(_gtest_dir)
unset(_gmock_dir)

# syrof_add_m4_program(NAME <name> SOURCES ... [LIBS ...])
# A bare-metal image for the mps2-an386 board: <name>.elf in the runtime output
# directory, plus a .map file next to it. The board's reset handler calls
# main(argc, argv) and exits with its return value.
function(syrof_add_m4_program)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;LIBS" ${ARGN})
  add_executable(${ARG_NAME} ${ARG_SOURCES})
  set_target_properties(${ARG_NAME} PROPERTIES SUFFIX .elf)
  target_link_libraries(${ARG_NAME} PRIVATE ${ARG_LIBS} syrof::board_mps2_an386)
  target_link_options(${ARG_NAME} PRIVATE "LINKER:-Map=$<TARGET_FILE_DIR:${ARG_NAME}>/${ARG_NAME}.map")
  syrof_set_warnings(${ARG_NAME})
endfunction()

# syrof_add_m4_test(NAME <name> SOURCES ... [LIBS ...] [LABELS ...])
# The same GoogleTest sources as the host test, linked into one image with the
# board's test main, and registered as one CTest test (label m4 plus LABELS)
# that runs the whole image under qemu. A failed assertion makes the image
# exit non-zero, which fails the CTest test.
function(syrof_add_m4_test)
  cmake_parse_arguments(ARG "" "NAME" "SOURCES;LIBS;LABELS" ${ARGN})
  syrof_add_m4_program(NAME ${ARG_NAME} SOURCES ${ARG_SOURCES}
                       LIBS ${ARG_LIBS} syrof::board_mps2_an386_test_main GTest::gmock)
  add_test(NAME ${ARG_NAME} COMMAND ${SYROF_M4_RUN_COMMAND} -kernel $<TARGET_FILE:${ARG_NAME}>)
  set_tests_properties(${ARG_NAME} PROPERTIES
      LABELS "m4;${ARG_LABELS}" TIMEOUT ${SYROF_M4_TEST_TIMEOUT})
endfunction()
