// gather: packs the swarm into a hexagonal packing (GatherSlots) around one
// centre that every robot agrees on and that stays put across epochs:
//   - the first COOPERATIVE epoch takes the centre of the
//     ShortestEnclosingCircle of the map;
//   - every robot then publishes that centre in its payload
//     (sendMessageData), and later epochs take the centre from the payload
//     of the member with the smallest id that carries one. Every COOPERATIVE
//     robot holds the same map, so all pick the same centre, and a robot that
//     joins later learns it from the map instead of computing a different one.
// Robots are assigned to slots by MinWeightedMatching in every epoch.
#include <array>
#include <cmath>

#include "target_matching.h"
#include "builtin_apps.h"
#include "formation_app.h"

namespace syrof::lab::apps {
namespace {

// Payload: the tag, then the centre's x and y in millimetres as
// little-endian int16 (5 of the 9 bytes).
constexpr uint8_t kCentreTag = 'G';
constexpr size_t kCentrePayloadBytes = 5;

class GatherApp final : public FormationApp {
 public:
  explicit GatherApp(const GatherParams& params) : FormationApp(params.margin_m), params_(params) {}
  const char* name() const override { return "gather"; }

 protected:
  bool PlanTargets(const syrof_ldmap& ldmap, std::span<const syrof_queries_member> members,
                   std::span<Position> targets) override {
    if (!FindPublishedCentre(ldmap) && !ComputeCentre(members)) return false;
    Publish();
    const std::vector<Position> slots = GatherSlots(
        {centre_x_mm_ / 1000.0, centre_y_mm_ / 1000.0}, members.size(), params_, arena(), body_radius_m());
    if (!AssignTargets(platform().queries_workspace(), members, slots, assignment_)) return false;
    for (size_t i = 0; i < members.size(); ++i) {
      const uint16_t slot = assignment_.target_of_member[i];
      if (slot != SYROF_QUERIES_NO_TARGET) targets[i] = slots[slot];
    }
    return true;
  }

  void HoldStill(const syrof_ldmap& /*ldmap*/) override {
    // Keep the centre in this robot's next snapshot, so the group still
    // finds it after AUTONOMOUS epochs.
    if (has_centre_) Publish();
  }

 private:
  bool FindPublishedCentre(const syrof_ldmap& ldmap) {
    for (size_t i = 0; i < ldmap.member_count; ++i) {
      const syrof_member_state& member = ldmap.members[i];
      if (member.payload_length != kCentrePayloadBytes || member.payload[0] != kCentreTag) continue;
      centre_x_mm_ = static_cast<int16_t>(member.payload[1] | (member.payload[2] << 8));
      centre_y_mm_ = static_cast<int16_t>(member.payload[3] | (member.payload[4] << 8));
      has_centre_ = true;
      return true;
    }
    return false;
  }

  bool ComputeCentre(std::span<const syrof_queries_member> members) {
    syrof_queries_circle circle{};
    if (syrof_queries_shortest_enclosing_circle(platform().queries_workspace(), members.data(), members.size(),
                                                &circle) != SYROF_QUERIES_OK) {
      return false;
    }
    // The centre lies within the members' bounding box, so it fits int16 mm.
    centre_x_mm_ = static_cast<int16_t>(std::lround(static_cast<double>(circle.centre_x_m) * 1000.0));
    centre_y_mm_ = static_cast<int16_t>(std::lround(static_cast<double>(circle.centre_y_m) * 1000.0));
    has_centre_ = true;
    return true;
  }

  void Publish() {
    const auto x = static_cast<uint16_t>(centre_x_mm_);
    const auto y = static_cast<uint16_t>(centre_y_mm_);
    const std::array<uint8_t, kCentrePayloadBytes> payload{kCentreTag, static_cast<uint8_t>(x & 0xFF),
                                                           static_cast<uint8_t>(x >> 8), static_cast<uint8_t>(y & 0xFF),
                                                           static_cast<uint8_t>(y >> 8)};
    // Five bytes are always within the limit; nothing to handle.
    (void)platform().SendMessageData(payload);
  }

  GatherParams params_;
  bool has_centre_ = false;
  int16_t centre_x_mm_ = 0;
  int16_t centre_y_mm_ = 0;
  TargetAssignment assignment_;
};

}  // namespace

std::unique_ptr<app::App> MakeGatherApp(const GatherParams& params) { return std::make_unique<GatherApp>(params); }

}  // namespace syrof::lab::apps
