// What the reports' tests share: a graded submission built by hand (the one
// docs/grading.md shows), and a small XML reader that refuses what is not
// well-formed, so the JUnit test needs no XML library.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "syrof/assignment/result.h"

namespace syrof::grader::report::testing {

using assignment::CriterionScore;
using assignment::SubmissionResult;
using assignment::TestResult;
using assignment::Visibility;

/// Alice's gather submission: two public runs (one passed, one lost half
/// the goal) and two hidden runs (one over its time limit, one passed).
inline SubmissionResult ExampleResult() {
  SubmissionResult result;
  result.submission = "alice";
  result.assignment = "gather";
  result.title = "Gather the swarm";
  result.build.verdict = assignment::BuildVerdict::kOk;
  result.build.log_path = "build.log";
  result.build.library_path = "/tmp/grade/alice/build/libgather.so";
  result.build.wall_seconds = 3.5;
  result.max_points = 100;

  const std::vector<CriterionScore> clean = {
      {"goal", 50, 50, "2 of 2 checks passed"},
      {"collisions", 20, 20, "no collision and no wall contact"},
      {"agreement", 30, 30, "the robots' global states agreed in 40 of 40 COOPERATIVE epochs"}};

  TestResult passed;
  passed.name = "gather_6/seed-1";
  passed.scenario = "gather_6";
  passed.seed = 1;
  passed.score = {clean, 100, 100};
  passed.max_points = 25;
  passed.points = 25;
  passed.passed = true;
  passed.replay_command =
      "syrof run gather/scenarios/gather_6.yaml --app build/libgather.so "
      "--seed 1 --out rerun/gather_6-seed-1";
  passed.output_dir = "runs/gather_6/seed-1";
  passed.wall_seconds = 1.25;
  result.tests.push_back(passed);

  TestResult half = passed;
  half.name = "gather_6/seed-2";
  half.seed = 2;
  half.score.criteria[0] = {"goal", 25, 50,
                            "1 of 2 checks passed; gathered: robot 3 is 0.900 m from (1.000, 1.000); the limit is "
                            "0.500 m"};
  half.score.points = 75;
  half.max_points = 25;
  half.points = 18.75;
  half.passed = false;
  half.replay_command =
      "syrof run gather/scenarios/gather_6.yaml --app build/libgather.so "
      "--seed 2 --out rerun/gather_6-seed-2";
  half.output_dir = "runs/gather_6/seed-2";
  half.replay_path = "runs/gather_6/seed-2/replay";
  half.wall_seconds = 1.5;
  result.tests.push_back(half);

  TestResult timeout;
  timeout.name = "crash10/seed-101";
  timeout.scenario = "crash10";
  timeout.seed = 101;
  timeout.visibility = Visibility::kHidden;
  timeout.max_points = 25;
  timeout.run_error = "time limit of 120 s reached";
  timeout.replay_command =
      "syrof run gather/hidden/gather_10_crash.yaml --app build/libgather.so "
      "--seed 101 --out rerun/crash10-seed-101";
  timeout.output_dir = "runs/crash10/seed-101";
  timeout.wall_seconds = 120.2;
  result.tests.push_back(timeout);

  TestResult hidden_passed = passed;
  hidden_passed.name = "crash10/seed-102";
  hidden_passed.scenario = "crash10";
  hidden_passed.seed = 102;
  hidden_passed.visibility = Visibility::kHidden;
  hidden_passed.replay_command =
      "syrof run gather/hidden/gather_10_crash.yaml --app build/libgather.so "
      "--seed 102 --out rerun/crash10-seed-102";
  hidden_passed.output_dir = "runs/crash10/seed-102";
  hidden_passed.wall_seconds = 2.0;
  result.tests.push_back(hidden_passed);

  result.points = 68.75;
  result.tests_passed = 2;
  return result;
}

/// One element of a parsed XML document.
struct XmlElement {
  std::string name;
  std::map<std::string, std::string> attributes;  ///< values with references resolved
  std::string text;                               ///< the element's own text, references resolved
  std::vector<XmlElement> children;

  /// The first child named `child`, or nullptr.
  const XmlElement* Child(std::string_view child) const {
    for (const XmlElement& element : children) {
      if (element.name == child) return &element;
    }
    return nullptr;
  }
};

/// A reader for the XML JUnit reports use: an optional <?xml ...?>
/// declaration, elements, attributes in quotes, text, and character and the
/// five predefined entity references. Anything else, or anything not
/// well-formed (a stray < or &, an unknown reference, a mismatched or
/// unclosed tag, a repeated attribute, a control character, bytes that are
/// not UTF-8), is an error naming the byte offset.
class XmlReader {
 public:
  explicit XmlReader(std::string_view text) : text_(text) {}

  std::optional<XmlElement> Document() {
    if (!ValidUtf8()) return std::nullopt;
    if (text_.substr(0, 5) == "<?xml") {
      const size_t end = text_.find("?>");
      if (end == std::string_view::npos) return Fail("the declaration is not closed");
      at_ = end + 2;
    }
    SkipSpace();
    std::optional<XmlElement> root = Element();
    if (!root) return std::nullopt;
    SkipSpace();
    if (at_ != text_.size()) return Fail("text after the root element");
    return root;
  }

  const std::string& error() const { return error_; }

 private:
  std::nullopt_t Fail(const std::string& what) {
    if (error_.empty()) error_ = "offset " + std::to_string(at_) + ": " + what;
    return std::nullopt;
  }
  bool Refuse(const std::string& what) {
    Fail(what);
    return false;
  }
  bool More() const { return at_ < text_.size(); }
  void SkipSpace() {
    while (More() && (text_[at_] == ' ' || text_[at_] == '\n' || text_[at_] == '\t' || text_[at_] == '\r')) ++at_;
  }
  static bool NameStart(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_' || c == ':'; }
  static bool NameChar(char c) { return NameStart(c) || (c >= '0' && c <= '9') || c == '-' || c == '.'; }

  bool ValidUtf8() {
    for (size_t i = 0; i < text_.size();) {
      const auto lead = static_cast<uint8_t>(text_[i]);
      const size_t length = lead < 0x80 ? 1 : (lead & 0xE0) == 0xC0 ? 2 : (lead & 0xF0) == 0xE0 ? 3
                                              : (lead & 0xF8) == 0xF0 ? 4 : 0;
      at_ = i;
      if (length == 0 || i + length > text_.size()) return Refuse("not UTF-8");
      for (size_t k = 1; k < length; ++k) {
        if ((static_cast<uint8_t>(text_[i + k]) & 0xC0) != 0x80) return Refuse("not UTF-8");
      }
      if (length == 1 && lead < 0x20 && lead != '\t' && lead != '\n' && lead != '\r') {
        return Refuse("a control character");
      }
      i += length;
    }
    at_ = 0;
    return true;
  }

  std::optional<std::string> Name() {
    if (!More() || !NameStart(text_[at_])) return Fail("a name was expected");
    const size_t start = at_;
    while (More() && NameChar(text_[at_])) ++at_;
    return std::string(text_.substr(start, at_ - start));
  }

  static void AppendUtf8(std::string& out, uint32_t code) {
    if (code < 0x80) {
      out += static_cast<char>(code);
    } else if (code < 0x800) {
      out += static_cast<char>(0xC0 | (code >> 6));
      out += static_cast<char>(0x80 | (code & 0x3F));
    } else if (code < 0x10000) {
      out += static_cast<char>(0xE0 | (code >> 12));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (code & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (code >> 18));
      out += static_cast<char>(0x80 | ((code >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (code & 0x3F));
    }
  }

  // At '&': appends what the reference stands for; false (and the error
  // set) when it is not a reference XML knows.
  bool Reference(std::string& out) {
    const size_t end = text_.find(';', at_);
    if (end == std::string_view::npos || end - at_ > 12) return Refuse("'&' starts no reference");
    const std::string_view name = text_.substr(at_ + 1, end - at_ - 1);
    static const std::map<std::string_view, char> kEntities = {
        {"lt", '<'}, {"gt", '>'}, {"amp", '&'}, {"quot", '"'}, {"apos", '\''}};
    if (const auto entity = kEntities.find(name); entity != kEntities.end()) {
      out += entity->second;
    } else if (name.size() > 1 && name[0] == '#') {
      const bool hex = name[1] == 'x';
      const std::string digits(name.substr(hex ? 2 : 1));
      if (digits.empty() || digits.size() > 7 ||
          digits.find_first_not_of(hex ? "0123456789abcdefABCDEF" : "0123456789") != std::string::npos) {
        return Refuse("a bad character reference");
      }
      const auto code = static_cast<uint32_t>(std::stoul(digits, nullptr, hex ? 16 : 10));
      const bool allowed = code == 0x9 || code == 0xA || code == 0xD || (code >= 0x20 && code <= 0xD7FF) ||
                           (code >= 0xE000 && code <= 0xFFFD) || (code >= 0x10000 && code <= 0x10FFFF);
      if (!allowed) return Refuse("a reference to a character XML forbids");
      AppendUtf8(out, code);
    } else {
      return Refuse("an unknown entity '" + std::string(name) + "'");
    }
    at_ = end + 1;
    return true;
  }

  std::optional<XmlElement> Element() {
    if (!More() || text_[at_] != '<') return Fail("'<' was expected");
    ++at_;
    XmlElement element;
    std::optional<std::string> name = Name();
    if (!name) return std::nullopt;
    element.name = *name;
    for (;;) {
      const size_t before = at_;
      SkipSpace();
      if (!More()) return Fail("the tag is not closed");
      if (text_.substr(at_, 2) == "/>") {
        at_ += 2;
        return element;
      }
      if (text_[at_] == '>') {
        ++at_;
        break;
      }
      if (at_ == before) return Fail("space was expected before an attribute");
      std::optional<std::string> attribute = Name();
      if (!attribute) return std::nullopt;
      SkipSpace();
      if (!More() || text_[at_] != '=') return Fail("'=' was expected");
      ++at_;
      SkipSpace();
      if (!More() || (text_[at_] != '"' && text_[at_] != '\'')) return Fail("a quoted value was expected");
      const char quote = text_[at_++];
      std::string value;
      while (More() && text_[at_] != quote) {
        if (text_[at_] == '<') return Fail("'<' in an attribute value");
        if (text_[at_] == '&') {
          if (!Reference(value)) return std::nullopt;
        } else {
          value += text_[at_++];
        }
      }
      if (!More()) return Fail("the attribute value is not closed");
      ++at_;
      if (!element.attributes.emplace(*attribute, value).second) return Fail("attribute repeated: " + *attribute);
    }
    for (;;) {
      if (!More()) return Fail("<" + element.name + "> is not closed");
      if (text_.substr(at_, 2) == "</") {
        at_ += 2;
        std::optional<std::string> end = Name();
        if (!end) return std::nullopt;
        if (*end != element.name) return Fail("</" + *end + "> closes <" + element.name + ">");
        SkipSpace();
        if (!More() || text_[at_] != '>') return Fail("'>' was expected");
        ++at_;
        return element;
      }
      if (text_[at_] == '<') {
        std::optional<XmlElement> child = Element();
        if (!child) return std::nullopt;
        element.children.push_back(std::move(*child));
      } else if (text_[at_] == '&') {
        if (!Reference(element.text)) return std::nullopt;
      } else {
        element.text += text_[at_++];
      }
    }
  }

  std::string_view text_;
  size_t at_ = 0;
  std::string error_;
};

}  // namespace syrof::grader::report::testing
