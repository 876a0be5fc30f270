// report.html in headless Chromium, from file:// as a student opens it: the
// page loads and shows the score, and the <iframe> of a failing run shows
// the viewer of that run's replay (a real one, from a short scenario run).
//
// Chromium's --dump-dom prints only the top page, so the viewer inside the
// frame is read by a probe page beside the report: it frames report.html
// and, once the viewer in it says it is ready (<body data-ready="1">, its
// JSON summary in #report, as viewer.js writes them), copies what both say
// into its own DOM. Reading into frames from file:// needs
// --allow-file-access-from-files, for the probe only; the report is loaded
// without it in the first test.
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "report_test_support.h"
#include "syrof/lab/scenario/scenario.h"
#include "syrof/lab/sim/simulation.h"
#include "syrof/report/reports.h"

namespace syrof::grader::report {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string Chromium(const fs::path& page, const std::string& flags) {
  const fs::path profile = page.parent_path() / ("profile-" + page.stem().string());
  return std::string(SYROF_CHROMIUM) + " --headless --no-sandbox --disable-gpu --hide-scrollbars --no-first-run" +
         " --disable-extensions --disable-dev-shm-usage --user-data-dir=" + profile.string() +
         " --window-size=1400,1000 --virtual-time-budget=8000 " + flags + " --dump-dom 'file://" + page.string() +
         "' 2>/dev/null";
}

std::string DumpDom(const fs::path& page, const std::string& flags = "") {
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(Chromium(page, flags).c_str(), "r"), pclose);
  if (!pipe) return {};
  std::string dom;
  std::array<char, 65536> buffer;
  size_t got = 0;
  while ((got = fread(buffer.data(), 1, buffer.size(), pipe.get())) > 0) dom.append(buffer.data(), got);
  return dom;
}

std::string Unescape(std::string text) {
  for (const auto& [from, to] : std::array<std::pair<std::string, std::string>, 4>{
           {{"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""}, {"&amp;", "&"}}}) {
    for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
      text.replace(at, from.size(), to);
    }
  }
  return text;
}

// The probe: frames report.html and reports what it and its first viewer show.
constexpr const char* kProbe = R"(<!DOCTYPE html>
<html><head><meta charset="utf-8"></head><body>
<pre id="probe">waiting</pre>
<iframe id="report" src="report.html" style="width:1400px;height:3000px"></iframe>
<script>
function check() {
  const seen = {};
  try {
    const report = document.getElementById('report').contentDocument;
    seen.score = report.getElementById('score').textContent;
    const frames = report.querySelectorAll('iframe.viewer');
    seen.frames = frames.length;
    seen.src = frames[0].getAttribute('src');
    const viewer = frames[0].contentDocument;
    seen.ready = viewer.body.getAttribute('data-ready');
    if (seen.ready === '1') seen.viewer = JSON.parse(viewer.getElementById('report').textContent);
  } catch (error) {
    seen.error = String(error);
  }
  document.getElementById('probe').textContent = JSON.stringify(seen);
  if (seen.ready === '1') document.body.setAttribute('data-done', '1');
  else setTimeout(check, 100);
}
window.addEventListener('load', check);
</script>
</body></html>
)";

class ReportBrowserTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() / ("syrof_report_browser_" + std::to_string(getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_ / "runs/gather_6/seed-2");
    // A short real run: demo_circle, 4 s, seed 7.
    lab::scenario::Overrides overrides;
    overrides.duration_s = 4;
    overrides.seed = 7;
    const lab::scenario::LoadResult loaded =
        lab::scenario::LoadScenarioFile(std::string(SYROF_SCENARIOS_DIR) + "/demo_circle.yaml", overrides);
    ASSERT_TRUE(loaded.ok());
    std::ofstream replay(*dir_ / "runs/gather_6/seed-2/replay", std::ios::binary);
    lab::sim::SimulationOptions options;
    options.replay = &replay;
    (void)lab::sim::Run(*loaded.scenario, options, 0.0);
    replay.close();
    ASSERT_EQ(WriteSubmissionReports(testing::ExampleResult(), dir_->string()), std::nullopt);
    std::ofstream(*dir_ / "probe.html", std::ios::binary) << kProbe;
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }
  static fs::path* dir_;
};
fs::path* ReportBrowserTest::dir_ = nullptr;

TEST_F(ReportBrowserTest, ThePageLoadsAndShowsTheScore) {
  const std::string dom = DumpDom(*dir_ / "report.html");

  ASSERT_NE(dom.find("<h1>Gather the swarm</h1>"), std::string::npos) << dom.substr(0, 2000);
  EXPECT_NE(dom.find("Points <b>68.75/100</b>"), std::string::npos);
  EXPECT_NE(dom.find("Tests passed <b>2/4</b>"), std::string::npos);
  EXPECT_NE(dom.find("src=\"runs/gather_6/seed-2/replay.html\""), std::string::npos);
}

TEST_F(ReportBrowserTest, TheFrameOfAFailingRunShowsItsViewer) {
  const std::string dom = DumpDom(*dir_ / "probe.html", "--allow-file-access-from-files");

  std::smatch match;
  ASSERT_TRUE(std::regex_search(dom, match, std::regex(R"re(<pre id="probe">([^<]*)</pre>)re"))) << dom;
  const json seen = json::parse(Unescape(match[1].str()), nullptr, false);
  ASSERT_TRUE(seen.is_object()) << match[1].str();
  EXPECT_NE(dom.find("data-done=\"1\""), std::string::npos) << "the viewer never said it was ready: " << seen.dump();
  EXPECT_EQ(seen.value("score", ""), "Points 68.75/100 · Tests passed 2/4");
  EXPECT_EQ(seen.value("frames", 0), 1);
  EXPECT_EQ(seen.value("src", ""), "runs/gather_6/seed-2/replay.html");
  ASSERT_TRUE(seen.contains("viewer")) << seen.dump();
  EXPECT_EQ(seen["viewer"].value("status", ""), "complete");
  EXPECT_EQ(seen["viewer"].value("robots_drawn", 0), 10);
}

}  // namespace
}  // namespace syrof::grader::report
