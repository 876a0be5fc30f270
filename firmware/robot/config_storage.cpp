#include "config_storage.h"

// The block itself: zeros in the image's own section, kept by the linker
// scripts (KEEP) and by `used` when nothing else refers to it.
extern "C" {
__attribute__((section(".syrof_config"), used, aligned(16))) const uint8_t
    syrof_config_block[syrof::firmware::robot::kConfigBlockBytes] = {};
}

namespace syrof::firmware::robot {

std::span<const uint8_t, kConfigBlockBytes> FlashedConfigBlock() {
  // The array is const and zero-initialised: without this the compiler
  // could read it as zeros at compile time and drop the check. The empty asm
  // hides where the pointer points.
  const uint8_t* block = syrof_config_block;
  asm volatile("" : "+r"(block));
  return std::span<const uint8_t, kConfigBlockBytes>(block, kConfigBlockBytes);
}

}  // namespace syrof::firmware::robot
