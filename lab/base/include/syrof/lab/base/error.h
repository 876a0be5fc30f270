// lab's one error value (docs/style.md): what went wrong and where, for every
// failure that comes from outside the program (a file, text, a spec built
// from input, later a child process). It is returned by value, never
// thrown; caller mistakes and broken invariants stop the program through
// SYROF_CHECK instead.
#pragma once

#include <ostream>
#include <string>

namespace syrof::lab {

struct Error {
  /// Where: a file's path, "<string>", or the part of the input at fault
  /// ("body 3", "link 0 -> 9", "offset 1204").
  std::string where;
  /// 1-based place in a text; 0 when the error is not at one place (an
  /// override, an I/O failure, a binary file).
  int line = 0;
  int column = 0;
  /// What is wrong, in words, with the value found: "unknown key 'robtos'
  /// (did you mean 'robots'?)".
  std::string message;

  /// "where:line:column: message", "where: message" without a place, or the
  /// message alone without a where.
  std::string ToString() const {
    if (where.empty()) return message;
    if (line <= 0) return where + ": " + message;
    return where + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + message;
  }

  friend bool operator==(const Error&, const Error&) = default;
  friend std::ostream& operator<<(std::ostream& out, const Error& error) { return out << error.ToString(); }
};

}  // namespace syrof::lab
