// The MK20's UARTs: 8N1, a transmit ring drained by the TDRE interrupt, the
// receive interrupt handing each byte to a callback.
#include <cstdlib>

#include "pins_internal.h"
#include "registers.h"
#include "syrof/board/teensy32/board.h"
#include "syrof/board/teensy32/clock_config.h"

namespace syrof::board::teensy32 {

namespace {
inline volatile uint8_t& U(uintptr_t base, uintptr_t offset) { return reg::R8(base + offset); }
constexpr uint8_t kUartInterruptLevel = 2;  // above every kernel level
}  // namespace

Uart::Uart(uintptr_t base, uint32_t clock_hz, int irq, PinIndex rx, PinIndex tx, uint32_t clock_gate)
    : base_(base), clock_hz_(clock_hz), irq_(irq), rx_(rx), tx_(tx), clock_gate_(clock_gate) {}

bool Uart::Start(uint32_t baud, ReceiveFn on_byte, void* context) {
  const UartDivider divider = UartDividerFor(clock_hz_, baud);
  if (divider.sbr == 0) return false;
  const uint64_t reached = UartMillibaud(clock_hz_, divider);
  const uint64_t wanted = static_cast<uint64_t>(baud) * 1000;
  if ((reached > wanted ? reached - wanted : wanted - reached) * 50 > wanted) return false;  // > 2%
  on_byte_ = on_byte;
  context_ = context;
  baud_ = baud;
  reg::R32(reg::kSimScgc4) |= clock_gate_;
  MuxPin(rx_, reg::kPcrPullEnable | reg::kPcrPullSelectUp);  // idle high when nothing drives it
  MuxPin(tx_, reg::kPcrDriveStrength);
  U(base_, reg::kUartC2) = 0;  // transmitter and receiver off while the rate changes
  U(base_, reg::kUartBdh) = static_cast<uint8_t>((divider.sbr >> 8) & 0x1F);
  U(base_, reg::kUartBdl) = static_cast<uint8_t>(divider.sbr & 0xFF);  // BDL last: it latches SBR
  U(base_, reg::kUartC4) = static_cast<uint8_t>(divider.brfa & 0x1F);
  U(base_, reg::kUartC1) = 0;  // 8 data bits, no parity
  U(base_, reg::kUartC2) = reg::kUartC2Te | reg::kUartC2Re | (on_byte != nullptr ? reg::kUartC2Rie : 0);
  reg::EnableIrq(irq_, kUartInterruptLevel);
  return true;
}

size_t Uart::Free() const { return kTxCapacity - (tx_head_ - tx_tail_); }

size_t Uart::Write(std::span<const uint8_t> bytes) {
  size_t taken = 0;
  uint32_t head = tx_head_;
  while (taken < bytes.size() && head - tx_tail_ < kTxCapacity) {
    tx_buffer_[head % kTxCapacity] = bytes[taken++];
    ++head;
  }
  tx_head_ = head;
  if (taken > 0) {
    // Let the interrupt drain the ring; it clears TIE when the ring is empty.
    asm volatile("cpsid i" ::: "memory");
    U(base_, reg::kUartC2) = U(base_, reg::kUartC2) | reg::kUartC2Tie;
    asm volatile("cpsie i" ::: "memory");
  }
  return taken;
}

void Uart::Flush() {
  // At most a full ring at 10 bits per byte, plus one byte in the shifter.
  const int64_t limit_ns = now_ns() + static_cast<int64_t>(kTxCapacity + 2) * 10 * 1'000'000'000 /
                                           static_cast<int64_t>(baud_ == 0 ? 1 : baud_);
  while (tx_head_ != tx_tail_ && now_ns() < limit_ns) {
  }
}

void Uart::OnInterrupt() {
  const uint8_t status = U(base_, reg::kUartS1);
  if ((status & (reg::kUartS1Rdrf | reg::kUartS1Or)) != 0) {
    // Reading S1 then D clears RDRF and OR.
    const uint8_t byte = U(base_, reg::kUartD);
    if ((status & reg::kUartS1Or) != 0) ++overruns_;
    if (on_byte_ != nullptr && (status & reg::kUartS1Rdrf) != 0) on_byte_(byte, context_);
  }
  if ((U(base_, reg::kUartC2) & reg::kUartC2Tie) != 0 && (status & reg::kUartS1Tdre) != 0) {
    if (tx_tail_ != tx_head_) {
      U(base_, reg::kUartD) = tx_buffer_[tx_tail_ % kTxCapacity];  // S1 read, then D written: clears TDRE
      tx_tail_ = tx_tail_ + 1;
    } else {
      U(base_, reg::kUartC2) = U(base_, reg::kUartC2) & static_cast<uint8_t>(~reg::kUartC2Tie);
    }
  }
}

Uart& RadioUart() {
  static Uart uart(reg::kUart0Base, kCoreHz, reg::kIrqUart0Status, kRadioRx, kRadioTx, reg::kScgc4Uart0);
  return uart;
}

Uart& ConsoleUart() {
  static Uart uart(reg::kUart2Base, kBusHz, reg::kIrqUart2Status, kConsoleRx, kConsoleTx, reg::kScgc4Uart2);
  return uart;
}

}  // namespace syrof::board::teensy32

extern "C" void uart0_status_handler() { syrof::board::teensy32::RadioUart().OnInterrupt(); }
extern "C" void uart2_status_handler() { syrof::board::teensy32::ConsoleUart().OnInterrupt(); }
