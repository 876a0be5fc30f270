#include "syrof/sim_dds/report_codec.h"

#include <algorithm>
#include <cstring>

#include "syrof/sync/synchronizer.h"

namespace syrof::sim_dds {
namespace {

class Writer {
 public:
  explicit Writer(ReportKind) {}
  void U8(uint8_t v) { bytes_.push_back(v); }
  void U16(uint16_t v) { Raw(&v, 2); }
  void I16(int16_t v) { Raw(&v, 2); }
  void U32(uint32_t v) { Raw(&v, 4); }
  void I64(int64_t v) { Raw(&v, 8); }
  void U64(uint64_t v) { Raw(&v, 8); }
  void F32(float v) { Raw(&v, 4); }
  void Text(std::string_view text) {
    const size_t room = kMaxReportBytes - std::min(kMaxReportBytes, bytes_.size());
    Raw(text.data(), std::min(room, text.size()));
  }
  std::vector<uint8_t> Take() { return std::move(bytes_); }

 private:
  // Little-endian hosts only (x86-64, aarch64): the world and robots are.
  void Raw(const void* data, size_t size) {
    const auto* p = static_cast<const uint8_t*>(data);
    bytes_.insert(bytes_.end(), p, p + size);
  }
  std::vector<uint8_t> bytes_;
};

class Reader {
 public:
  explicit Reader(std::span<const uint8_t> bytes) : bytes_(bytes) {}
  bool U8(uint8_t& v) { return Raw(&v, 1); }
  bool U16(uint16_t& v) { return Raw(&v, 2); }
  bool I16(int16_t& v) { return Raw(&v, 2); }
  bool U32(uint32_t& v) { return Raw(&v, 4); }
  bool I64(int64_t& v) { return Raw(&v, 8); }
  bool U64(uint64_t& v) { return Raw(&v, 8); }
  bool F32(float& v) { return Raw(&v, 4); }
  std::string Rest() {
    std::string text(bytes_.begin() + static_cast<std::ptrdiff_t>(offset_), bytes_.end());
    offset_ = bytes_.size();
    return text;
  }
  bool done() const { return offset_ == bytes_.size(); }

 private:
  bool Raw(void* out, size_t size) {
    if (bytes_.size() - offset_ < size) return false;
    std::memcpy(out, bytes_.data() + offset_, size);
    offset_ += size;
    return true;
  }
  std::span<const uint8_t> bytes_;
  size_t offset_ = 0;
};

void WriteSet(Writer& w, const wire::MemberSet& set) {
  w.U16(static_cast<uint16_t>(set.count()));
  for (const uint16_t id : set) w.U16(id);
}

// What is wrong with the report's part `where` ("" for the whole report).
lab::Error BadReport(std::string where, std::string message) {
  return lab::Error{.where = std::move(where), .message = std::move(message)};
}

// Reads a member set, the report's part `what`, into `set`; what is wrong
// with it, if anything.
std::optional<lab::Error> ReadSet(Reader& r, uint16_t swarm_size, wire::MemberSet& set, const char* what) {
  uint16_t count = 0;
  if (!r.U16(count)) return BadReport(what, "truncated count");
  if (count > swarm_size) {
    return BadReport(what, std::to_string(count) + " ids for a swarm of " + std::to_string(swarm_size));
  }
  for (uint16_t i = 0; i < count; ++i) {
    uint16_t id = 0;
    if (!r.U16(id)) return BadReport(what, "truncated id list");
    if (id >= swarm_size) {
      return BadReport(what, "id " + std::to_string(id) + " at or above the swarm size " + std::to_string(swarm_size));
    }
    set.set(id);
  }
  return std::nullopt;
}

}  // namespace

std::vector<uint8_t> EncodeEpochStart(const sync::LDMap& ldmap) {
  Writer w(ReportKind::kEpochStart);
  w.U16(ldmap.epoch);
  w.U8(static_cast<uint8_t>(ldmap.mode));
  w.U16(static_cast<uint16_t>(ldmap.members.count()));
  for (const uint16_t id : ldmap.members) {
    const wire::Snapshot& s = ldmap.snapshots[id];
    w.U16(id);
    w.U8(static_cast<uint8_t>(ldmap.phases[id]));
    w.I16(s.x_mm);
    w.I16(s.y_mm);
    w.I16(s.heading_mrad);
    w.I16(s.vx_mm_s);
    w.I16(s.vy_mm_s);
    w.U8(s.payload_length);
    for (const uint8_t byte : s.payload) w.U8(byte);
  }
  return w.Take();
}

std::vector<uint8_t> EncodeMembership(const wire::MemberSet& removed, const wire::MemberSet& joined) {
  Writer w(ReportKind::kMembership);
  WriteSet(w, removed);
  WriteSet(w, joined);
  return w.Take();
}

std::vector<uint8_t> EncodeAppFault(uint8_t callback, uint16_t epoch, uint8_t verdict, std::string_view detail) {
  Writer w(ReportKind::kAppFault);
  w.U8(callback);
  w.U16(epoch);
  w.U8(verdict);
  w.Text(detail);
  return w.Take();
}

std::vector<uint8_t> EncodeInvalidCommand(uint16_t epoch, std::string_view what) {
  Writer w(ReportKind::kInvalidCommand);
  w.U16(epoch);
  w.Text(what);
  return w.Take();
}

std::vector<uint8_t> EncodePayloadRefused(uint16_t epoch, uint32_t length) {
  Writer w(ReportKind::kPayloadRefused);
  w.U16(epoch);
  w.U32(length);
  return w.Take();
}

std::vector<uint8_t> EncodeSafety(int64_t time_ns, uint16_t other) {
  Writer w(ReportKind::kSafety);
  w.I64(time_ns);
  w.U16(other);
  return w.Take();
}

std::vector<uint8_t> EncodePrecaution(int64_t time_ns, uint16_t other) {
  Writer w(ReportKind::kPrecaution);
  w.I64(time_ns);
  w.U16(other);
  return w.Take();
}

std::vector<uint8_t> EncodeRound(const RoundReport& round) {
  Writer w(ReportKind::kRound);
  w.U32(round.round);
  w.I64(round.activation_ns);
  w.U8(round.status);
  w.U8(round.phase);
  w.U8(round.epoch_mode);
  w.U8(round.estimate_valid);
  w.U16(round.epoch);
  w.F32(round.est_x_m);
  w.F32(round.est_y_m);
  w.F32(round.est_heading_rad);
  w.U32(round.beacons_heard);
  WriteSet(w, round.heard_in_round);
  return w.Take();
}

std::vector<uint8_t> EncodeAppState(const AppStateReport& app_state) {
  Writer w(ReportKind::kAppState);
  w.U8(app_state.new_round ? 1 : 0);
  w.U16(app_state.epoch);
  w.U8(app_state.cooperative ? 1 : 0);
  w.U64(app_state.map_fingerprint);
  w.U8(app_state.state);
  return w.Take();
}

DecodedReport DecodeReport(uint8_t kind, std::span<const uint8_t> bytes, uint16_t swarm_size) {
  DecodedReport result;
  std::optional<lab::Error>& error = result.error;
  if (kind >= kReportKinds) {
    error = BadReport("", "report kind " + std::to_string(kind) + " unknown (0 .. " +
                              std::to_string(kReportKinds - 1) + ")");
    return result;
  }
  if (bytes.size() > kMaxReportBytes) {
    error = BadReport("", "report body of " + std::to_string(bytes.size()) + " bytes, above " +
                              std::to_string(kMaxReportBytes));
    return result;
  }
  ReportBody body;
  body.kind = static_cast<ReportKind>(kind);
  Reader r(bytes);
  bool ok = true;
  switch (body.kind) {
    case ReportKind::kEpochStart: {
      uint8_t mode = 0;
      uint16_t count = 0;
      ok = r.U16(body.ldmap.epoch) && r.U8(mode) && r.U16(count);
      if (!ok) break;
      if (mode > 1) {
        error = BadReport("epoch start", "mode " + std::to_string(mode) + " unknown");
        return result;
      }
      if (count == 0 || count > swarm_size) {
        error = BadReport("epoch start",
                          std::to_string(count) + " members for a swarm of " + std::to_string(swarm_size));
        return result;
      }
      body.ldmap.mode = static_cast<wire::Mode>(mode);
      int last = -1;
      for (uint16_t i = 0; i < count && ok; ++i) {
        uint16_t id = 0;
        uint8_t phase = 0;
        wire::Snapshot s;
        ok = r.U16(id) && r.U8(phase) && r.I16(s.x_mm) && r.I16(s.y_mm) && r.I16(s.heading_mrad) &&
             r.I16(s.vx_mm_s) && r.I16(s.vy_mm_s) && r.U8(s.payload_length);
        for (uint8_t& byte : s.payload) ok = ok && r.U8(byte);
        if (!ok) break;
        if (id >= swarm_size || static_cast<int>(id) <= last) {
          error = BadReport("epoch start", "member " + std::to_string(id) +
                                               " out of order or at or above the swarm size " +
                                               std::to_string(swarm_size));
          return result;
        }
        if (phase > 2 || s.payload_length > wire::kMaxPayloadBytes) {
          error = BadReport("epoch start", "member " + std::to_string(id) + " has phase " + std::to_string(phase) +
                                               " or payload length " + std::to_string(s.payload_length) +
                                               " out of range");
          return result;
        }
        last = id;
        body.ldmap.members.set(id);
        body.ldmap.phases[id] = static_cast<wire::Phase>(phase);
        body.ldmap.snapshots[id] = s;
      }
      break;
    }
    case ReportKind::kMembership:
      if ((error = ReadSet(r, swarm_size, body.removed, "membership removed")) ||
          (error = ReadSet(r, swarm_size, body.joined, "membership joined"))) {
        return result;
      }
      break;
    case ReportKind::kBecameJoiner:
      break;
    case ReportKind::kAppFault:
      ok = r.U8(body.callback) && r.U16(body.epoch) && r.U8(body.verdict);
      if (ok) body.text = r.Rest();
      break;
    case ReportKind::kInvalidCommand:
      ok = r.U16(body.epoch);
      if (ok) body.text = r.Rest();
      break;
    case ReportKind::kPayloadRefused:
      ok = r.U16(body.epoch) && r.U32(body.length);
      break;
    case ReportKind::kSafety:
    case ReportKind::kPrecaution:
      ok = r.I64(body.time_ns) && r.U16(body.other);
      break;
    case ReportKind::kRound: {
      RoundReport& round = body.round;
      ok = r.U32(round.round) && r.I64(round.activation_ns) && r.U8(round.status) && r.U8(round.phase) &&
           r.U8(round.epoch_mode) && r.U8(round.estimate_valid) && r.U16(round.epoch) && r.F32(round.est_x_m) &&
           r.F32(round.est_y_m) && r.F32(round.est_heading_rad) && r.U32(round.beacons_heard);
      if (ok && (round.status > 1 || round.phase > 2 || round.epoch_mode > 1 || round.estimate_valid > 1)) {
        error = BadReport("round report", "status, phase, mode or estimate flag out of range");
        return result;
      }
      if (ok && (error = ReadSet(r, swarm_size, round.heard_in_round, "round report heard_in_round"))) return result;
      break;
    }
    case ReportKind::kAppState: {
      AppStateReport& app_state = body.app_state;
      uint8_t new_round = 0, cooperative = 0;
      ok = r.U8(new_round) && r.U16(app_state.epoch) && r.U8(cooperative) && r.U64(app_state.map_fingerprint) &&
           r.U8(app_state.state);
      if (ok && (new_round > 1 || cooperative > 1)) {
        error = BadReport("app state report", "call or mode flag out of range");
        return result;
      }
      app_state.new_round = new_round != 0;
      app_state.cooperative = cooperative != 0;
      break;
    }
  }
  if (!ok) {
    error = BadReport("report kind " + std::to_string(kind),
                      "body of " + std::to_string(bytes.size()) + " bytes is truncated");
    return result;
  }
  if (!r.done()) {
    error = BadReport("report kind " + std::to_string(kind),
                      std::to_string(bytes.size()) + " bytes, more than its layout");
    return result;
  }
  result.body = std::move(body);
  return result;
}

}  // namespace syrof::sim_dds
