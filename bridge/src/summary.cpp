#include "syrof/bridge/summary.h"

#include <nlohmann/json.hpp>

#include <cstdio>

#include "syrof/lab/replay/reader.h"
#include "syrof/wire/beacon.h"

namespace syrof::bridge {

namespace replay = lab::replay;

ReplayFacts ReadReplayFacts(std::istream& in) {
  ReplayFacts facts;
  replay::Reader reader(in);
  replay::Header header;
  if (!reader.ReadHeader(header)) {
    facts.error = reader.error();
    return facts;
  }
  facts.robots.resize(header.robots.size());
  for (size_t i = 0; i < header.robots.size(); ++i) facts.robots[i].id = header.robots[i].id;
  replay::Round round;
  while (reader.Next(round)) {
    ++facts.rounds;
    for (const replay::RobotFrame& frame : round.robots) {
      if (frame.id >= facts.robots.size() || frame.presence != replay::Presence::kRunning) continue;
      RobotReplayFacts& robot = facts.robots[frame.id];
      if (!robot.seen) robot.first_epoch = frame.epoch;
      robot.seen = true;
      robot.last_epoch = frame.epoch;
      ++robot.running_rounds;
    }
    for (const replay::Event& event : round.events) {
      if (event.kind != replay::EventKind::kEpochStart || event.robot >= facts.robots.size()) continue;
      ++facts.robots[event.robot].epoch_starts;
      if (event.mode == static_cast<uint8_t>(wire::Mode::kCooperative)) ++facts.robots[event.robot].cooperative_starts;
    }
  }
  facts.read = reader.complete();
  if (!facts.read) facts.error = reader.error();
  return facts;
}

namespace {

nlohmann::json ReasonCounts(std::span<const uint64_t> counts, const char* (*name)(size_t)) {
  nlohmann::json object = nlohmann::json::object();
  for (size_t i = 1; i < counts.size(); ++i) object[name(i)] = counts[i];
  return object;
}

}  // namespace

std::string SummaryJson(const BaseStation& station, const BridgeRunInfo& run, const std::optional<ReplayFacts>& facts) {
  const StationCounts& counts = station.counts();
  const Rejections& rejections = station.rejections();
  nlohmann::json kinds = nlohmann::json::object();
  for (size_t i = 1; i < kFrameKinds; ++i) kinds[FrameKindName(i)] = counts.by_kind[i];
  nlohmann::json robots = nlohmann::json::array();
  for (size_t i = 0; i < station.robots().size(); ++i) {
    const HeardRobot& robot = station.robots()[i];
    nlohmann::json entry = {{"id", i},
                            {"heard", robot.heard},
                            {"beacons", robot.beacons},
                            {"epoch_starts", robot.epoch_starts},
                            {"cooperative_starts", robot.cooperative_starts}};
    if (robot.heard) {
      entry["last_heard_round"] = robot.last_heard_round;
      entry["rssi_dbm"] = robot.rssi_dbm;
      entry["joining"] = robot.joining;
      entry["epoch"] = robot.latest.epoch;
      entry["phase"] = wire::ToString(robot.latest.phase);
      entry["mode"] = wire::ToString(robot.epoch_mode);
      if (robot.has_hears) {
        nlohmann::json hears = nlohmann::json::array();
        for (uint16_t id : robot.hears) hears.push_back(id);
        entry["hears"] = hears;
      }
      if (robot.has_view) {
        nlohmann::json view = nlohmann::json::array();
        for (uint16_t id : robot.view) view.push_back(id);
        entry["view"] = view;
      }
      entry["x_mm"] = robot.latest.snapshot.x_mm;
      entry["y_mm"] = robot.latest.snapshot.y_mm;
    }
    robots.push_back(entry);
  }
  nlohmann::json document = {
      {"input", run.input},
      {"end", run.end},
      {"wall_s", run.wall_s},
      {"robots_configured", station.robots().size()},
      {"radio_round_ns", station.header().radio_round_ns},
      {"rounds", counts.rounds},
      {"bytes", counts.bytes},
      {"frames", counts.frames},
      {"frames_by_kind", kinds},
      {"beacons_accepted", counts.beacons},
      {"events", counts.events},
      {"rejected",
       {{"total", rejections.total()},
        {"frames", ReasonCounts(rejections.frames, LinkReasonName)},
        {"beacons", ReasonCounts(rejections.beacons, BeaconReasonName)},
        {"bytes_discarded", rejections.bytes_discarded}}},
      {"robots", robots},
      {"dds", {{"enabled", run.dds}, {"domain", run.dds_domain}, {"published", run.dds_published}, {"failed", run.dds_failed}}},
  };
  if (!run.replay_path.empty()) {
    nlohmann::json replay_entry = {{"path", run.replay_path}};
    if (facts) {
      replay_entry["read_back"] = facts->read;
      if (!facts->read) replay_entry["error"] = facts->error->ToString();
      replay_entry["rounds"] = facts->rounds;
      nlohmann::json per_robot = nlohmann::json::array();
      for (const RobotReplayFacts& robot : facts->robots) {
        per_robot.push_back({{"id", robot.id},
                             {"seen", robot.seen},
                             {"running_rounds", robot.running_rounds},
                             {"first_epoch", robot.first_epoch},
                             {"last_epoch", robot.last_epoch},
                             {"epoch_starts", robot.epoch_starts},
                             {"cooperative_starts", robot.cooperative_starts}});
      }
      replay_entry["robots"] = per_robot;
    }
    document["replay"] = replay_entry;
  }
  return document.dump(2) + "\n";
}

std::string SummaryText(const BaseStation& station, const BridgeRunInfo& run) {
  const StationCounts& counts = station.counts();
  const Rejections& rejections = station.rejections();
  std::string text;
  char line[256];
  std::snprintf(line, sizeof line, "syrof-bridge: %s, %.1f s, %u rounds (%s)\n", run.input.c_str(), run.wall_s,
                counts.rounds, run.end.c_str());
  text += line;
  std::snprintf(line, sizeof line, "  link        %llu bytes, %llu frames, %llu beacons accepted, %llu rejected\n",
                static_cast<unsigned long long>(counts.bytes), static_cast<unsigned long long>(counts.frames),
                static_cast<unsigned long long>(counts.beacons), static_cast<unsigned long long>(rejections.total()));
  text += line;
  for (size_t i = 0; i < station.robots().size(); ++i) {
    const HeardRobot& robot = station.robots()[i];
    if (!robot.heard) {
      std::snprintf(line, sizeof line, "  robot %-4zu  never heard\n", i);
      text += line;
      continue;
    }
    std::string hears;
    for (uint16_t id : robot.hears) hears += (hears.empty() ? "" : ",") + std::to_string(id);
    std::snprintf(line, sizeof line,
                  "  robot %-4zu  %llu beacons, last in round %u (%d dBm): epoch %u %s %s%s, %u epoch starts (%u "
                  "COOPERATIVE), hears ",
                  i, static_cast<unsigned long long>(robot.beacons), robot.last_heard_round, robot.rssi_dbm,
                  robot.latest.epoch, wire::ToString(robot.latest.phase), wire::ToString(robot.epoch_mode),
                  robot.joining ? " (joining)" : "", robot.epoch_starts, robot.cooperative_starts);
    text += line;
    text += robot.has_hears ? "{" + hears + "}\n" : "?\n";
  }
  for (size_t i = 1; i < kLinkErrors; ++i) {
    if (rejections.frames[i] == 0) continue;
    std::snprintf(line, sizeof line, "  rejected    frame %s: %llu\n", LinkReasonName(i),
                  static_cast<unsigned long long>(rejections.frames[i]));
    text += line;
  }
  for (size_t i = 1; i < kWireErrors; ++i) {
    if (rejections.beacons[i] == 0) continue;
    std::snprintf(line, sizeof line, "  rejected    beacon %s: %llu\n", BeaconReasonName(i),
                  static_cast<unsigned long long>(rejections.beacons[i]));
    text += line;
  }
  if (rejections.bytes_discarded > 0) {
    std::snprintf(line, sizeof line, "  discarded   %llu bytes outside frames\n",
                  static_cast<unsigned long long>(rejections.bytes_discarded));
    text += line;
  }
  if (run.dds) {
    std::snprintf(line, sizeof line, "  dds         domain %u: %llu beacons published, %llu refused\n", run.dds_domain,
                  static_cast<unsigned long long>(run.dds_published), static_cast<unsigned long long>(run.dds_failed));
    text += line;
  }
  if (!run.replay_path.empty()) text += "  replay      " + run.replay_path + "\n";
  return text;
}

}  // namespace syrof::bridge
