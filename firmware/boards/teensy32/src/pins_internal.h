#pragma once

#include <cstdint>

#include "syrof/board/teensy32/pins.h"

namespace syrof::board::teensy32 {

/// Gates the pin's port, selects its table alternative, plus PCR bits.
void MuxPin(PinIndex index, uint32_t extra_pcr_bits = 0);

}  // namespace syrof::board::teensy32
