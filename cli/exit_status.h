#pragma once

// The exit statuses the syrof subcommands return (and main passes on), one
// definition for every command: 0 done, 1 something failed inside syrof
// (a file it could not write, an unexpected exception), 2 bad input (a file
// or argument the user can fix; the message names it).

namespace syrof::cli {

inline constexpr int kOk = 0;
inline constexpr int kInternalError = 1;
inline constexpr int kBadInput = 2;

}  // namespace syrof::cli
