// libFuzzer target for the radio link's streaming decoder.
//
// Input: any bytes, fed one at a time as the UART would. Every frame the
// decoder delivers must re-encode and decode again to the same frame, and
// after the input a valid frame must arrive whatever came before it (the
// resynchronisation rule of docs/radio-link.md). The same bytes also build a
// frame (kind, sequence, RSSI, status, beacon and the sensor link's
// readings and drive command taken from them) that must
// round-trip, so the valid paths are covered without guessing a CRC.
// Anything else stops the run.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
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
namespace drivers = syrof::firmware::drivers;

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

// A finite float from four of the input's bytes (0 past its end).
float FloatAt(const uint8_t* data, size_t size, size_t at) {
  uint8_t bytes[4] = {};
  for (size_t i = 0; i < 4 && at + i < size; ++i) bytes[i] = data[at + i];
  float value;
  std::memcpy(&value, bytes, sizeof value);
  return std::isfinite(value) ? value : 1.0f;
}

// A valid frame built from the input's first bytes.
void RequireBuiltFrameRoundTrips(const uint8_t* data, size_t size) {
  if (size < 4) return;
  const std::span<const uint8_t> beacon(data + 3, std::min(size - 3, kMaxLinkBeaconBytes));
  switch (data[0] % 8) {
    case 0: RequireRoundTrip(MakeSendBeacon(data[1], beacon)); break;
    case 1: RequireRoundTrip(MakeReceivedBeacon(data[1], static_cast<int8_t>(data[2]), beacon)); break;
    case 2: RequireRoundTrip(MakeSendDone(data[1], static_cast<SendStatus>(data[2] % 3))); break;
    case 3: RequireRoundTrip(MakeHello(data[1])); break;
    case 4: {
      drivers::ImuPayload imu;
      for (size_t i = 0; i < 3; ++i) {
        imu.accel_g[i] = FloatAt(data, size, 3 + 4 * i);
        imu.gyro_dps[i] = FloatAt(data, size, 15 + 4 * i);
      }
      RequireRoundTrip(drivers::MakeImu(data[1], imu));
      break;
    }
    case 5:
      RequireRoundTrip(drivers::MakeFlow(
          data[1], drivers::FlowPayload{static_cast<uint32_t>(data[2]) + 1u, static_cast<int16_t>(data[3] << 8),
                                        static_cast<int16_t>(-data[2])}));
      break;
    case 6: {
      drivers::UwbPayload uwb;
      uwb.valid_mask = data[2];
      uwb.sweep = data[3];
      for (size_t i = 0; i < drivers::kLinkAnchors && 4 + 2 * i + 1 < size; ++i) {
        uwb.range_mm[i] = static_cast<uint16_t>((data[4 + 2 * i] << 8) | data[5 + 2 * i]);
      }
      RequireRoundTrip(drivers::MakeUwb(data[1], uwb));
      break;
    }
    default: {
      drivers::DrivePayload drive;
      drive.kind = data[2] % 2;
      drive.vx_mps = FloatAt(data, size, 3);
      drive.vy_mps = FloatAt(data, size, 7);
      drive.yaw_rate_radps = FloatAt(data, size, 11);
      drive.left_mps = FloatAt(data, size, 15);
      drive.right_mps = FloatAt(data, size, 19);
      RequireRoundTrip(drivers::MakeDrive(data[1], drive));
      break;
    }
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
