// CMSDK APB UART and timer registers (Arm CoreLink SDK technical reference;
// qemu's hw/char/cmsdk-apb-uart and hw/timer/cmsdk-apb-timer model them).
#include "syrof/board/mps2_an386/cmsdk_uart.h"

namespace syrof::board::mps2_an386 {
namespace {

inline volatile uint32_t& R(uintptr_t base, uintptr_t offset) {
  return *reinterpret_cast<volatile uint32_t*>(base + offset);
}

// UART.
constexpr uintptr_t kData = 0x00, kState = 0x04, kCtrl = 0x08, kIntStatus = 0x0C, kBaudDiv = 0x10;
constexpr uint32_t kStateTxFull = 1u << 0, kStateRxFull = 1u << 1, kStateRxOverrun = 1u << 3;
constexpr uint32_t kCtrlTxEnable = 1u << 0, kCtrlRxEnable = 1u << 1, kCtrlTxInterrupt = 1u << 2,
                   kCtrlRxInterrupt = 1u << 3;
constexpr uint32_t kMinimumBaudDivider = 16;

// Timer.
constexpr uintptr_t kTimerCtrl = 0x00, kTimerValue = 0x04, kTimerReload = 0x08, kTimerIntStatus = 0x0C;
constexpr uint32_t kTimerEnable = 1u << 0, kTimerInterruptEnable = 1u << 3;

}  // namespace

void CmsdkUart::Start(bool interrupts) {
  R(base_, kCtrl) = 0;
  R(base_, kBaudDiv) = kMinimumBaudDivider;
  R(base_, kCtrl) = kCtrlTxEnable | kCtrlRxEnable | (interrupts ? kCtrlTxInterrupt | kCtrlRxInterrupt : 0);
  // Reading the (empty) data register changes nothing on the UART, but
  // under qemu it tells the character device the guest takes input now:
  // without it, qemu notices only at its main loop's next wake-up, which
  // for an idle guest came up to a second later (a held robot's Start
  // frame sent 0.5 s after boot was read 0.5 s late).
  const uint32_t discarded = R(base_, kData);
  (void)discarded;
}

size_t CmsdkUart::Free() const { return kRing - (tx_head_ - tx_tail_); }

size_t CmsdkUart::Write(std::span<const uint8_t> bytes) {
  size_t taken = 0;
  uint32_t head = tx_head_;
  while (taken < bytes.size() && head - tx_tail_ < kRing) tx_[head++ % kRing] = bytes[taken++];
  tx_head_ = head;
  Poll();  // start sending at once
  return taken;
}

size_t CmsdkUart::Read(std::span<uint8_t> out) {
  size_t taken = 0;
  uint32_t tail = rx_tail_;
  while (taken < out.size() && tail != rx_head_) out[taken++] = rx_[tail++ % kRing];
  rx_tail_ = tail;
  return taken;
}

bool CmsdkUart::Poll() {
  bool moved = false;
  const uint32_t state = R(base_, kState);
  if ((state & kStateRxOverrun) != 0) {
    R(base_, kState) = kStateRxOverrun;  // write 1 to clear
    ++dropped_;
  }
  if ((state & kStateRxFull) != 0) {
    const auto byte = static_cast<uint8_t>(R(base_, kData));
    if (byte == 0) zeros_received_ = zeros_received_ + 1;
    if (rx_head_ - rx_tail_ < kRing) {
      rx_[rx_head_ % kRing] = byte;
      rx_head_ = rx_head_ + 1;
    } else {
      ++dropped_;
    }
    moved = true;
  }
  if ((state & kStateTxFull) == 0 && tx_tail_ != tx_head_) {
    R(base_, kData) = tx_[tx_tail_ % kRing];
    tx_tail_ = tx_tail_ + 1;
    moved = true;
  }
  R(base_, kIntStatus) = 0x3;  // clear both interrupts; the states above say what is left
  return moved;
}

void CmsdkTimer::Start(uint32_t reload, bool interrupt) {
  R(base_, kTimerCtrl) = 0;
  reload_ = reload;
  R(base_, kTimerReload) = reload;
  R(base_, kTimerValue) = reload;
  last_value_ = reload;
  elapsed_ = 0;
  R(base_, kTimerCtrl) = kTimerEnable | (interrupt ? kTimerInterruptEnable : 0);
}

void CmsdkTimer::Stop() { R(base_, kTimerCtrl) = 0; }

uint32_t CmsdkTimer::value() const { return R(base_, kTimerValue); }

uint64_t CmsdkTimer::count_cycles() {
  const uint32_t now = value();
  // Down-counter: elapsed since the last reading, across at most one reload.
  const uint64_t delta = now <= last_value_ ? last_value_ - now : uint64_t{last_value_} + 1 + (reload_ - now);
  last_value_ = now;
  elapsed_ += delta;
  return elapsed_;
}

bool CmsdkTimer::ClearInterrupt() {
  const bool pending = (R(base_, kTimerIntStatus) & 1u) != 0;
  R(base_, kTimerIntStatus) = 1u;
  return pending;
}

}  // namespace syrof::board::mps2_an386
