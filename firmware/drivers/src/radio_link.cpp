#include "syrof/firmware/drivers/radio_link.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace syrof::firmware::drivers {
namespace {

// The one description of the frame kinds: the decoder's length and field
// checks and docs/radio-link.md's table both come from it.
struct KindDescription {
  FrameKind kind;
  const char* direction;
  uint8_t fixed_payload_bytes;  // before the beacon, if any
  bool carries_beacon;          // then 1 .. kMaxLinkBeaconBytes beacon bytes
  const char* payload;          // for the table
};

constexpr KindDescription kKinds[] = {
    {FrameKind::kSendBeacon, "M4 to radio", 0, true, "beacon (1 to 31 bytes, as wire::Encode wrote it)"},
    {FrameKind::kReceivedBeacon, "radio to M4", 1, true,
     "rssi_dbm (1 byte, signed, dBm), then the beacon (1 to 31 bytes)"},
    {FrameKind::kSendDone, "radio to M4", 1, false,
     "status (1 byte): 0 sent, 1 busy (dropped), 2 rejected (dropped)"},
    {FrameKind::kHello, "both", 1, false, "version (1 byte): 1"},
    {FrameKind::kImu, "world to M4", 24, false,
     "accel_g x, y, z, then gyro_dps x, y, z: six binary32, finite"},
    {FrameKind::kFlow, "world to M4", 8, false,
     "interval_ns (4 bytes, > 0), delta_x_px, delta_y_px (2 bytes each, signed)"},
    {FrameKind::kUwb, "world to M4", 18, false,
     "valid_mask (1 byte), sweep (1 byte), 8 ranges in mm (2 bytes each)"},
    {FrameKind::kDrive, "M4 to world", 21, false,
     "drive kind (1 byte: 0 omni, 1 wheels), vx_mps, vy_mps, yaw_rate_radps, left_mps, right_mps: five binary32, finite"},
    {FrameKind::kStart, "world to M4", 4, false, "run_ms (4 bytes): how long the robot runs from this frame, 0 for ever"},
};

// Big-endian fields of the sensor link's payloads.
void PutU16(uint8_t* at, uint16_t value) {
  at[0] = static_cast<uint8_t>(value >> 8);
  at[1] = static_cast<uint8_t>(value & 0xFF);
}
void PutU32(uint8_t* at, uint32_t value) {
  PutU16(at, static_cast<uint16_t>(value >> 16));
  PutU16(at + 2, static_cast<uint16_t>(value & 0xFFFF));
}
void PutFloat(uint8_t* at, float value) { PutU32(at, std::bit_cast<uint32_t>(value)); }
uint16_t GetU16(const uint8_t* at) { return static_cast<uint16_t>((uint16_t{at[0]} << 8) | at[1]); }
uint32_t GetU32(const uint8_t* at) { return (uint32_t{GetU16(at)} << 16) | GetU16(at + 2); }
float GetFloat(const uint8_t* at) { return std::bit_cast<float>(GetU32(at)); }

bool AllFinite(std::span<const float> values) {
  for (const float value : values) {
    if (!std::isfinite(value)) return false;
  }
  return true;
}

// The sensor-link kinds' payloads: written into `at` (fixed_payload_bytes
// long), or read from it; false for a value the link refuses.
bool PutSensorPayload(const Frame& frame, uint8_t* at) {
  switch (frame.kind) {
    case FrameKind::kImu:
      if (!AllFinite(frame.imu.accel_g) || !AllFinite(frame.imu.gyro_dps)) return false;
      for (size_t i = 0; i < 3; ++i) PutFloat(at + 4 * i, frame.imu.accel_g[i]);
      for (size_t i = 0; i < 3; ++i) PutFloat(at + 12 + 4 * i, frame.imu.gyro_dps[i]);
      return true;
    case FrameKind::kFlow:
      if (frame.flow.interval_ns == 0) return false;
      PutU32(at, frame.flow.interval_ns);
      PutU16(at + 4, static_cast<uint16_t>(frame.flow.delta_x_px));
      PutU16(at + 6, static_cast<uint16_t>(frame.flow.delta_y_px));
      return true;
    case FrameKind::kUwb:
      at[0] = frame.uwb.valid_mask;
      at[1] = frame.uwb.sweep;
      for (size_t i = 0; i < kLinkAnchors; ++i) PutU16(at + 2 + 2 * i, frame.uwb.range_mm[i]);
      return true;
    case FrameKind::kDrive: {
      const DrivePayload& drive = frame.drive;
      const float values[] = {drive.vx_mps, drive.vy_mps, drive.yaw_rate_radps, drive.left_mps, drive.right_mps};
      if (drive.kind > 1 || !AllFinite(values)) return false;
      at[0] = drive.kind;
      for (size_t i = 0; i < 5; ++i) PutFloat(at + 1 + 4 * i, values[i]);
      return true;
    }
    case FrameKind::kStart: PutU32(at, frame.run_ms); return true;
    default: return false;
  }
}

bool GetSensorPayload(const uint8_t* at, Frame& frame) {
  switch (frame.kind) {
    case FrameKind::kImu:
      for (size_t i = 0; i < 3; ++i) frame.imu.accel_g[i] = GetFloat(at + 4 * i);
      for (size_t i = 0; i < 3; ++i) frame.imu.gyro_dps[i] = GetFloat(at + 12 + 4 * i);
      return AllFinite(frame.imu.accel_g) && AllFinite(frame.imu.gyro_dps);
    case FrameKind::kFlow:
      frame.flow.interval_ns = GetU32(at);
      frame.flow.delta_x_px = static_cast<int16_t>(GetU16(at + 4));
      frame.flow.delta_y_px = static_cast<int16_t>(GetU16(at + 6));
      return frame.flow.interval_ns != 0;
    case FrameKind::kUwb:
      frame.uwb.valid_mask = at[0];
      frame.uwb.sweep = at[1];
      for (size_t i = 0; i < kLinkAnchors; ++i) frame.uwb.range_mm[i] = GetU16(at + 2 + 2 * i);
      return true;
    case FrameKind::kDrive: {
      DrivePayload& drive = frame.drive;
      drive.kind = at[0];
      float values[5];
      for (size_t i = 0; i < 5; ++i) values[i] = GetFloat(at + 1 + 4 * i);
      drive.vx_mps = values[0];
      drive.vy_mps = values[1];
      drive.yaw_rate_radps = values[2];
      drive.left_mps = values[3];
      drive.right_mps = values[4];
      return drive.kind <= 1 && AllFinite(values);
    }
    case FrameKind::kStart: frame.run_ms = GetU32(at); return true;
    default: return false;
  }
}

const KindDescription* Describe(uint8_t kind) {
  for (const KindDescription& description : kKinds) {
    if (static_cast<uint8_t>(description.kind) == kind) return &description;
  }
  return nullptr;
}

constexpr uint8_t kMaxSendStatus = static_cast<uint8_t>(SendStatus::kRejected);

// CRC-16/GENIBUS: the CCITT polynomial, register preset to 0xFFFF, result
// inverted. The register after a body whose own CRC follows it (big-endian)
// is this constant whatever the body.
constexpr uint16_t kCrcInitial = 0xFFFF;
constexpr uint16_t kCrcFinalXor = 0xFFFF;
constexpr uint16_t kCrcResidue = 0x1D0F;

uint16_t CrcStep(uint16_t crc, uint8_t byte) {
  crc = static_cast<uint16_t>(crc ^ (uint16_t{byte} << 8));
  for (int bit = 0; bit < 8; ++bit) {
    crc = (crc & 0x8000u) ? static_cast<uint16_t>((crc << 1) ^ 0x1021u) : static_cast<uint16_t>(crc << 1);
  }
  return crc;
}

// Longest body of a kind, and its wire size with COBS's overhead and both delimiters.
size_t MaxBodyBytes(const KindDescription& description) {
  return kHeaderBytes + description.fixed_payload_bytes + (description.carries_beacon ? kMaxLinkBeaconBytes : 0) +
         kCrcBytes;
}
size_t MinBodyBytes(const KindDescription& description) {
  return kHeaderBytes + description.fixed_payload_bytes + (description.carries_beacon ? 1 : 0) + kCrcBytes;
}
size_t WireBytes(size_t body_bytes) { return 1 + body_bytes + (body_bytes + 253) / 254 + 1; }

}  // namespace

const char* ToString(LinkError error) {
  switch (error) {
    case LinkError::kOk: return "Ok";
    case LinkError::kBufferTooSmall: return "BufferTooSmall";
    case LinkError::kUnknownKind: return "UnknownKind";
    case LinkError::kBadLength: return "BadLength";
    case LinkError::kBadField: return "BadField";
    case LinkError::kCrcMismatch: return "CrcMismatch";
    case LinkError::kBadStuffing: return "BadStuffing";
    case LinkError::kFrameTooLong: return "FrameTooLong";
    case LinkError::kFrameTooShort: return "FrameTooShort";
  }
  return "?";
}

const char* ToString(FrameKind kind) {
  switch (kind) {
    case FrameKind::kSendBeacon: return "SendBeacon";
    case FrameKind::kReceivedBeacon: return "ReceivedBeacon";
    case FrameKind::kSendDone: return "SendDone";
    case FrameKind::kHello: return "Hello";
    case FrameKind::kImu: return "Imu";
    case FrameKind::kFlow: return "Flow";
    case FrameKind::kUwb: return "Uwb";
    case FrameKind::kDrive: return "Drive";
    case FrameKind::kStart: return "Start";
  }
  return "?";
}

uint16_t Crc16(std::span<const uint8_t> bytes) {
  uint16_t crc = kCrcInitial;
  for (const uint8_t byte : bytes) crc = CrcStep(crc, byte);
  return static_cast<uint16_t>(crc ^ kCrcFinalXor);
}

namespace {

Frame WithBeacon(FrameKind kind, uint8_t sequence, std::span<const uint8_t> beacon) {
  Frame frame;
  frame.kind = kind;
  frame.sequence = sequence;
  frame.beacon_length = static_cast<uint8_t>(std::min<size_t>(beacon.size(), 255));
  std::copy_n(beacon.begin(), std::min(beacon.size(), kMaxLinkBeaconBytes), frame.beacon.begin());
  return frame;
}

}  // namespace

Frame MakeSendBeacon(uint8_t sequence, std::span<const uint8_t> beacon) {
  return WithBeacon(FrameKind::kSendBeacon, sequence, beacon);
}

Frame MakeReceivedBeacon(uint8_t sequence, int8_t rssi_dbm, std::span<const uint8_t> beacon) {
  Frame frame = WithBeacon(FrameKind::kReceivedBeacon, sequence, beacon);
  frame.rssi_dbm = rssi_dbm;
  return frame;
}

Frame MakeSendDone(uint8_t sequence, SendStatus status) {
  Frame frame;
  frame.kind = FrameKind::kSendDone;
  frame.sequence = sequence;
  frame.send_status = status;
  return frame;
}

Frame MakeHello(uint8_t sequence) {
  Frame frame;
  frame.kind = FrameKind::kHello;
  frame.sequence = sequence;
  frame.version = kRadioLinkVersion;
  return frame;
}

namespace {

Frame WithKind(FrameKind kind, uint8_t sequence) {
  Frame frame;
  frame.kind = kind;
  frame.sequence = sequence;
  return frame;
}

}  // namespace

Frame MakeImu(uint8_t sequence, const ImuPayload& imu) {
  Frame frame = WithKind(FrameKind::kImu, sequence);
  frame.imu = imu;
  return frame;
}

Frame MakeFlow(uint8_t sequence, const FlowPayload& flow) {
  Frame frame = WithKind(FrameKind::kFlow, sequence);
  frame.flow = flow;
  return frame;
}

Frame MakeUwb(uint8_t sequence, const UwbPayload& uwb) {
  Frame frame = WithKind(FrameKind::kUwb, sequence);
  frame.uwb = uwb;
  return frame;
}

Frame MakeDrive(uint8_t sequence, const DrivePayload& drive) {
  Frame frame = WithKind(FrameKind::kDrive, sequence);
  frame.drive = drive;
  return frame;
}

Frame MakeStart(uint8_t sequence, uint32_t run_ms) {
  Frame frame = WithKind(FrameKind::kStart, sequence);
  frame.run_ms = run_ms;
  return frame;
}

base::Result<size_t, LinkError> EncodeFrame(const Frame& frame, std::span<uint8_t> out) {
  const KindDescription* description = Describe(static_cast<uint8_t>(frame.kind));
  if (description == nullptr) return LinkError::kUnknownKind;

  std::array<uint8_t, kMaxBodyBytes> body{};
  size_t length = 0;
  body[length++] = static_cast<uint8_t>(frame.kind);
  body[length++] = frame.sequence;
  switch (frame.kind) {
    case FrameKind::kReceivedBeacon: body[length++] = static_cast<uint8_t>(frame.rssi_dbm); break;
    case FrameKind::kSendDone:
      if (static_cast<uint8_t>(frame.send_status) > kMaxSendStatus) return LinkError::kBadField;
      body[length++] = static_cast<uint8_t>(frame.send_status);
      break;
    case FrameKind::kHello:
      if (frame.version != kRadioLinkVersion) return LinkError::kBadField;
      body[length++] = frame.version;
      break;
    case FrameKind::kSendBeacon: break;
    case FrameKind::kImu:
    case FrameKind::kFlow:
    case FrameKind::kUwb:
    case FrameKind::kDrive:
    case FrameKind::kStart:
      if (!PutSensorPayload(frame, body.data() + length)) return LinkError::kBadField;
      length += description->fixed_payload_bytes;
      break;
  }
  if (description->carries_beacon) {
    if (frame.beacon_length == 0 || frame.beacon_length > kMaxLinkBeaconBytes) return LinkError::kBadLength;
    std::copy_n(frame.beacon.begin(), frame.beacon_length, body.begin() + static_cast<std::ptrdiff_t>(length));
    length += frame.beacon_length;
  }
  const uint16_t crc = Crc16(std::span<const uint8_t>(body.data(), length));
  body[length++] = static_cast<uint8_t>(crc >> 8);
  body[length++] = static_cast<uint8_t>(crc & 0xFF);

  const size_t wire_bytes = WireBytes(length);
  if (out.size() < wire_bytes) return LinkError::kBufferTooSmall;
  // COBS: each block is a code byte n followed by n - 1 non-zero bytes; a
  // code below 0xFF stands for a 0x00 after its block (dropped at the end).
  size_t at = 0;
  out[at++] = 0x00;
  size_t code_at = at++;
  uint8_t code = 1;
  for (size_t i = 0; i < length; ++i) {
    if (body[i] == 0) {
      out[code_at] = code;
      code_at = at++;
      code = 1;
      continue;
    }
    out[at++] = body[i];
    if (++code == 0xFF) {
      out[code_at] = code;
      code_at = at++;
      code = 1;
    }
  }
  out[code_at] = code;
  out[at++] = 0x00;
  SYROF_CHECK(at <= wire_bytes);
  return at;
}

void FrameDecoder::Reset() {
  body_length_ = 0;
  crc_ = kCrcInitial;
  block_left_ = 0;
  zero_pending_ = false;
  in_frame_ = false;
  started_ = false;
  offset_ = 0;
  frame_start_ = 0;
  error_offset_ = 0;
  error_ = LinkError::kOk;
  counters_ = {};
  frame_ = {};
}

DecodeEvent FrameDecoder::Reject(LinkError error) {
  error_ = error;
  error_offset_ = frame_start_;
  ++counters_.rejected;
  if (error == LinkError::kCrcMismatch) ++counters_.crc_mismatches;
  return DecodeEvent::kError;
}

DecodeEvent FrameDecoder::Push(uint8_t byte) {
  const uint64_t here = offset_++;
  if (byte == 0x00) {
    const bool had_frame = in_frame_ && started_;
    const LinkError result = had_frame ? Finish() : LinkError::kOk;
    const uint64_t rejected_start = frame_start_;
    // Every delimiter starts the next frame.
    in_frame_ = true;
    started_ = false;
    body_length_ = 0;
    crc_ = kCrcInitial;
    block_left_ = 0;
    zero_pending_ = false;
    frame_start_ = here + 1;
    if (!had_frame) return DecodeEvent::kNone;
    if (result != LinkError::kOk) {
      frame_start_ = rejected_start;
      const DecodeEvent event = Reject(result);
      frame_start_ = here + 1;
      return event;
    }
    ++counters_.frames;
    return DecodeEvent::kFrame;
  }
  if (!in_frame_) {
    ++counters_.bytes_discarded;
    return DecodeEvent::kNone;
  }
  started_ = true;
  uint8_t data = byte;
  bool append = true;
  if (block_left_ == 0) {  // a code byte: its block's length, and the previous block's implied zero
    block_left_ = static_cast<uint8_t>(byte - 1);
    append = zero_pending_;
    data = 0x00;
    zero_pending_ = byte != 0xFF;
  } else {
    --block_left_;
  }
  if (!append) return DecodeEvent::kNone;
  if (body_length_ == kMaxBodyBytes) {
    in_frame_ = false;  // discard up to the next delimiter
    return Reject(LinkError::kFrameTooLong);
  }
  body_[body_length_++] = data;
  crc_ = CrcStep(crc_, data);
  return DecodeEvent::kNone;
}

LinkError FrameDecoder::Finish() {
  if (block_left_ != 0) return LinkError::kBadStuffing;
  if (body_length_ < kHeaderBytes + kCrcBytes) return LinkError::kFrameTooShort;
  if (crc_ != kCrcResidue) return LinkError::kCrcMismatch;

  const KindDescription* description = Describe(body_[0]);
  if (description == nullptr) return LinkError::kUnknownKind;
  const size_t payload_bytes = body_length_ - kHeaderBytes - kCrcBytes;
  const size_t beacon_bytes = payload_bytes - std::min<size_t>(payload_bytes, description->fixed_payload_bytes);
  if (payload_bytes < description->fixed_payload_bytes) return LinkError::kBadLength;
  if (description->carries_beacon ? (beacon_bytes == 0 || beacon_bytes > kMaxLinkBeaconBytes) : beacon_bytes != 0) {
    return LinkError::kBadLength;
  }

  Frame frame;
  frame.kind = description->kind;
  frame.sequence = body_[1];
  const uint8_t* payload = body_.data() + kHeaderBytes;
  switch (frame.kind) {
    case FrameKind::kReceivedBeacon: frame.rssi_dbm = static_cast<int8_t>(payload[0]); break;
    case FrameKind::kSendDone:
      if (payload[0] > kMaxSendStatus) return LinkError::kBadField;
      frame.send_status = static_cast<SendStatus>(payload[0]);
      break;
    case FrameKind::kHello:
      if (payload[0] != kRadioLinkVersion) return LinkError::kBadField;
      frame.version = payload[0];
      break;
    case FrameKind::kSendBeacon: break;
    case FrameKind::kImu:
    case FrameKind::kFlow:
    case FrameKind::kUwb:
    case FrameKind::kDrive:
    case FrameKind::kStart:
      if (!GetSensorPayload(payload, frame)) return LinkError::kBadField;
      break;
  }
  if (description->carries_beacon) {
    frame.beacon_length = static_cast<uint8_t>(beacon_bytes);
    std::copy_n(payload + description->fixed_payload_bytes, beacon_bytes, frame.beacon.begin());
  }
  frame_ = frame;
  return LinkError::kOk;
}

namespace {

// Appends text and numbers to a fixed buffer; remembers when it ran out.
class TableWriter {
 public:
  explicit TableWriter(std::span<char> out) : out_(out) {}

  TableWriter& operator<<(const char* text) {
    for (; *text != '\0'; ++text) Put(*text);
    return *this;
  }
  TableWriter& operator<<(size_t number) {
    char digits[20];
    size_t count = 0;
    do {
      digits[count++] = static_cast<char>('0' + number % 10);
      number /= 10;
    } while (number > 0);
    while (count > 0) Put(digits[--count]);
    return *this;
  }
  bool fits() const { return fits_; }
  size_t length() const { return at_; }

 private:
  void Put(char c) {
    if (at_ >= out_.size()) {
      fits_ = false;
      return;
    }
    out_[at_++] = c;
  }

  std::span<char> out_;
  size_t at_ = 0;
  bool fits_ = true;
};

}  // namespace

base::Result<size_t, LinkError> RenderFrameTable(std::span<char> out) {
  TableWriter table(out);
  table << "| Kind | Value | Direction | Payload | Body bytes | Wire bytes |\n";
  table << "| --- | --- | --- | --- | --- | --- |\n";
  for (const KindDescription& description : kKinds) {
    const size_t low = MinBodyBytes(description);
    const size_t high = MaxBodyBytes(description);
    table << "| " << ToString(description.kind) << " | " << static_cast<size_t>(description.kind) << " | "
          << description.direction << " | " << description.payload << " | ";
    if (low == high) {
      table << low << " | " << WireBytes(low) << " |\n";
    } else {
      table << low << " to " << high << " | " << WireBytes(low) << " to " << WireBytes(high) << " |\n";
    }
  }
  if (!table.fits()) return LinkError::kBufferTooSmall;
  return table.length();
}

}  // namespace syrof::firmware::drivers
