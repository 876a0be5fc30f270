// I2C0 as a polled master: every byte waits for IICIF with a bounded spin.
#include "pins_internal.h"
#include "registers.h"
#include "syrof/board/teensy32/board.h"
#include "syrof/board/teensy32/clock_config.h"

namespace syrof::board::teensy32 {

using firmware::drivers::BusStatus;

namespace {
inline volatile uint8_t& I(uintptr_t offset) { return reg::R8(reg::kI2c0Base + offset); }
}  // namespace

uint32_t I2c0::Start(uint32_t scl_hz) {
  reg::R32(reg::kSimScgc4) |= reg::kScgc4I2c0;
  const uint32_t pad = reg::kPcrOpenDrain | reg::kPcrDriveStrength | reg::kPcrPullEnable | reg::kPcrPullSelectUp;
  MuxPin(kI2cScl, pad);
  MuxPin(kI2cSda, pad);
  const uint8_t icr = I2cIcrFor(kBusHz, scl_hz);
  I(reg::kI2cC1) = 0;
  I(reg::kI2cF) = icr;  // MULT = 1
  I(reg::kI2cC1) = reg::kI2cC1Iicen;
  return kBusHz / kI2cSclDividers[icr];
}

BusStatus I2c0::WaitByteDone() {
  for (uint32_t spin = 0; spin < kBusSpinLimit; ++spin) {
    const uint8_t status = I(reg::kI2cS);
    if ((status & reg::kI2cSIicif) != 0) {
      I(reg::kI2cS) = reg::kI2cSIicif;  // write 1 to clear
      if ((status & reg::kI2cSArbl) != 0) {
        I(reg::kI2cS) = reg::kI2cSArbl;
        return BusStatus::kError;
      }
      return BusStatus::kOk;
    }
  }
  return BusStatus::kTimeout;
}

BusStatus I2c0::SendByte(uint8_t byte) {
  I(reg::kI2cD) = byte;
  const BusStatus status = WaitByteDone();
  if (status != BusStatus::kOk) return status;
  return (I(reg::kI2cS) & reg::kI2cSRxak) != 0 ? BusStatus::kNack : BusStatus::kOk;
}

void I2c0::Stop() {
  I(reg::kI2cC1) = reg::kI2cC1Iicen;  // MST 1 -> 0 sends STOP
  for (uint32_t spin = 0; spin < kBusSpinLimit && (I(reg::kI2cS) & reg::kI2cSBusy) != 0; ++spin) {
  }
}

BusStatus I2c0::Write(uint8_t address, std::span<const uint8_t> data) {
  I(reg::kI2cC1) = reg::kI2cC1Iicen | reg::kI2cC1Mst | reg::kI2cC1Tx;  // START
  BusStatus status = SendByte(static_cast<uint8_t>(address << 1));
  for (size_t i = 0; status == BusStatus::kOk && i < data.size(); ++i) status = SendByte(data[i]);
  Stop();
  return status;
}

BusStatus I2c0::WriteRead(uint8_t address, std::span<const uint8_t> command, std::span<uint8_t> response) {
  I(reg::kI2cC1) = reg::kI2cC1Iicen | reg::kI2cC1Mst | reg::kI2cC1Tx;  // START
  BusStatus status = SendByte(static_cast<uint8_t>(address << 1));
  for (size_t i = 0; status == BusStatus::kOk && i < command.size(); ++i) status = SendByte(command[i]);
  if (status == BusStatus::kOk && !response.empty()) {
    I(reg::kI2cC1) = reg::kI2cC1Iicen | reg::kI2cC1Mst | reg::kI2cC1Tx | reg::kI2cC1Rsta;  // repeated START
    status = SendByte(static_cast<uint8_t>((address << 1) | 1));
    if (status == BusStatus::kOk) {
      // Receive; NACK the last byte (TXAK set before it is clocked in).
      const uint8_t ack = response.size() == 1 ? reg::kI2cC1Txak : 0;
      I(reg::kI2cC1) = static_cast<uint8_t>(reg::kI2cC1Iicen | reg::kI2cC1Mst | ack);
      const uint8_t dummy = I(reg::kI2cD);  // a dummy read starts the first byte
      (void)dummy;
      for (size_t i = 0; i < response.size(); ++i) {
        status = WaitByteDone();
        if (status != BusStatus::kOk) break;
        if (i + 1 == response.size()) {
          I(reg::kI2cC1) = reg::kI2cC1Iicen;  // STOP before reading D, so no further byte is clocked
        } else if (i + 2 == response.size()) {
          I(reg::kI2cC1) = reg::kI2cC1Iicen | reg::kI2cC1Mst | reg::kI2cC1Txak;
        }
        response[i] = I(reg::kI2cD);
      }
    }
  }
  Stop();
  return status;
}

I2c0& I2cBus0() {
  static I2c0 bus;
  return bus;
}

}  // namespace syrof::board::teensy32
