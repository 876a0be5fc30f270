// report.html (docs/grading.md, "report.html"): one page, with no script of
// its own, in the student's form (a hidden test only as a row of its name,
// set, points and verdict) or the instructor's full form. Each failing run's viewer page is a file
// beside the run's replay, shown here in an <iframe> by relative path; the
// page's Content-Security-Policy lets it load nothing but those frames.
#include <fmt/format.h>

#include <filesystem>

#include "syrof/report/reports.h"
#include "text.h"

namespace syrof::grader::report {
namespace {

using text::Markup;

std::string Html(std::string_view value) { return text::Escape(value, Markup::kHtml); }

// A relative path as a URL path: each byte outside RFC 3986's unreserved
// set percent-encoded, '/' kept.
std::string UrlPath(std::string_view path) {
  std::string url;
  for (const char c : path) {
    const auto byte = static_cast<unsigned char>(c);
    if ((byte >= 'A' && byte <= 'Z') || (byte >= 'a' && byte <= 'z') || (byte >= '0' && byte <= '9') || c == '-' ||
        c == '.' || c == '_' || c == '~' || c == '/') {
      url += c;
    } else {
      url += fmt::format("%{:02X}", byte);
    }
  }
  return url;
}

constexpr const char* kStyle = R"css(
:root { --ink: #1d2330; --muted: #667085; --line: #d9dde5; --ok: #1f7a3a; --ok-bg: #e8f5ec;
  --bad: #9b1c1c; --bad-bg: #fdecec; --part: #8a4b00; --part-bg: #fff4e0; }
* { box-sizing: border-box; }
body { margin: 0 auto; max-width: 1320px; padding: 16px 20px 40px; color: var(--ink); background: #f4f5f7;
  font: 14px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, "DejaVu Sans", sans-serif; }
h1 { margin: 0 0 2px; font-size: 24px; }
h2 { margin: 28px 0 8px; font-size: 17px; }
code { font: 12.5px/1.4 ui-monospace, "DejaVu Sans Mono", monospace; }
.what { margin: 0; color: var(--muted); }
#score { display: inline-block; margin: 12px 0 0; padding: 10px 16px; border-radius: 8px; font-size: 20px; }
#score.full { background: var(--ok-bg); color: var(--ok); }
#score.partial { background: var(--part-bg); color: var(--part); }
#score.none { background: var(--bad-bg); color: var(--bad); }
.box { background: #fff; border: 1px solid var(--line); border-radius: 8px; padding: 10px 14px; }
.bad { color: var(--bad); }
.ok { color: var(--ok); }
table { width: 100%; border-collapse: collapse; background: #fff; border: 1px solid var(--line); }
th, td { padding: 6px 8px; border-bottom: 1px solid var(--line); text-align: left; vertical-align: top; }
th { background: #eef0f4; font-weight: 600; }
td.points { white-space: nowrap; font-variant-numeric: tabular-nums; }
tr.failed td.result { color: var(--bad); font-weight: 600; }
tr.passed td.result { color: var(--ok); font-weight: 600; }
ul.criteria { margin: 0; padding-left: 18px; }
ul.criteria li.lost { color: var(--bad); }
.replay { margin: 4px 0 0; color: var(--muted); }
details.run { margin: 10px 0; background: #fff; border: 1px solid var(--line); border-radius: 8px; }
details.run summary { padding: 8px 12px; cursor: pointer; }
details.run .links { margin: 0 12px 6px; }
details.run .note { margin: 0 12px 8px; color: var(--part); }
.hidden-note { margin: 0; color: var(--muted); }
iframe.viewer { display: block; width: 100%; height: 980px; border: 0; border-top: 1px solid var(--line); }
footer { margin-top: 30px; color: var(--muted); font-size: 12px; }
)css";

std::string ScoreClass(const SubmissionResult& result) {
  if (text::Points(result.points) == text::Points(result.max_points)) return "full";
  return text::Points(result.points) == "0" ? "none" : "partial";
}

// The anchor of a failing run's viewer.
std::string RunAnchor(size_t index) { return fmt::format("run-{}", index + 1); }

// A failing run with a replay that the form shows whole gets a place for
// its viewer (or for why there is none).
bool HasViewer(const TestResult& test, ReportForm form) {
  return !test.passed && !test.replay_path.empty() && ShowsWhole(test, form);
}

std::string TestRow(const SubmissionResult& result, const TestResult& test, size_t index, ReportForm form) {
  std::string criteria;
  if (!ShowsWhole(test, form)) {
    criteria = "<p class=\"hidden-note\">A hidden test: its details are kept from this page.</p>";
  } else if (!result.build.ok()) {
    criteria = "<p class=\"bad\">not run: the submission did not build</p>";
  } else {
    criteria += "<ul class=\"criteria\">";
    if (!test.run_error.empty()) {
      criteria += "<li class=\"lost\">" + Html("the run has no score: " + test.run_error) + "</li>";
    }
    for (const assignment::CriterionScore& criterion : test.score.criteria) {
      criteria += fmt::format("<li{}>{}</li>", text::Lost(criterion) ? " class=\"lost\"" : "",
                              Html(text::CriterionLine(criterion)));
    }
    if (!test.message_format.empty()) {
      criteria += "<li class=\"lost\">" + Html("message format: " + test.message_format) + "</li>";
    }
    criteria += "</ul>";
  }
  if (test.visibility == assignment::Visibility::kPublic && !test.replay_command.empty() && ShowsWhole(test, form)) {
    criteria += "<p class=\"replay\">Replay: <code>" + Html(test.replay_command) + "</code></p>";
  }
  const bool passed = test.passed && result.build.ok();
  std::string verdict = passed ? "passed" : "failed";
  if (HasViewer(test, form)) verdict = fmt::format("<a href=\"#{}\">failed: see its run</a>", RunAnchor(index));
  return fmt::format(
      "<tr id=\"test-{}\" class=\"{}\"><td><code>{}</code></td><td>{}</td><td class=\"points\">{}/{}</td>"
      "<td class=\"result\">{}</td><td>{}</td></tr>\n",
      index + 1, passed ? "passed" : "failed", Html(test.name), text::SetName(test), text::Points(test.points),
      text::Points(test.max_points), verdict, criteria);
}

std::string RunViewer(const SubmissionResult& result, const TestResult& test, size_t index, bool first,
                      const std::map<std::string, ReplayPageNote>& notes) {
  const std::string page = ReplayPagePath(test);
  const auto note = notes.find(test.name);
  const bool written = !page.empty() && (note == notes.end() || note->second.page_written);
  std::string html = fmt::format("<details id=\"{}\" class=\"run\"{}>\n<summary><code>{}</code>: {}</summary>\n",
                                 RunAnchor(index), first ? " open" : "", Html(test.name),
                                 Html(text::FailureMessage(result, test)));
  if (note != notes.end() && !note->second.note.empty()) {
    html += "<p class=\"note\">" + Html(note->second.note) + "</p>\n";
  }
  if (written) {
    html += fmt::format(
        "<p class=\"links\"><a href=\"{0}\" target=\"_blank\">Open the viewer on its own page</a> "
        "(<code>{1}</code>)</p>\n"
        "<iframe class=\"viewer\" src=\"{0}\" title=\"The viewer of {2}\"{3}></iframe>\n",
        UrlPath(page), Html(page), Html(test.name), first ? "" : " loading=\"lazy\"");
  }
  html += "</details>\n";
  return html;
}

}  // namespace

std::string_view ToString(ReportForm form) { return form == ReportForm::kFull ? "full" : "student"; }

std::optional<ReportForm> ParseReportForm(std::string_view text) {
  if (text == "student") return ReportForm::kStudent;
  if (text == "full") return ReportForm::kFull;
  return std::nullopt;
}

bool ShowsWhole(const TestResult& test, ReportForm form) {
  return form == ReportForm::kFull || test.visibility != assignment::Visibility::kHidden;
}

std::string ReplayPagePath(const TestResult& test) {
  if (test.replay_path.empty()) return {};
  const std::filesystem::path replay(test.replay_path);
  if (replay.is_absolute()) return {};
  for (const std::filesystem::path& part : replay) {
    if (part == "..") return {};
  }
  std::filesystem::path page = replay.parent_path() / "replay.html";
  if (page == replay) page = replay.string() + ".html";
  return page.generic_string();
}

std::string ReportHtml(const SubmissionResult& result, const std::map<std::string, ReplayPageNote>& notes,
                       ReportForm form) {
  std::string html = R"(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<meta http-equiv="Content-Security-Policy" content="default-src 'none'; style-src 'unsafe-inline'; frame-src 'self' file:">
)";
  html += fmt::format("<title>{}: {}</title>\n<style>{}</style>\n</head>\n<body>\n", Html(result.title),
                      Html(result.submission), kStyle);
  html += fmt::format("<header>\n<h1>{}</h1>\n", Html(result.title));
  html += fmt::format("<p class=\"what\">Assignment <code>{}</code>, submission <code>{}</code>{}{}</p>\n",
                      Html(result.assignment), Html(result.submission),
                      result.public_only ? ", graded on the public tests only" : "",
                      form == ReportForm::kFull ? " &middot; <b>instructor's full report: it shows the hidden tests</b>"
                                                : "");
  html += fmt::format("<p id=\"score\" class=\"{}\">Points <b>{}/{}</b> &middot; Tests passed <b>{}/{}</b></p>\n",
                      ScoreClass(result), text::Points(result.points), text::Points(result.max_points),
                      result.tests_passed, result.tests.size());
  html += "</header>\n";

  html += "<h2>Build</h2>\n<div id=\"build\" class=\"box\">";
  if (result.build.ok()) {
    html += "<p class=\"ok\">The submission built.</p>";
  } else {
    html += "<p class=\"bad\">" + Html(text::BuildFailure(result.build)) + ". Every test scores 0.</p>";
  }
  if (!result.build.log_path.empty()) {
    html += fmt::format("<p>The build's output: <a href=\"{}\">{}</a></p>", UrlPath(result.build.log_path),
                        Html(result.build.log_path));
  }
  html += "</div>\n";

  html += "<h2>Tests</h2>\n<table id=\"tests\">\n<thead><tr><th>Test</th><th>Set</th><th>Points</th>"
          "<th>Result</th><th>Criteria</th></tr></thead>\n<tbody>\n";
  for (size_t i = 0; i < result.tests.size(); ++i) html += TestRow(result, result.tests[i], i, form);
  html += "</tbody>\n</table>\n";

  bool first = true;
  std::string runs;
  for (size_t i = 0; i < result.tests.size(); ++i) {
    if (!HasViewer(result.tests[i], form)) continue;
    runs += RunViewer(result, result.tests[i], i, first, notes);
    first = false;
  }
  if (!runs.empty()) {
    html += "<h2>Failing runs</h2>\n<p>Each failing run in the viewer: play it, step it with the arrow keys, "
            "click a robot to see the map it started its epoch with, click an event to jump to it.</p>\n";
    html += "<div id=\"runs\">\n" + runs + "</div>\n";
  }
  html += "<footer>Written by <code>syrof grade</code>. This folder opens offline: the viewers are the "
          "<code>replay.html</code> files beside each run's replay.</footer>\n</body>\n</html>\n";
  return html;
}

}  // namespace syrof::grader::report
