#include "syrof/app/app.h"

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <span>
#include <string>

#include "syrof/app/c_abi_app.h"

namespace syrof::app {
namespace {

uint8_t Init(const syrof_app_info*) { return 0; }
uint8_t NewRound(syrof_car_command*, const syrof_ldmap*, uint8_t state, uint32_t) { return state; }
uint8_t EndOfRound(const syrof_ldmap*, uint8_t state, uint32_t) { return state; }

TEST(AppTest, ValidateChecksTheAbiVersionAndEveryCallback) {
  const syrof_app_descriptor good = {SYROF_APP_ABI_VERSION, "x", Init, NewRound, EndOfRound};
  const syrof_app_descriptor old_abi = {SYROF_APP_ABI_VERSION + 1, "x", Init, NewRound, EndOfRound};
  const syrof_app_descriptor missing = {SYROF_APP_ABI_VERSION, "x", Init, nullptr, EndOfRound};

  EXPECT_EQ(Validate(&good), DescriptorError::kOk);
  EXPECT_EQ(Validate(&old_abi), DescriptorError::kAbiVersionMismatch);
  EXPECT_EQ(Validate(&missing), DescriptorError::kMissingCallback);
  EXPECT_EQ(Validate(nullptr), DescriptorError::kNull);
}

TEST(AppTest, FindMemberSearchesById) {
  std::array<syrof_member_state, 3> members{};
  members[0].id = 2;
  members[1].id = 5;
  members[2].id = 9;
  const syrof_ldmap map{4, SYROF_MODE_COOPERATIVE, 5, 3, members.data()};

  EXPECT_EQ(FindMember(map, 5), &members[1]);
  EXPECT_EQ(FindMember(map, 9), &members[2]);
  EXPECT_EQ(FindMember(map, 3), nullptr);
}

TEST(AppTest, MembersForQueriesCopiesIdsAndPositions) {
  std::array<syrof_member_state, 2> members{};
  members[0] = {1, -5, 7, 0, 0, 0, 0, 0, {}, SYROF_KIND_OMNI};
  members[1] = {4, 100, -200, 0, 0, 0, 0, 0, {}, SYROF_KIND_OMNI};
  const syrof_ldmap map{0, SYROF_MODE_AUTONOMOUS, 1, 2, members.data()};
  std::array<syrof_queries_member, 2> out{};

  ASSERT_EQ(syrofMembersForQueries(&map, out.data()), 2u);

  EXPECT_EQ(out[1].id, 4);
  EXPECT_EQ(out[1].x_mm, 100);
  EXPECT_EQ(out[1].y_mm, -200);
  EXPECT_EQ(syrofMembersForQueries(nullptr, out.data()), 0u);
}

// A platform that records what reaches it and refuses what the robot would.
class RecordingPlatform final : public Platform {
 public:
  syrof_app_status SendMessageData(std::span<const uint8_t> payload) override {
    last_length = payload.size();
    return payload.size() > SYROF_APP_MAX_PAYLOAD_BYTES ? SYROF_APP_PAYLOAD_TOO_LONG : SYROF_APP_OK;
  }
  syrof_queries_workspace* queries_workspace() override { return nullptr; }
  size_t last_length = 0;
};

int last_send_result = -1;

uint8_t InitSeven(const syrof_app_info*) { return 7; }
uint8_t NewRoundSendsTooMuch(syrof_car_command*, const syrof_ldmap*, uint8_t state, uint32_t) {
  const uint8_t payload[SYROF_APP_MAX_PAYLOAD_BYTES + 1] = {};
  last_send_result = sendMessageData(payload, sizeof payload);
  return static_cast<uint8_t>(state + 1);
}

TEST(CAbiAppTest, ThreadsTheGlobalStateAndReportsOk) {
  const syrof_app_descriptor descriptor = {SYROF_APP_ABI_VERSION, "c", InitSeven, NewRoundSendsTooMuch, EndOfRound};
  CAbiApp app(descriptor);
  RecordingPlatform platform;
  uint8_t global_state = 0;
  syrof_car_command command{};
  const syrof_ldmap map{};

  ASSERT_TRUE(app.Init(syrof_app_info{}, platform, global_state).ok());
  EXPECT_EQ(global_state, 7);
  ASSERT_TRUE(app.NewRound(command, map, global_state, 0).ok());
  EXPECT_EQ(global_state, 8);
  ASSERT_TRUE(app.EndOfRound(map, global_state, 0).ok());
  EXPECT_EQ(global_state, 8);
}

TEST(CAbiAppTest, AnOverlongPayloadReachesThePlatformWhichRefusesIt) {
  // The robot behind the platform counts refusals, so the C side must not
  // refuse on its own.
  const syrof_app_descriptor descriptor = {SYROF_APP_ABI_VERSION, "c", InitSeven, NewRoundSendsTooMuch, EndOfRound};
  CAbiApp app(descriptor);
  RecordingPlatform platform;
  uint8_t global_state = 0;
  syrof_car_command command{};
  const syrof_ldmap map{};
  ASSERT_TRUE(app.Init(syrof_app_info{}, platform, global_state).ok());

  ASSERT_TRUE(app.NewRound(command, map, global_state, 0).ok());

  EXPECT_EQ(platform.last_length, SYROF_APP_MAX_PAYLOAD_BYTES + 1);
  EXPECT_EQ(last_send_result, SYROF_APP_PAYLOAD_TOO_LONG);
}

TEST(AppTest, PlatformFunctionsOutsideACallbackRefuse) {
  const uint8_t payload[1] = {1};
  EXPECT_EQ(sendMessageData(payload, 1), SYROF_APP_NOT_RUNNING);
  EXPECT_EQ(syrofQueriesWorkspace(), nullptr);
  double value = 3;
  EXPECT_EQ(syrofAppParameter("radius_m", &value), SYROF_APP_NOT_RUNNING);
  EXPECT_EQ(syrofAppInput("charge", &value), SYROF_APP_NOT_RUNNING);
  EXPECT_EQ(value, 3);
}

TEST(AppTest, FindParameterFindsByWholeName) {
  const Parameter params[] = {{"radius_m", 1.5}, {"margin", -2}};
  double value = 9;

  EXPECT_EQ(FindParameter(params, "margin", value), SYROF_APP_OK);
  EXPECT_EQ(value, -2);
  EXPECT_EQ(FindParameter(params, "radius", value), SYROF_APP_NO_SUCH_PARAMETER);
  EXPECT_EQ(FindParameter(params, "radius_m_", value), SYROF_APP_NO_SUCH_PARAMETER);
  EXPECT_EQ(FindParameter({}, "radius_m", value), SYROF_APP_NO_SUCH_PARAMETER);
  EXPECT_EQ(value, -2);
}

// A platform that gives the parameters of a table.
class ParameterPlatform final : public Platform {
 public:
  syrof_app_status SendMessageData(std::span<const uint8_t>) override { return SYROF_APP_OK; }
  syrof_queries_workspace* queries_workspace() override { return nullptr; }
  syrof_app_status AppParameter(std::string_view name, double& value) override {
    ++asked;
    return FindParameter(params, name, value);
  }
  std::array<Parameter, 2> params{{{"radius_m", 1.5}, {std::string_view(kLongestName), 4}}};
  static constexpr char kLongestName[] =
      "abcdefghijklmnopqrstuvwxyzabcdefghijklmnopqrstuvwxyzabcdefghijk";  // 63 characters
  int asked = 0;
};
static_assert(sizeof(ParameterPlatform::kLongestName) == SYROF_APP_MAX_PARAMETER_NAME_LENGTH + 1);

// What the init below saw, for the test to check.
struct ParameterResults {
  int found = -1;
  double radius_m = 0;
  int missing = -1;
  double missing_value = 0;
  int null_name = -1;
  int null_value = -1;
  int longest = -1;
  double longest_value = 0;
  int too_long = -1;
} parameter_results;

uint8_t InitReadsParameters(const syrof_app_info*) {
  ParameterResults& r = parameter_results;
  r.found = syrofAppParameter("radius_m", &r.radius_m);
  r.missing_value = 0.25;  // the default stays
  r.missing = syrofAppParameter("margin_m", &r.missing_value);
  double ignored = 0;
  r.null_name = syrofAppParameter(nullptr, &ignored);
  r.null_value = syrofAppParameter("radius_m", nullptr);
  r.longest = syrofAppParameter(ParameterPlatform::kLongestName, &r.longest_value);
  // 64 characters and more: never found, and only 64 bytes are read (the
  // rest of this buffer is not even NUL-terminated).
  static char too_long[200];
  std::memset(too_long, 'a', sizeof too_long);
  r.too_long = syrofAppParameter(too_long, &ignored);
  return 0;
}

TEST(CAbiAppTest, AnAppReadsItsParametersFromThePlatform) {
  const syrof_app_descriptor descriptor = {SYROF_APP_ABI_VERSION, "c", InitReadsParameters, NewRound, EndOfRound};
  CAbiApp app(descriptor);
  ParameterPlatform platform;
  uint8_t global_state = 0;

  ASSERT_TRUE(app.Init(syrof_app_info{}, platform, global_state).ok());

  const ParameterResults& r = parameter_results;
  EXPECT_EQ(r.found, SYROF_APP_OK);
  EXPECT_EQ(r.radius_m, 1.5);
  EXPECT_EQ(r.missing, SYROF_APP_NO_SUCH_PARAMETER);
  EXPECT_EQ(r.missing_value, 0.25);
  EXPECT_EQ(r.null_name, SYROF_APP_NULL_ARGUMENT);
  EXPECT_EQ(r.null_value, SYROF_APP_NULL_ARGUMENT);
  EXPECT_EQ(r.longest, SYROF_APP_OK);
  EXPECT_EQ(r.longest_value, 4);
  EXPECT_EQ(r.too_long, SYROF_APP_NO_SUCH_PARAMETER);
  EXPECT_EQ(platform.asked, 3);  // the NULLs and the overlong name never reach the platform
}

TEST(CAbiAppTest, APlatformWithoutParametersHasNone) {
  RecordingPlatform platform;
  double value = 1;
  EXPECT_EQ(static_cast<Platform&>(platform).AppParameter("radius_m", value), SYROF_APP_NO_SUCH_PARAMETER);
  EXPECT_EQ(static_cast<Platform&>(platform).AppInput("charge", value), SYROF_APP_NO_SUCH_INPUT);
  EXPECT_EQ(value, 1);
}

// A platform whose robot has one private input, and parameters of the same
// name space: syrofAppInput asks AppInput only.
class InputPlatform final : public Platform {
 public:
  syrof_app_status SendMessageData(std::span<const uint8_t>) override { return SYROF_APP_OK; }
  syrof_queries_workspace* queries_workspace() override { return nullptr; }
  syrof_app_status AppParameter(std::string_view name, double& value) override {
    return FindParameter(params, name, value);
  }
  syrof_app_status AppInput(std::string_view name, double& value) override {
    ++asked;
    return FindParameter(inputs, name, value, SYROF_APP_NO_SUCH_INPUT);
  }
  std::array<Parameter, 1> params{{{"radius_m", 1.5}}};
  std::array<Parameter, 1> inputs{{{"charge", 0.75}}};
  int asked = 0;
};

struct InputResults {
  int found = -1;
  double charge = 0;
  int parameter_as_input = -1;
  double untouched = 0;
  int null_name = -1;
  int too_long = -1;
} input_results;

uint8_t InitReadsInputs(const syrof_app_info*) {
  InputResults& r = input_results;
  r.found = syrofAppInput("charge", &r.charge);
  r.untouched = 0.5;
  r.parameter_as_input = syrofAppInput("radius_m", &r.untouched);
  double ignored = 0;
  r.null_name = syrofAppInput(nullptr, &ignored);
  static char too_long[200];
  std::memset(too_long, 'c', sizeof too_long);
  r.too_long = syrofAppInput(too_long, &ignored);
  return 0;
}

TEST(CAbiAppTest, AnAppReadsItsRobotsInputsFromThePlatform) {
  const syrof_app_descriptor descriptor = {SYROF_APP_ABI_VERSION, "c", InitReadsInputs, NewRound, EndOfRound};
  CAbiApp app(descriptor);
  InputPlatform platform;
  uint8_t global_state = 0;

  ASSERT_TRUE(app.Init(syrof_app_info{}, platform, global_state).ok());

  const InputResults& r = input_results;
  EXPECT_EQ(r.found, SYROF_APP_OK);
  EXPECT_EQ(r.charge, 0.75);
  EXPECT_EQ(r.parameter_as_input, SYROF_APP_NO_SUCH_INPUT);
  EXPECT_EQ(r.untouched, 0.5);
  EXPECT_EQ(r.null_name, SYROF_APP_NULL_ARGUMENT);
  EXPECT_EQ(r.too_long, SYROF_APP_NO_SUCH_INPUT);
  EXPECT_EQ(platform.asked, 2);  // the NULL and the overlong name never reach the platform
}

}  // namespace
}  // namespace syrof::app
