#pragma once

// The exit statuses the syrof subcommands return (and main passes on), one
// definition for every command: 0 done, 1 something failed inside syrof
// (a file it could not write, an unexpected exception), 2 bad input (a file
// or argument the user can fix; the message names it).
//
// `syrof compare` answers a question, as diff(1) and cmp(1) do: 0 the runs
// agree, 1 they differ (kRunsDiffer), 2 trouble: bad input, or an internal
// error (the message says which), so that 1 from it always means "differ".
// `syrof assignment check` likewise: 0 every subject got what it must, 1 one
// did not (kNotAsExpected; the table says which; also when grading failed
// inside syrof, which the table says too), 2 bad input.

namespace syrof::cli {

inline constexpr int kOk = 0;
inline constexpr int kInternalError = 1;
inline constexpr int kBadInput = 2;
inline constexpr int kRunsDiffer = 1;  ///< syrof compare only
inline constexpr int kNotAsExpected = 1;  ///< syrof assignment check only

}  // namespace syrof::cli
