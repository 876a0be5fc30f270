// What `syrof grade` prints for one submission: a header a student reads
// first ("Tests passed 17/20, Points 85.00/100"), then one line per test
// (name, points/max, PASS or FAIL, why it lost points) and, under a failed
// public test, the command that replays it. docs/grading.md shows an example.
#pragma once

#include <ostream>
#include <string>

#include "syrof/assignment/result.h"

namespace syrof::grader {

/// Why `test` lost points, in one line: its run_error, or the first
/// criterion below full points ("collisions: 2 collisions ..."); empty when
/// it passed.
std::string FirstLoss(const assignment::TestResult& test);

/// Prints `result`'s table. `out_dir` is where its files are (shown for the
/// build log and replays).
void PrintSubmissionTable(const assignment::SubmissionResult& result, const std::string& out_dir, std::ostream& out);

}  // namespace syrof::grader
