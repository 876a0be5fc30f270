#include "text_checks.h"

#include <cstdint>
#include <cstdio>

namespace syrof::lab::scenario {
namespace {

// 1-based line and column of a byte offset; columns count characters (UTF-8
// continuation bytes do not advance them), as yaml-cpp's marks do.
void Position(const std::string& text, size_t offset, int& line, int& column) {
  line = 1;
  column = 1;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte == '\n') {
      ++line;
      column = 1;
    } else if ((byte & 0xC0) != 0x80) {
      ++column;
    }
  }
}

bool FailAt(const std::string& text, size_t offset, Diagnostics& diagnostics, std::string message) {
  int line = 0;
  int column = 0;
  Position(text, offset, line, column);
  return diagnostics.Fail(line, column, std::move(message));
}

std::string Hex(unsigned char byte) {
  char buffer[8];
  std::snprintf(buffer, sizeof buffer, "0x%02x", byte);
  return buffer;
}

// Length of the UTF-8 sequence starting at `offset`, or 0 when it is not
// well-formed (overlong forms, surrogates and values above U+10FFFF included).
size_t Utf8Length(const std::string& text, size_t offset) {
  const auto lead = static_cast<unsigned char>(text[offset]);
  if (lead < 0x80) return 1;
  size_t length = 0;
  uint32_t value = 0;
  if ((lead & 0xE0) == 0xC0) {
    length = 2;
    value = lead & 0x1F;
  } else if ((lead & 0xF0) == 0xE0) {
    length = 3;
    value = lead & 0x0F;
  } else if ((lead & 0xF8) == 0xF0) {
    length = 4;
    value = lead & 0x07;
  } else {
    return 0;
  }
  if (offset + length > text.size()) return 0;
  for (size_t i = 1; i < length; ++i) {
    const auto byte = static_cast<unsigned char>(text[offset + i]);
    if ((byte & 0xC0) != 0x80) return 0;
    value = (value << 6) | (byte & 0x3F);
  }
  static constexpr uint32_t kSmallest[] = {0, 0, 0x80, 0x800, 0x10000};
  if (value < kSmallest[length] || value > 0x10FFFF || (value >= 0xD800 && value <= 0xDFFF)) return 0;
  return length;
}

bool CheckCharacters(const std::string& text, Diagnostics& diagnostics) {
  for (size_t i = 0; i < text.size();) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte < 0x20 && byte != '\t' && byte != '\n' && byte != '\r') {
      return FailAt(text, i, diagnostics, "control character " + Hex(byte) + ": a scenario is UTF-8 text");
    }
    if (byte == 0x7F) return FailAt(text, i, diagnostics, "control character 0x7f: a scenario is UTF-8 text");
    const size_t length = Utf8Length(text, i);
    if (length == 0) return FailAt(text, i, diagnostics, "byte " + Hex(byte) + " is not UTF-8: a scenario is UTF-8 text");
    i += length;
  }
  return true;
}

bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\r'; }
bool IsBlankOrBreak(char c) { return IsBlank(c) || c == '\n'; }

// One line of the text: [begin, end), end at the '\n' or the text's end.
struct Line {
  size_t begin;
  size_t end;
};

template <typename Visit>
void ForEachLine(const std::string& text, Visit visit) {
  size_t begin = 0;
  while (begin <= text.size()) {
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    if (!visit(Line{begin, end})) return;
    if (end == text.size()) return;
    begin = end + 1;
  }
}

bool CheckIndentation(const std::string& text, Diagnostics& diagnostics) {
  bool ok = true;
  ForEachLine(text, [&](Line line) {
    size_t i = line.begin;
    while (i < line.end && IsBlank(text[i])) ++i;
    if (i == line.end) return true;  // blank line: tabs do no harm
    const size_t tab = text.find('\t', line.begin);
    if (tab < i) {
      ok = FailAt(text, tab, diagnostics, "tab in indentation: YAML indents with spaces");
      return false;
    }
    return true;
  });
  return ok;
}

// "---" or "..." at the start of a line, followed by a blank or the line's end.
bool IsMarker(const std::string& text, Line line, const char* marker) {
  if (line.end - line.begin < 3 || text.compare(line.begin, 3, marker) != 0) return false;
  return line.end - line.begin == 3 || IsBlank(text[line.begin + 3]);
}

// True when [from, end) holds something other than blanks and a comment.
bool HasContent(const std::string& text, size_t from, size_t end) {
  size_t i = from;
  while (i < end && IsBlank(text[i])) ++i;
  return i < end && text[i] != '#';
}

bool CheckSingleDocument(const std::string& text, Diagnostics& diagnostics) {
  bool ok = true;
  bool content_seen = false;
  bool ended = false;
  ForEachLine(text, [&](Line line) {
    if (IsMarker(text, line, "---")) {
      if (content_seen || ended) {
        ok = FailAt(text, line.begin, diagnostics,
                    "a second YAML document starts here: a scenario file holds one document");
        return false;
      }
      content_seen = HasContent(text, line.begin + 3, line.end);
      return true;
    }
    if (IsMarker(text, line, "...")) {
      ended = content_seen || ended;
      if (HasContent(text, line.begin + 3, line.end)) {
        ok = FailAt(text, line.begin, diagnostics, "content after the end of the document ('...')");
        return false;
      }
      return true;
    }
    // Directives ("%YAML 1.2") belong to the document that follows.
    if (!content_seen && !ended && line.end > line.begin && text[line.begin] == '%') return true;
    if (HasContent(text, line.begin, line.end)) {
      if (ended) {
        ok = FailAt(text, line.begin, diagnostics,
                    "content after the end of the document ('...'): a scenario file holds one document");
        return false;
      }
      content_seen = true;
    }
    return true;
  });
  return ok;
}

size_t LineStart(const std::string& text, size_t offset) {
  const size_t newline = offset == 0 ? std::string::npos : text.rfind('\n', offset - 1);
  return newline == std::string::npos ? 0 : newline + 1;
}

size_t Indentation(const std::string& text, size_t line_start) {
  size_t i = line_start;
  while (i < text.size() && text[i] == ' ') ++i;
  return i - line_start;
}

bool IsFlowIndicator(char c) { return c == ',' || c == '[' || c == ']' || c == '{' || c == '}'; }

}  // namespace

int FlowDepth(const std::string& text, int limit, size_t& offset) {
  int depth = 0;
  int deepest = 0;
  size_t i = 0;
  const size_t size = text.size();
  auto next_is_separator = [&](size_t at) {
    return at + 1 >= size || IsBlankOrBreak(text[at + 1]) || (depth > 0 && IsFlowIndicator(text[at + 1]));
  };
  // The scan sits at the start of a token throughout the loop; each branch
  // consumes one token (or a comment, or blanks).
  while (i < size) {
    const char c = text[i];
    if (IsBlankOrBreak(c)) {
      ++i;
    } else if (c == '#') {
      while (i < size && text[i] != '\n') ++i;
    } else if (c == '[' || c == '{') {
      ++depth;
      if (depth > deepest) deepest = depth;
      if (depth > limit) {
        offset = i;
        return depth;
      }
      ++i;
    } else if (c == ']' || c == '}') {
      if (depth > 0) --depth;
      ++i;
    } else if (c == ',') {
      ++i;
    } else if (c == '"') {
      for (++i; i < size && text[i] != '"'; ++i) {
        if (text[i] == '\\') ++i;
      }
      ++i;
    } else if (c == '\'') {
      // A doubled quote inside closes and reopens: the same bytes skipped.
      for (++i; i < size && text[i] != '\''; ++i) {
      }
      ++i;
    } else if ((c == '|' || c == '>') && depth == 0) {
      // A block scalar: its lines are those indented more than the line of
      // its header (or blank); brackets in them are text.
      const size_t header_indent = Indentation(text, LineStart(text, i));
      i = text.find('\n', i);
      while (i != std::string::npos && i < size) {
        const size_t line = i + 1;
        size_t first = line;
        while (first < size && text[first] == ' ') ++first;
        const bool blank = first >= size || text[first] == '\n' || text[first] == '\r';
        if (!blank && first - line <= header_indent) break;
        i = text.find('\n', line);
      }
      if (i == std::string::npos) i = size;
    } else if ((c == '-' || c == '?' || c == ':') && next_is_separator(i)) {
      ++i;  // an indicator, not the start of a plain scalar
    } else {
      // A plain scalar: it ends at a line break (in block context), at
      // ": " or " #", and in flow context at ",[]{}" (yaml-cpp also ends it
      // at '?' there). Its first character is always part of it.
      ++i;
      while (i < size) {
        const char d = text[i];
        if (d == '\n' && depth == 0) break;
        if (d == ':' && next_is_separator(i)) break;
        if (IsBlankOrBreak(d) && i + 1 < size && text[i + 1] == '#') break;
        if (depth > 0 && (IsFlowIndicator(d) || d == '?')) break;
        ++i;
      }
    }
  }
  return deepest;
}

bool CheckScenarioText(const std::string& text, Diagnostics& diagnostics, size_t max_bytes) {
  if (text.size() > max_bytes) {
    return diagnostics.Fail(0, 0, "the scenario is " + std::to_string(text.size()) + " bytes; the limit is " +
                                      std::to_string(max_bytes) + " bytes");
  }
  if (!CheckCharacters(text, diagnostics)) return false;
  if (!CheckIndentation(text, diagnostics)) return false;
  if (!CheckSingleDocument(text, diagnostics)) return false;
  size_t offset = 0;
  if (FlowDepth(text, kMaxScenarioDepth, offset) > kMaxScenarioDepth) {
    return FailAt(text, offset, diagnostics,
                  "'[' and '{' nest more than " + std::to_string(kMaxScenarioDepth) + " deep");
  }
  return true;
}

}  // namespace syrof::lab::scenario
