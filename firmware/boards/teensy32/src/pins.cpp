// Pin multiplexing and GPIO over the pin table (pins.h).
#include "pins_internal.h"

#include "registers.h"
#include "syrof/board/teensy32/board.h"

namespace syrof::board::teensy32 {

void MuxPin(PinIndex index, uint32_t extra_pcr_bits) {
  const PinAssignment& pin = kPins[index];
  const auto port = static_cast<uint32_t>(pin.port);
  reg::R32(reg::kSimScgc5) |= reg::kScgc5PortA << port;
  reg::R32(reg::kPortABase + 0x1000u * port + 4u * pin.bit) = reg::PcrMux(pin.mux) | extra_pcr_bits;
}

namespace {
uintptr_t GpioBase(const PinAssignment& pin) { return reg::kGpioABase + 0x40u * static_cast<uint32_t>(pin.port); }
}  // namespace

void GpioWrite(PinIndex index, bool high) {
  const PinAssignment& pin = kPins[index];
  reg::R32(GpioBase(pin) + (high ? 0x4u : 0x8u)) = 1u << pin.bit;  // PSOR or PCOR
}

void GpioConfigureOutput(PinIndex index, bool high) {
  const PinAssignment& pin = kPins[index];
  MuxPin(index, reg::kPcrDriveStrength);
  GpioWrite(index, high);
  reg::R32(GpioBase(pin) + 0x14u) |= 1u << pin.bit;  // PDDR: output
}

}  // namespace syrof::board::teensy32
