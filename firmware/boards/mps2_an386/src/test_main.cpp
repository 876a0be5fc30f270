// main() for GoogleTest images on the emulated Cortex-M4. The reset handler
// passes qemu's semihosting command line, so `-append "--gtest_filter=..."`
// works when running an image by hand; the return value becomes qemu's exit
// status, non-zero when any test failed.
#include <gtest/gtest.h>

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
