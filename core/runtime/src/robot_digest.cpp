// Robot::AddToDigest (robot.h): what a search needs to tell two robots in
// the same state apart from two that only look alike. Kept apart from
// robot.cpp's steps; every field of Robot is named here or in the comment
// of what stays out.
#include <span>

#include <cstring>

#include "syrof/app/state_digest.h"
#include "syrof/runtime/robot.h"
#include "syrof/sync/state_digest.h"

namespace syrof::runtime {

// Out, on purpose: config_ (fixed for the run), the references and pointers
// (app_, radio_, receive_storage_ itself, observer_, port_, the tasks and
// the publishers and subscribers, whose queues are the broker's),
// counters_ and alignment_stats_ (read by reports only), and app_map_ (built
// from ldmap_ before each app call).
void Robot::AddToDigest(base::StateDigest& digest) const {
  const size_t swarm = config_.sync.swarm_size;
  sync::AddToDigest(digest, state_, swarm);
  digest.AddValue(out_.send);
  wire::AddToDigest(digest, out_.beacon);
  digest.AddValue(out_.epoch_started);
  wire::AddToDigest(digest, out_.removed);
  wire::AddToDigest(digest, out_.joined);
  digest.AddValue(out_.became_joiner);
  sync::AddToDigest(digest, ldmap_, swarm);
  estimator_.AddToDigest(digest);
  app::AddToDigest(digest, controller_.command());
  digest.AddValue(controller_.arrived());
  if (controller_.config().hold_position) {  // drones only: the others' digests stay as they were
    const motion::HoldPoint& hold = controller_.hold();  // field by field: padding
    digest.AddValue(hold.x_m);
    digest.AddValue(hold.y_m);
    digest.AddValue(hold.set);
  }
  digest.AddValue(estimate_);
  digest.AddValue(motion_estimate_);

  // Beacons that wait for a later step, by content (the pointers differ
  // from run to run), with their arrival times.
  auto add_beacons = [&digest](std::span<const wire::Beacon* const> beacons, std::span<const int64_t> arrivals) {
    digest.AddValue(beacons.size());
    for (size_t i = 0; i < beacons.size(); ++i) {
      wire::AddToDigest(digest, *beacons[i]);
      digest.AddValue(arrivals[i]);
    }
  };
  add_beacons(std::span(inbox_.data(), inbox_count_), std::span(inbox_arrival_ns_.data(), inbox_count_));
  add_beacons(std::span(deferred_.data(), deferred_count_), std::span(deferred_arrival_ns_.data(), deferred_count_));
  digest.AddValue(carried_count_);
  digest.AddValue(inbox_timed_);
  digest.AddValue(receiving_bank_);
  digest.AddValue(stored_count_);
  if (bank_size_ > 0 && stored_count_ <= bank_size_) {
    const size_t first = static_cast<size_t>(receiving_bank_) * bank_size_;
    for (size_t i = 0; i < stored_count_; ++i) wire::AddToDigest(digest, receive_storage_[first + i]);
    digest.AddRange(std::span<const int64_t>(received_arrival_ns_.data() + first, stored_count_));
  }
  digest.AddValue(round_task_id_);
  digest.AddValue(last_shift_ns_);
  digest.AddValue(last_alignment_.correction_ns);
  digest.AddValue(last_alignment_.median_error_ns);
  digest.AddValue(last_alignment_.samples);
  digest.AddValue(last_alignment_.spread_ns);
  digest.AddValue(last_alignment_.jumped);

  for (size_t i = 0; i < swarm; ++i) app::AddToDigest(digest, app_members_[i]);
  app::AddToDigest(digest, command_);
  app::AddToDigest(digest, handed_command_);
  digest.AddValue(command_handed_);
  safety_filter_.AddToDigest(digest);
  shared_reports_.AddToDigest(digest, swarm);
  motion_reports_.AddToDigest(digest, swarm);
  digest.AddValue(reports_changed_);
  digest.AddValue(relay_cursor_);
  digest.AddValue(intervention_count_);
  for (size_t i = 0; i < intervention_count_; ++i) {
    digest.AddValue(intervention_starts_[i].time_ns);
    digest.AddValue(intervention_starts_[i].other);
  }
  digest.AddValue(global_state_);
  digest.AddValue(payload_length_);
  digest.AddValue(payload_);
  digest.AddValue(maneuver_active_);
  if (config_.activation.model == sync::ActivationModel::kAsync) {
    digest.AddValue(async_tracker_.Packed());
    app::AddToDigest(digest, async_move_);
    digest.AddValue(async_last_move_epoch_);
    digest.AddValue(async_cut_pending_);
    digest.AddValue(async_cut_done_);
    digest.AddValue(async_covered_m_);
  }
  digest.AddValue(rounds_in_progress_);
  digest.AddValue(app_fault_.verdict());
  digest.AddBytes(std::as_bytes(std::span(app_fault_.detail(), std::strlen(app_fault_.detail()))));
  digest.AddValue(app_call_now_ns_);
  digest.AddValue(app_call_epoch_);
  digest.AddValue(start_ns_);
  digest.AddValue(started_);
  digest.AddValue(last_round_ns_);
}

}  // namespace syrof::runtime
