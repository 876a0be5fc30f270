# CMake toolchain file for the Teensy 3.2 (MK20DX256: Cortex-M4 without FPU).
#
#   cmake -S . -B build-cross -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/teensy32.cmake
#
# The same flags serve the emulated Cortex-M4 (qemu mps2-an386) used by
# `make test-m4`: that board has an FPU, but soft-float code never touches it,
# so what passes there is what runs on the Teensy.

set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

# Found on PATH (Debian's gcc-arm-none-eabi puts them in /usr/bin).
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)

# Bare metal has no loader and no syscalls until a board provides them, so
# the compiler checks build a static library instead of linking a program.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

# Soft float: the MK20DX256 has no FPU. Function and data sections let the
# linker drop whatever a firmware image does not use.
set(_syrof_m4_flags "-mcpu=cortex-m4 -mthumb -mfloat-abi=soft -ffunction-sections -fdata-sections")
# GCC notes that the ABI for passing some structs changed in GCC 7.1, on every
# std::vector insert; everything in an image is built by this one compiler.
string(APPEND _syrof_m4_flags " -Wno-psabi")
set(CMAKE_C_FLAGS_INIT "${_syrof_m4_flags}")
set(CMAKE_ASM_FLAGS_INIT "${_syrof_m4_flags}")
# Core and firmware code never throws and never asks for a type at runtime.
set(CMAKE_CXX_FLAGS_INIT "${_syrof_m4_flags} -fno-exceptions -fno-rtti")
unset(_syrof_m4_flags)

# Programs (qemu, size) come from the host; headers and libraries must not.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
