// libFuzzer target for the radio link's streaming decoder.
//
// Input: any bytes, fed one at a time as the UART would. Every frame the
// decoder delivers must re-encode and decode again to the same frame, and
// after the input a valid frame must arrive whatever came before it (the
// resynchronisation rule of docs/radio-link.md). The same bytes also build a
// frame (kind, sequence, RSSI, status and beacon taken from them) that must
// round-trip, so the valid paths are covered without guessing a CRC.
// Anything else stops the run.
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/firmware/drivers/radio_link.h"

namespace {

using syrof::firmware::drivers::DecodeEvent;
using syrof::firmware::drivers::EncodeFrame;
using syrof::firmware::drivers::Frame;
using syrof::firmware::drivers::FrameDecoder;
using syrof::firmware::drivers::kMaxWireBytes;
using syrof::firmware::drivers::kMaxLinkBeaconBytes;
using syrof::firmware::drivers::MakeHello;
using syrof::firmware::drivers::MakeReceivedBeacon;
using syrof::firmware::drivers::MakeSendBeacon;
using syrof::firmware::drivers::MakeSendDone;
using syrof::firmware::drivers::SendStatus;

void require(bool condition) {
  if (!condition) __builtin_trap();
}

void RequireRoundTrip(const Frame& frame) {
  std::array<uint8_t, kMaxWireBytes> wire{};
  const auto length = EncodeFrame(frame, wire);
  require(length.ok());
  FrameDecoder again;
  int delivered = 0;
  for (size_t i = 0; i < length.value(); ++i) {
    const DecodeEvent event = again.Push(wire[i]);
    require(event != DecodeEvent::kError);
    if (event == DecodeEvent::kFrame) {
      require(again.frame() == frame);
      ++delivered;
    }
  }
  require(delivered == 1);
}

// A valid frame built from the input's first bytes.
void RequireBuiltFrameRoundTrips(const uint8_t* data, size_t size) {
  if (size < 4) return;
  const std::span<const uint8_t> beacon(data + 3, std::min(size - 3, kMaxLinkBeaconBytes));
  switch (data[0] % 4) {
    case 0: RequireRoundTrip(MakeSendBeacon(data[1], beacon)); break;
    case 1: RequireRoundTrip(MakeReceivedBeacon(data[1], static_cast<int8_t>(data[2]), beacon)); break;
    case 2: RequireRoundTrip(MakeSendDone(data[1], static_cast<SendStatus>(data[2] % 3))); break;
    default: RequireRoundTrip(MakeHello(data[1])); break;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FrameDecoder decoder;
  uint32_t frames = 0;
  for (size_t i = 0; i < size; ++i) {
    if (decoder.Push(data[i]) == DecodeEvent::kFrame) {
      ++frames;
      RequireRoundTrip(decoder.frame());
    }
  }
  require(decoder.counters().frames == frames);

  const uint8_t beacon[] = {2, 5, 0, 0, 0x11, 0, 0x42};
  const Frame sentinel = MakeReceivedBeacon(0xA5, -70, beacon);
  std::array<uint8_t, kMaxWireBytes> wire{};
  const auto length = EncodeFrame(sentinel, wire);
  require(length.ok());
  DecodeEvent last = DecodeEvent::kNone;
  for (size_t i = 0; i < length.value(); ++i) last = decoder.Push(wire[i]);
  require(last == DecodeEvent::kFrame && decoder.frame() == sentinel);

  RequireBuiltFrameRoundTrips(data, size);
  return 0;
}
