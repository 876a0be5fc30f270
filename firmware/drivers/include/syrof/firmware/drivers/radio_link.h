// The radio link: frames between the robot's Cortex-M4 and its nRF51822
// over a UART. Spec and rationale: docs/radio-link.md. The emulated swarm's
// sensor link (a second UART between a qemu robot and the host that plays
// the world) uses the same framing with four more kinds: IMU, flow and UWB
// readings to the robot, its drive command back (sensor_frames.h converts
// them to and from the estimator's and the motion task's messages).
//
// A frame's body is [kind][sequence][payload][CRC-16, big-endian], the CRC
// (CRC-16/GENIBUS: polynomial 0x1021, initial 0xFFFF, no reflection, final
// xor 0xFFFF; check value 0xD64E) over kind, sequence and payload. On the wire
// the body is COBS-stuffed, so it holds no 0x00 byte, and sent between two
// 0x00 delimiters. A receiver that loses its place (garbage, a dropped or
// corrupted byte) discards everything up to the next 0x00 and is in step
// again from the next frame on.
//
// The beacon inside is opaque here: the bytes wire::Encode produced (the
// radio chip puts them in one BLE advertisement, so at most 31 bytes).
//
//   Frame frame = MakeSendBeacon(sequence, beacon_bytes);
//   uint8_t wire_bytes[kMaxWireBytes];
//   auto length = EncodeFrame(frame, wire_bytes);      // to the UART
//
//   FrameDecoder decoder;                               // in the UART's RX interrupt
//   if (decoder.Push(byte) == DecodeEvent::kFrame) use(decoder.frame());
//
// Everything here is bounded (O(1) per received byte, O(frame) to encode) and
// allocates nothing.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "syrof/base/result.h"

namespace syrof::firmware::drivers {

/// Largest beacon a frame carries: one BLE legacy advertising payload.
inline constexpr size_t kMaxLinkBeaconBytes = 31;
/// kHello's version byte: this page's layout.
inline constexpr uint8_t kRadioLinkVersion = 1;

/// The body's fixed parts.
inline constexpr size_t kHeaderBytes = 2;  ///< kind, sequence
inline constexpr size_t kCrcBytes = 2;
/// Longest body: header, RSSI, a full beacon, CRC (kReceivedBeacon).
inline constexpr size_t kMaxBodyBytes = kHeaderBytes + 1 + kMaxLinkBeaconBytes + kCrcBytes;
/// COBS adds one byte per started block of 254 bytes.
inline constexpr size_t kMaxStuffedBytes = kMaxBodyBytes + (kMaxBodyBytes + 253) / 254;
/// Longest frame on the wire: both delimiters and the stuffed body.
inline constexpr size_t kMaxWireBytes = 1 + kMaxStuffedBytes + 1;

/// The frame kinds. Directions: M4 -> radio (to the nRF51822) or radio -> M4.
enum class FrameKind : uint8_t {
  kSendBeacon = 1,      ///< M4 -> radio: advertise this beacon once
  kReceivedBeacon = 2,  ///< radio -> M4: a beacon heard, with its RSSI
  kSendDone = 3,        ///< radio -> M4: what became of the kSendBeacon with this sequence
  kHello = 4,           ///< both ways: the sender (re)started; carries kRadioLinkVersion
  // The sensor link (emulated swarm): world -> M4 readings, M4 -> world drive.
  kImu = 5,    ///< world -> M4: one IMU sample (ImuPayload)
  kFlow = 6,   ///< world -> M4: one optical-flow reading (FlowPayload)
  kUwb = 7,    ///< world -> M4: one UWB sweep (UwbPayload)
  kDrive = 8,  ///< M4 -> world: the motion task's drive command (DrivePayload)
  kStart = 9,  ///< world -> M4: start the robot's clock now, for run_ms (the swarm's common start)
};

/// Anchors a kUwb frame carries (estimation::kMaxAnchors).
inline constexpr size_t kLinkAnchors = 8;

/// kImu's payload: an MPU-9250 sample in the estimator's units (each an
/// IEEE-754 binary32, big-endian on the wire; finite). No timestamp: the
/// receiver stamps a reading with its own clock when it arrives.
struct ImuPayload {
  std::array<float, 3> accel_g{};   ///< body x, y, z, g
  std::array<float, 3> gyro_dps{};  ///< body x, y, z, deg/s, counter-clockwise positive
  friend bool operator==(const ImuPayload&, const ImuPayload&) = default;
};

/// kFlow's payload.
struct FlowPayload {
  uint32_t interval_ns = 1;  ///< the interval the deltas cover, > 0
  int16_t delta_x_px = 0;    ///< body x, pixels
  int16_t delta_y_px = 0;    ///< body y, pixels
  friend bool operator==(const FlowPayload&, const FlowPayload&) = default;
};

/// kUwb's payload: a sweep's ranges in whole millimetres (0 .. 65.535 m; the
/// DWM1000 resolves about 4.7 mm), in the arena's anchor order.
struct UwbPayload {
  uint8_t valid_mask = 0;  ///< bit i: range_mm[i] is a fresh range
  uint8_t sweep = 0;       ///< the sender's sweep counter, low 8 bits
  std::array<uint16_t, kLinkAnchors> range_mm{};
  friend bool operator==(const UwbPayload&, const UwbPayload&) = default;
};

/// kDrive's payload: motion::DriveCommand without its timestamp (binary32s
/// big-endian, finite; the fields of the other kind zero).
struct DrivePayload {
  uint8_t kind = 0;  ///< motion::DriveKind: 0 omni, 1 wheels
  float vx_mps = 0;  ///< omni: arena frame, m/s
  float vy_mps = 0;
  float yaw_rate_radps = 0;
  float left_mps = 0;  ///< wheels: ground speeds, m/s
  float right_mps = 0;
  friend bool operator==(const DrivePayload&, const DrivePayload&) = default;
};

/// kSendDone's outcome.
enum class SendStatus : uint8_t {
  kSent = 0,      ///< the advertisement went out
  kBusy = 1,      ///< dropped: the previous advertisement was still on the air
  kRejected = 2,  ///< dropped: the radio could not use the beacon
};

/// One frame, decoded. Only the fields of its kind are meaningful; the
/// decoder sets the others to zero and the encoder ignores them.
struct Frame {
  FrameKind kind = FrameKind::kHello;
  uint8_t sequence = 0;                ///< the sender's counter (wraps); kSendDone echoes kSendBeacon's
  int8_t rssi_dbm = 0;                 ///< kReceivedBeacon
  SendStatus send_status = SendStatus::kSent;  ///< kSendDone
  uint8_t version = 0;                 ///< kHello
  uint8_t beacon_length = 0;           ///< kSendBeacon, kReceivedBeacon: 1 .. kMaxLinkBeaconBytes
  std::array<uint8_t, kMaxLinkBeaconBytes> beacon{};  ///< the first beacon_length bytes in use
  ImuPayload imu{};      ///< kImu
  FlowPayload flow{};    ///< kFlow
  UwbPayload uwb{};      ///< kUwb
  DrivePayload drive{};  ///< kDrive
  uint32_t run_ms = 0;   ///< kStart: how long the robot runs from now, ms (0: for ever)

  friend bool operator==(const Frame&, const Frame&) = default;
};

/// Why a frame could not be encoded, or was rejected by the decoder.
enum class [[nodiscard]] LinkError : uint8_t {
  kOk = 0,
  kBufferTooSmall,  ///< encoder: output shorter than the frame (size it kMaxWireBytes)
  kUnknownKind,     ///< the kind byte names no FrameKind
  kBadLength,       ///< the payload's length does not fit the kind (an empty or over-long beacon, too)
  kBadField,        ///< a field's value is out of range (send status, version, a non-finite float, a zero flow interval, a drive kind)
  kCrcMismatch,     ///< the CRC does not match the body
  kBadStuffing,     ///< the COBS structure ends inside a block
  kFrameTooLong,    ///< more bytes between delimiters than the longest frame
  kFrameTooShort,   ///< fewer body bytes than a header and a CRC
};

/// The enumerator's name without the k ("CrcMismatch"); "?" for an unknown value.
const char* ToString(LinkError error);
const char* ToString(FrameKind kind);

/// CRC-16/GENIBUS of `bytes` (0xD64E for the nine bytes "123456789").
uint16_t Crc16(std::span<const uint8_t> bytes);

/// Frame builders (the fields of other kinds zero). A beacon of 0 or more
/// than kMaxLinkBeaconBytes bytes gives a frame EncodeFrame rejects with
/// kBadLength (beacon_length is then the input's length, up to 255, and only
/// the first kMaxLinkBeaconBytes bytes are kept).
Frame MakeSendBeacon(uint8_t sequence, std::span<const uint8_t> beacon);
Frame MakeReceivedBeacon(uint8_t sequence, int8_t rssi_dbm, std::span<const uint8_t> beacon);
Frame MakeSendDone(uint8_t sequence, SendStatus status);
Frame MakeHello(uint8_t sequence);
Frame MakeImu(uint8_t sequence, const ImuPayload& imu);
Frame MakeFlow(uint8_t sequence, const FlowPayload& flow);
Frame MakeUwb(uint8_t sequence, const UwbPayload& uwb);
Frame MakeDrive(uint8_t sequence, const DrivePayload& drive);
Frame MakeStart(uint8_t sequence, uint32_t run_ms);

/// Writes `frame` as it goes on the wire (0x00, stuffed body, 0x00) into
/// `out` and returns the number of bytes. Errors: kUnknownKind, kBadLength
/// (beacon_length 0 or above kMaxLinkBeaconBytes), kBadField (a send status,
/// version, float, flow interval or drive kind the decoder would reject),
/// kBufferTooSmall. The decoder
/// accepts exactly what this writes.
base::Result<size_t, LinkError> EncodeFrame(const Frame& frame, std::span<uint8_t> out);

/// What FrameDecoder::Push() made of a byte.
enum class DecodeEvent : uint8_t {
  kNone,   ///< nothing yet (inside a frame, between frames, or discarding)
  kFrame,  ///< a valid frame ended: frame() holds it until the next Push
  kError,  ///< a frame was rejected: error() and error_offset() say why and where
};

/// Counts since construction or Reset(); they wrap.
struct LinkCounters {
  uint32_t frames = 0;           ///< valid frames delivered
  uint32_t rejected = 0;         ///< frames rejected (any LinkError)
  uint32_t crc_mismatches = 0;   ///< of which for a wrong CRC
  uint32_t bytes_discarded = 0;  ///< bytes skipped while looking for a delimiter
};

/// The streaming decoder: one byte at a time, from the UART's receive
/// interrupt. O(1) per byte (the CRC runs as the bytes come), no allocation,
/// 208 bytes of state on the Cortex-M4 (the sensor link's payloads included).
///
/// Resynchronisation: after construction, Reset() or a frame too long, the
/// decoder discards bytes until a 0x00; every 0x00 ends the frame in
/// progress (valid or rejected) and starts the next. So whatever garbage
/// precedes it, a complete frame sent after its leading 0x00 is received.
/// Two 0x00 in a row are an empty gap, not an error.
class FrameDecoder {
 public:
  FrameDecoder() { Reset(); }

  /// Feeds the next byte of the stream.
  DecodeEvent Push(uint8_t byte);

  /// The last valid frame (after kFrame).
  const Frame& frame() const { return frame_; }
  /// Why the last rejected frame was rejected (after kError).
  LinkError error() const { return error_; }
  /// Stream offset (bytes pushed since Reset(), from 0) of the first byte
  /// after the delimiter that started the rejected frame.
  uint64_t error_offset() const { return error_offset_; }
  const LinkCounters& counters() const { return counters_; }

  /// Back to the state after construction: discarding until a 0x00, counters zero.
  void Reset();

 private:
  DecodeEvent Reject(LinkError error);
  LinkError Finish();

  std::array<uint8_t, kMaxBodyBytes> body_{};
  size_t body_length_ = 0;
  uint16_t crc_ = 0;          // CRC register over the body so far; a fixed residue after a correct trailing CRC
  uint8_t block_left_ = 0;    // data bytes left in the current COBS block
  bool zero_pending_ = false; // the current block ends with an implied 0x00
  bool in_frame_ = false;     // a delimiter was seen and bytes are being collected
  bool started_ = false;      // at least one byte after the delimiter
  uint64_t offset_ = 0;
  uint64_t frame_start_ = 0;
  uint64_t error_offset_ = 0;
  LinkError error_ = LinkError::kOk;
  LinkCounters counters_{};
  Frame frame_{};
};

/// The frame table of docs/radio-link.md, rendered from the same constants
/// the codec uses (kinds, payloads, sizes), as a Markdown table. Returns the
/// number of characters written; kBufferTooSmall if `out` is too short.
base::Result<size_t, LinkError> RenderFrameTable(std::span<char> out);

}  // namespace syrof::firmware::drivers
