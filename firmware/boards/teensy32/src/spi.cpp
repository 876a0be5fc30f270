// SPI0 as a polled master, one byte per PUSHR/POPR, with a GPIO chip select
// per device and the device's clock and mode loaded into CTAR0 at Select().
#include "pins_internal.h"
#include "registers.h"
#include "syrof/board/teensy32/board.h"
#include "syrof/board/teensy32/clock_config.h"

namespace syrof::board::teensy32 {

using firmware::drivers::BusStatus;

namespace {
inline volatile uint32_t& S(uintptr_t offset) { return reg::R32(reg::kSpi0Base + offset); }

bool spi_started = false;

uint32_t MakeCtar(SpiBaud baud, SpiMode mode) {
  const auto mode_bits = static_cast<uint32_t>(mode);
  return reg::SpiCtarFrameSize(8) | ((mode_bits & 2u) != 0 ? reg::kSpiCtarCpol : 0) |
         ((mode_bits & 1u) != 0 ? reg::kSpiCtarCpha : 0) | (baud.dbr ? reg::kSpiCtarDbr : 0) |
         (static_cast<uint32_t>(baud.pbr) << 16) | baud.br;
}
}  // namespace

Spi0Device::Spi0Device(PinIndex chip_select, uint32_t max_sck_hz, SpiMode mode)
    : chip_select_(chip_select), mode_(mode) {
  SetMaxClock(max_sck_hz);
}

void Spi0Device::SetMaxClock(uint32_t max_sck_hz) {
  const SpiBaud baud = SpiBaudFor(kBusHz, max_sck_hz);
  ctar_ = MakeCtar(baud, mode_);
  sck_hz_ = baud.sck_hz;
}

void Spi0Device::Start() {
  GpioConfigureOutput(chip_select_, true);
  if (spi_started) return;
  spi_started = true;
  reg::R32(reg::kSimScgc6) |= reg::kScgc6Spi0;
  MuxPin(kSpiSck, reg::kPcrDriveStrength);
  MuxPin(kSpiMosi, reg::kPcrDriveStrength);
  MuxPin(kSpiMiso);
  S(reg::kSpiMcr) = reg::kSpiMcrMstr | reg::kSpiMcrPcsisAll | reg::kSpiMcrClrTxf | reg::kSpiMcrClrRxf |
                    reg::kSpiMcrHalt;
}

void Spi0Device::Select() {
  // CTAR may change only while the module is halted.
  S(reg::kSpiMcr) = reg::kSpiMcrMstr | reg::kSpiMcrPcsisAll | reg::kSpiMcrHalt;
  S(reg::kSpiCtar0) = ctar_;
  S(reg::kSpiMcr) = reg::kSpiMcrMstr | reg::kSpiMcrPcsisAll | reg::kSpiMcrClrTxf | reg::kSpiMcrClrRxf;
  GpioWrite(chip_select_, false);
}

void Spi0Device::Deselect() { GpioWrite(chip_select_, true); }

BusStatus Spi0Device::Transfer(std::span<const uint8_t> out, std::span<uint8_t> in) {
  const size_t count = out.empty() ? in.size() : out.size();
  for (size_t i = 0; i < count; ++i) {
    S(reg::kSpiSr) = reg::kSpiSrTcf | reg::kSpiSrRfdf | reg::kSpiSrRfof | reg::kSpiSrTfuf | reg::kSpiSrEoqf;
    S(reg::kSpiPushr) = out.empty() ? 0u : out[i];  // CTAS 0, no hardware chip select
    uint32_t spin = 0;
    while ((S(reg::kSpiSr) & reg::kSpiSrRfdf) == 0) {
      if (++spin == kBusSpinLimit) return BusStatus::kTimeout;
    }
    const auto byte = static_cast<uint8_t>(S(reg::kSpiPopr));
    if (i < in.size()) in[i] = byte;
  }
  return BusStatus::kOk;
}

}  // namespace syrof::board::teensy32
