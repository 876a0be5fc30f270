// Where each robot image keeps its configuration block (config_block.h):
// 1 KB in the `.syrof_config` section, which both boards' linker scripts
// place right after the vector table. As built it is all zeros (empty);
// syrof-firmware-config writes one robot's block into a copy of the image.
#pragma once

#include <cstdint>
#include <span>

#include "syrof/firmware/robot/config_block.h"

namespace syrof::firmware::robot {

/// The image's configuration block, as flashed. The compiler cannot see
/// its contents (a tool writes them after the link), so it reads them.
std::span<const uint8_t, kConfigBlockBytes> FlashedConfigBlock();

}  // namespace syrof::firmware::robot
