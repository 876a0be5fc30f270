// Mixed swarms (docs/grading.md, "Mixed swarms"): one swarm whose robots
// come from several submissions, robot i running submission i mod k, on
// every test of an assignment whose README fixes the robots' message format
// (`mixable: true`, with its `message:` format). Every payload each robot
// sets is checked against that format. The report says, per submission,
// which of its robots broke the message format, faulted, collided, or took
// part in the first disagreement of a COOPERATIVE epoch (the side whose
// robot departed from the epoch's first state is said to have disagreed
// first; two of one submission disagreeing pins it down), and names the
// sides that broke the format.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "syrof/assignment/assignment.h"
#include "syrof/assignment/score.h"
#include "syrof/grader/grade.h"

namespace syrof::grader {

/// One submission of the mix, already built.
struct MixEntry {
  std::string name;     ///< the submission's folder name
  std::string library;  ///< its app library
};

/// What one submission's robots did in one mixed run.
struct MixShare {
  std::vector<uint16_t> robots;     ///< the robots that ran it
  int faults = 0;                   ///< of those, robots whose app faulted
  std::string first_fault;          ///< "robot 2 in new_round at 3.50 s: crashed (SIGSEGV)"
  int collisions = 0;               ///< collisions one of its robots was in (of the listed ones)
  int invalid_commands = 0;         ///< only the first is attributed: 1 when it was one of its robots
  bool in_first_disagreement = false;  ///< the run's first disagreement names one of its robots (either side)
  bool disagreed_first = false;     ///< its robot is the one whose state departed from the epoch's first
  int format_violations = 0;        ///< payloads its robots set that broke the assignment's message format
  std::string first_format_violation;  ///< "robot 1 in init of epoch 0: 10 bytes, but the format has 2"
};

struct MixRun {
  std::string name;          ///< "<scenario>/seed-<seed>"
  std::string output_dir;    ///< relative to the mix's out dir (metrics.json, replay.bin, robots/)
  std::string run_error;
  assignment::RunScore score;  ///< the whole swarm's score with the rubric
  std::string disagreement;  ///< the first disagreement, with the submissions named; empty when none
  std::vector<MixShare> shares;  ///< one per MixEntry, in order
};

/// Runs every test of `assignment` (public only with options.public_only)
/// with the mixed swarm into `out_dir`/runs/, on options.jobs threads.
std::vector<MixRun> RunMix(const assignment::Assignment& assignment, const std::vector<MixEntry>& entries,
                           const std::string& out_dir, const GradeOptions& options);

/// The report: per run, each submission's robots and what they did.
void PrintMixReport(const std::vector<MixRun>& runs, const std::vector<MixEntry>& entries, std::ostream& out);

}  // namespace syrof::grader
