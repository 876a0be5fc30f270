#include "syrof/lab/replay/epoch_table.h"

#include <algorithm>

namespace syrof::lab::replay {

EpochTableBuilder::EpochTableBuilder(const Header& header, uint16_t version, size_t max_cells)
    : max_rows_(header.robots.empty() ? max_cells : max_cells / header.robots.size()) {
  table_.robot_ids.reserve(header.robots.size());
  for (const RobotInfo& robot : header.robots) table_.robot_ids.push_back(robot.id);
  table_.has_maps = version >= 3;
}

int64_t EpochTableBuilder::Unwrap(uint16_t wire_epoch) {
  if (!any_epoch_) {
    any_epoch_ = true;
    last_epoch_ = wire_epoch;
    return last_epoch_;
  }
  // The serial difference to the last start, in -32768 .. 32767: robots'
  // epochs are never that far apart.
  const auto difference = static_cast<int16_t>(static_cast<uint16_t>(wire_epoch - static_cast<uint16_t>(last_epoch_)));
  last_epoch_ += difference;
  return last_epoch_;
}

EpochStart* EpochTableBuilder::Entry(int64_t number, uint16_t robot) {
  const auto id = std::lower_bound(table_.robot_ids.begin(), table_.robot_ids.end(), robot);
  if (id == table_.robot_ids.end() || *id != robot) return nullptr;
  const auto slot = static_cast<size_t>(id - table_.robot_ids.begin());
  // Starts come mostly in increasing epoch order: the row is usually the
  // last one, or a new one after it.
  auto row = std::lower_bound(table_.epochs.begin(), table_.epochs.end(), number,
                              [](const EpochRow& candidate, int64_t value) { return candidate.number < value; });
  if (row == table_.epochs.end() || row->number != number) {
    if (table_.epochs.size() >= max_rows_) {
      full_ = true;
      return nullptr;
    }
    row = table_.epochs.insert(row, EpochRow{.number = number, .robots = std::vector<EpochStart>(table_.robot_ids.size())});
  }
  return &row->robots[slot];
}

EpochTableBuilder::MapContents EpochTableBuilder::ContentsOf(const std::shared_ptr<const EpochMap>& map) {
  if (const auto cached = contents_cache_.find(map.get()); cached != contents_cache_.end()) return cached->second.second;
  if (contents_cache_.size() > table_.robot_ids.size()) contents_cache_.clear();
  auto members = std::make_shared<MemberIds>();
  auto payloads = std::make_shared<MemberPayloads>();
  members->reserve(map->members.size());
  payloads->reserve(map->members.size());
  for (const MapMember& member : map->members) {
    members->push_back(member.id);
    payloads->push_back(member.payload);
  }
  MapContents contents{.members = std::move(members), .payloads = std::move(payloads)};
  contents_cache_.emplace(map.get(), std::make_pair(map, contents));
  return contents;
}

bool EpochTableBuilder::Add(const Round& round) {
  if (full_) return false;
  if (table_.round_count == 0) table_.first_round = round.index;
  table_.last_round = round.index;
  ++table_.round_count;
  for (const Event& event : round.events) {
    if (event.kind != EventKind::kEpochStart) continue;
    EpochStart* start = Entry(Unwrap(event.epoch), event.robot);
    if (start == nullptr) continue;
    if (start->start_count++ == 0) {
      start->round = round.index;
      start->mode = event.mode;
    }
  }
  for (const RobotMap& entry : round.maps) {
    if (entry.map == nullptr) continue;
    EpochStart* start = Entry(Unwrap(entry.map->epoch), entry.robot);
    if (start == nullptr) continue;
    if (start->start_count == 0) {  // a map without its event
      start->start_count = 1;
      start->round = round.index;
      start->mode = entry.map->mode;
    }
    // The map of the first start only: a second start of the same epoch
    // (start_count > 1) already has the first's members.
    if (start->members == nullptr && start->round == round.index) {
      MapContents contents = ContentsOf(entry.map);
      start->members = std::move(contents.members);
      start->payloads = std::move(contents.payloads);
    }
  }
  return !full_;
}

EpochTable EpochTableBuilder::Finish() && {
  contents_cache_.clear();
  return std::move(table_);
}

EpochTable BuildEpochTable(const Header& header, uint16_t version, std::span<const Round> rounds) {
  EpochTableBuilder builder(header, version);
  for (const Round& round : rounds) {
    if (!builder.Add(round)) break;
  }
  return std::move(builder).Finish();
}

}  // namespace syrof::lab::replay
