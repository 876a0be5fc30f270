// scripts/broken-variant.sh on every assignment's broken variants: each
// variant folder holds its NOTE.md, expected.yaml and mistake.patch and no
// copy of the sources; its patch applies to its reference; and the sources
// it makes differ from the reference's (a variant equal to its reference
// would only get the reference's marks). Then, on a planted assignment,
// that a patch which no longer applies, or changes nothing, fails with a
// message naming the assignment, the variant and the file.
//
// One test per variant, found by scanning SYROF_ASSIGNMENTS_DIR when ctest
// starts; the script is SYROF_BROKEN_VARIANT_SCRIPT.
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <ostream>
#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace syrof::grader::assignment {
namespace {

namespace fs = std::filesystem;

struct Variant {
  std::string assignment;  // the assignment folder's name
  std::string name;        // the folder under broken/
};

void PrintTo(const Variant& variant, std::ostream* out) { *out << variant.assignment << "/broken/" << variant.name; }

std::vector<Variant> FindVariants() {
  std::vector<Variant> found;
  for (const fs::directory_entry& entry : fs::directory_iterator(SYROF_ASSIGNMENTS_DIR)) {
    if (!fs::exists(entry.path() / "assignment.yaml") || !fs::is_directory(entry.path() / "broken")) continue;
    for (const fs::directory_entry& variant : fs::directory_iterator(entry.path() / "broken")) {
      if (variant.is_directory()) found.push_back({entry.path().filename().string(), variant.path().filename().string()});
    }
  }
  std::sort(found.begin(), found.end(),
            [](const Variant& a, const Variant& b) { return std::tie(a.assignment, a.name) < std::tie(b.assignment, b.name); });
  return found;
}

std::string TestName(const ::testing::TestParamInfo<Variant>& info) { return info.param.assignment + "_" + info.param.name; }

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void WriteFile(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

bool IsSource(const fs::path& path) {
  static const std::set<std::string> kSourceExtensions = {".c", ".cc", ".cpp", ".cxx", ".h", ".hpp"};
  return kSourceExtensions.count(path.extension().string()) > 0;
}

struct ScriptResult {
  int status = -1;     // the script's exit status; -1 if it did not exit
  std::string output;  // stdout and stderr together
};

// scripts/broken-variant.sh with `arguments`, each quoted.
ScriptResult RunScript(const std::vector<std::string>& arguments) {
  std::string line = std::string("'") + SYROF_BROKEN_VARIANT_SCRIPT + "'";
  for (const std::string& argument : arguments) line += " '" + argument + "'";
  ScriptResult result;
  FILE* pipe = popen((line + " 2>&1").c_str(), "r");
  char buffer[4096];
  size_t got = 0;
  while (pipe != nullptr && (got = fread(buffer, 1, sizeof buffer, pipe)) > 0) result.output.append(buffer, got);
  const int status = pipe == nullptr ? -1 : pclose(pipe);
  result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

// broken-variant.sh ASSIGNMENT VARIANT DIR.
ScriptResult MakeVariant(const fs::path& assignment, const std::string& variant, const fs::path& dir) {
  return RunScript({assignment.string(), variant, dir.string()});
}

fs::path Scratch(const std::string& name) {
  const fs::path path = fs::path(::testing::TempDir()) / ("syrof_broken_variant_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(path);
  return path;
}

class BrokenVariantTest : public ::testing::TestWithParam<Variant> {};

TEST_P(BrokenVariantTest, HoldsItsNotesAndPatchAndNoCopyOfTheSources) {
  const fs::path folder = fs::path(SYROF_ASSIGNMENTS_DIR) / GetParam().assignment / "broken" / GetParam().name;

  std::set<std::string> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) files.insert(entry.path().filename().string());

  EXPECT_EQ(files, (std::set<std::string>{"NOTE.md", "expected.yaml", "mistake.patch"}))
      << folder << ": a variant is its reference plus mistake.patch (docs/grading.md, \"Broken variants\")";
}

TEST_P(BrokenVariantTest, PatchAppliesAndTheSourcesDifferFromTheReference) {
  const fs::path assignment = fs::path(SYROF_ASSIGNMENTS_DIR) / GetParam().assignment;
  const fs::path out = Scratch(TestName({GetParam(), 0}));

  const ScriptResult made = MakeVariant(assignment, GetParam().name, out);

  ASSERT_EQ(made.status, 0) << made.output;
  int sources = 0;
  std::vector<std::string> changed;
  for (const fs::directory_entry& entry : fs::directory_iterator(assignment / "reference")) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file() || name == "expected.yaml") continue;
    ASSERT_TRUE(fs::exists(out / name)) << name << " was not written";
    if (!IsSource(entry.path())) continue;
    ++sources;
    if (ReadFile(entry.path()) != ReadFile(out / name)) changed.push_back(name);
  }
  EXPECT_GT(sources, 0) << "the reference has no sources";
  EXPECT_FALSE(changed.empty()) << "mistake.patch leaves every source as the reference's";
  EXPECT_EQ(ReadFile(out / "expected.yaml"), ReadFile(assignment / "broken" / GetParam().name / "expected.yaml"))
      << "the variant's expected.yaml, not the reference's";
  fs::remove_all(out);
}

INSTANTIATE_TEST_SUITE_P(Assignments, BrokenVariantTest, ::testing::ValuesIn(FindVariants()), TestName);

// An assignment of one source file with one variant, `off_by_one`, whose
// patch changes line 3 of `widget.c`.
class PlantedVariantTest : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = Scratch(::testing::UnitTest::GetInstance()->current_test_info()->name());
    assignment_ = root_ / "widget";
    WriteFile(assignment_ / "assignment.yaml", "title: Widget\n");
    WriteFile(assignment_ / "reference/widget.c", "int a = 1;\nint b = 2;\nint c = 3;\nint d = 4;\nint e = 5;\n");
    WriteFile(assignment_ / "reference/expected.yaml", "points: 100\nloses: []\n");
    WriteFile(assignment_ / "broken/off_by_one/NOTE.md", "# off by one\n");
    WriteFile(assignment_ / "broken/off_by_one/expected.yaml", "points: 50\nloses: [goal]\n");
    WriteFile(assignment_ / "broken/off_by_one/mistake.patch",
              "--- a/widget.c\n+++ b/widget.c\n@@ -1,5 +1,5 @@\n int a = 1;\n int b = 2;\n-int c = 3;\n+int c = 4;\n"
              " int d = 4;\n int e = 5;\n");
  }
  void TearDown() override { fs::remove_all(root_); }

  fs::path root_;
  fs::path assignment_;
};

TEST_F(PlantedVariantTest, AppliesToItsReference) {
  const ScriptResult made = MakeVariant(assignment_, "off_by_one", root_ / "out");

  ASSERT_EQ(made.status, 0) << made.output;
  EXPECT_EQ(ReadFile(root_ / "out/widget.c"), "int a = 1;\nint b = 2;\nint c = 4;\nint d = 4;\nint e = 5;\n");
  EXPECT_EQ(ReadFile(root_ / "out/expected.yaml"), "points: 50\nloses: [goal]\n");
}

TEST_F(PlantedVariantTest, AReferenceChangedWhereThePatchGoesFailsNamingAssignmentVariantAndFile) {
  WriteFile(assignment_ / "reference/widget.c", "int a = 1;\nint b = 2;\nint c = 30;\nint d = 4;\nint e = 5;\n");

  const ScriptResult made = MakeVariant(assignment_, "off_by_one", root_ / "out");

  EXPECT_EQ(made.status, 1);
  EXPECT_NE(made.output.find("assignment 'widget', broken variant 'off_by_one': mistake.patch does not apply to "
                             "reference/widget.c"),
            std::string::npos)
      << made.output;
  EXPECT_FALSE(fs::exists(root_ / "out")) << "nothing written when the patch fails";
}

TEST_F(PlantedVariantTest, AReferenceChangedElsewhereStillTakesThePatch) {
  WriteFile(assignment_ / "reference/widget.c",
            "// a fix above\nint a = 1;\nint b = 2;\nint c = 3;\nint d = 4;\nint e = 5;\nint f = 6;\n");

  const ScriptResult made = MakeVariant(assignment_, "off_by_one", root_ / "out");

  ASSERT_EQ(made.status, 0) << made.output;
  EXPECT_EQ(ReadFile(root_ / "out/widget.c"),
            "// a fix above\nint a = 1;\nint b = 2;\nint c = 4;\nint d = 4;\nint e = 5;\nint f = 6;\n");
}

TEST_F(PlantedVariantTest, APatchThatChangesNothingFails) {
  WriteFile(assignment_ / "broken/off_by_one/mistake.patch", "");

  const ScriptResult made = MakeVariant(assignment_, "off_by_one", root_ / "out");

  EXPECT_EQ(made.status, 1);
  EXPECT_NE(made.output.find("'off_by_one': mistake.patch changes none of the reference's files"), std::string::npos)
      << made.output;
}

TEST_F(PlantedVariantTest, WritePatchMakesThePatchBackFromAnEditedFolder) {
  const std::string patch = ReadFile(assignment_ / "broken/off_by_one/mistake.patch");
  WriteFile(root_ / "edited/widget.c", "int a = 1;\nint b = 2;\nint c = 4;\nint d = 4;\nint e = 5;\n");
  fs::remove(assignment_ / "broken/off_by_one/mistake.patch");

  const ScriptResult written = RunScript({"--write-patch", assignment_.string(), "off_by_one", (root_ / "edited").string()});

  ASSERT_EQ(written.status, 0) << written.output;
  EXPECT_EQ(ReadFile(assignment_ / "broken/off_by_one/mistake.patch"), patch);
}

TEST_F(PlantedVariantTest, AnUnknownVariantFailsListingTheKnownOnes) {
  const ScriptResult made = MakeVariant(assignment_, "off_by_two", root_ / "out");

  EXPECT_EQ(made.status, 2);
  EXPECT_NE(made.output.find("has no broken variant 'off_by_two'"), std::string::npos) << made.output;
  EXPECT_NE(made.output.find("its variants: off_by_one"), std::string::npos) << made.output;
}

}  // namespace
}  // namespace syrof::grader::assignment
