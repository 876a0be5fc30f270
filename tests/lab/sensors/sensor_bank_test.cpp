#include "syrof/lab/sensors/sensor_bank.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include "syrof/estimation/flow_model.h"
#include "syrof/estimation/imu_model.h"
#include "syrof/estimation/multilateration.h"

namespace syrof::lab::sensors {
namespace {

constexpr int64_t kMillisecond = 1'000'000;

// Keeps every reading, and every reading's bytes in one stream.
class Recorder final : public ReadingSink {
 public:
  void OnImu(const estimation::ImuReading& reading) override {
    imu.push_back(reading);
    Append(reading);
  }
  void OnFlow(const estimation::FlowReading& reading) override {
    flow.push_back(reading);
    Append(reading);
  }
  void OnUwb(const estimation::UwbReading& reading) override {
    uwb.push_back(reading);
    Append(reading);
  }
  std::vector<estimation::ImuReading> imu;
  std::vector<estimation::FlowReading> flow;
  std::vector<estimation::UwbReading> uwb;
  std::vector<unsigned char> bytes;

 private:
  template <typename T>
  void Append(const T& reading) {
    const size_t at = bytes.size();
    bytes.resize(at + sizeof(T));
    std::memcpy(bytes.data() + at, &reading, sizeof(T));
  }
};

// Samples a bank every 10 ms for `seconds` along a trajectory.
void SampleEvery10Ms(SensorBank& bank, const Trajectory& trajectory, double seconds, ReadingSink& sink) {
  const int64_t end = static_cast<int64_t>(seconds * 1000) * kMillisecond;
  for (int64_t t = 0; t < end; t += 10 * kMillisecond) bank.Sample(t, trajectory.At(t), sink);
}

struct Statistics {
  void Add(double value) {
    ++count;
    sum += value;
    sum_squares += value * value;
  }
  double mean() const { return sum / count; }
  double sigma() const { return std::sqrt(sum_squares / count - mean() * mean()); }
  double count = 0;
  double sum = 0;
  double sum_squares = 0;
};

TEST(SensorBankTest, EmitsAtTheDefaultRates) {
  SensorBank bank(SensorBankConfig{}, 1);
  Recorder recorder;
  const FigureEight eight(FigureEight::Params{});
  EXPECT_EQ(bank.next_due_ns(), 0);
  SampleEvery10Ms(bank, eight, 10.0, recorder);
  EXPECT_EQ(recorder.imu.size(), 1000u);
  EXPECT_EQ(recorder.flow.size(), 500u);
  EXPECT_EQ(recorder.uwb.size(), 100u);
  EXPECT_EQ(bank.next_due_ns(), 10'000 * kMillisecond);
  EXPECT_EQ(recorder.imu[1].timestamp_ns, 10 * kMillisecond);
  EXPECT_EQ(recorder.flow[1].timestamp_ns, 20 * kMillisecond);
  EXPECT_EQ(recorder.flow[1].interval_ns, 20'000'000u);
  EXPECT_EQ(recorder.uwb[1].timestamp_ns, 100 * kMillisecond);
  EXPECT_EQ(recorder.uwb[1].sweep, 1u);
  EXPECT_EQ(bank.missed(), 0u);
}

TEST(SensorBankTest, SameSeedGivesTheSameBytesAndAnotherSeedDoesNot) {
  const FigureEight eight(FigureEight::Params{});
  Recorder first;
  Recorder second;
  Recorder other;
  SensorBank first_bank(SensorBankConfig{}, 42);
  SensorBank second_bank(SensorBankConfig{}, 42);
  SensorBank other_bank(SensorBankConfig{}, 43);
  SampleEvery10Ms(first_bank, eight, 5.0, first);
  SampleEvery10Ms(second_bank, eight, 5.0, second);
  SampleEvery10Ms(other_bank, eight, 5.0, other);
  ASSERT_EQ(first.bytes.size(), second.bytes.size());
  EXPECT_EQ(first.bytes, second.bytes);
  EXPECT_NE(first.bytes, other.bytes);
}

TEST(SensorBankTest, ImuNoiseAndBiasFollowTheModel) {
  SensorBankConfig config;
  config.imu.accel_bias_walk_mps2_per_sqrt_s = 0;
  config.imu.gyro_bias_walk_radps_per_sqrt_s = 0;
  SensorBank bank(config, 2);
  Recorder recorder;
  const StraightLine standing = Stationary(1.0, 1.0, 0.7);
  SampleEvery10Ms(bank, standing, 100.0, recorder);
  Statistics accel_x;
  Statistics accel_z;
  Statistics gyro_z;
  for (const estimation::ImuReading& reading : recorder.imu) {
    accel_x.Add(reading.accel_g[0] * kStandardGravity);
    accel_z.Add(reading.accel_g[2] * kStandardGravity);
    gyro_z.Add(reading.gyro_dps[2] * std::numbers::pi / 180);
  }
  const ImuBias& bias = bank.imu_bias();
  EXPECT_NEAR(accel_x.mean(), bias.accel_mps2[0], 0.002);
  EXPECT_NEAR(accel_x.sigma(), config.imu.accel_sigma_mps2, 0.1 * config.imu.accel_sigma_mps2);
  EXPECT_NEAR(accel_z.mean(), kStandardGravity + bias.accel_mps2[2], 0.002);
  EXPECT_NEAR(gyro_z.mean(), bias.gyro_radps[2], 1e-4);
  EXPECT_NEAR(gyro_z.sigma(), config.imu.gyro_sigma_radps, 0.1 * config.imu.gyro_sigma_radps);
  EXPECT_NE(bias.gyro_radps[2], 0.0);
}

TEST(SensorBankTest, GyroBiasWalksAtItsRate) {
  SensorBankConfig config;
  config.imu.gyro_bias_sigma_radps = 0;
  config.imu.gyro_bias_walk_radps_per_sqrt_s = 1e-3;
  const StraightLine standing = Stationary(1.0, 1.0, 0.0);
  Statistics drift;
  for (uint64_t seed = 0; seed < 200; ++seed) {
    SensorBank bank(config, seed);
    Recorder recorder;
    SampleEvery10Ms(bank, standing, 4.0, recorder);
    drift.Add(bank.imu_bias().gyro_radps[2]);
  }
  // After 4 s the walk has spread by 1e-3 * sqrt(4).
  EXPECT_NEAR(drift.sigma(), 2e-3, 0.3e-3);
}

TEST(SensorBankTest, ImuReportsTheBodyFrameSpecificForceInG) {
  SensorBankConfig config;
  config.imu = ImuModel{config.imu.period_ns, 0, 0, 0, 0, 0, 0, 0};  // noiseless
  SensorBank bank(config, 3);
  Recorder recorder;
  const FigureEight eight(FigureEight::Params{});
  SampleEvery10Ms(bank, eight, 1.0, recorder);
  for (size_t k = 0; k < recorder.imu.size(); ++k) {
    const TrueState truth = eight.At(recorder.imu[k].timestamp_ns);
    const auto sample = estimation::ConvertImuReading<double>(recorder.imu[k]);
    ASSERT_TRUE(sample.ok());
    // On the right loop the centripetal acceleration points to the robot's right.
    const double right_turn = -0.5 * 0.5 / 0.8;
    EXPECT_NEAR(sample.value().accel_mps2[0], 0.0, 1e-6);
    EXPECT_NEAR(sample.value().accel_mps2[1], right_turn * 9.81 / kStandardGravity, 1e-6);
    EXPECT_NEAR(sample.value().accel_mps2[2], 9.81, 1e-5);  // the paper's G
    EXPECT_NEAR(sample.value().rate_radps[2], truth.yaw_rate_radps, 1e-6);
  }
}

TEST(SensorBankTest, FlowCountsBodyMotionInPixelsWithItsNoise) {
  const estimation::FlowGeometry<double> geometry{};
  const double metres_per_pixel = estimation::FlowMetresPerPixel(geometry);
  const StraightLine line(StraightLine::Params{0.5, 0.5, 0.3, 0.4});
  SensorBank bank(SensorBankConfig{}, 4);
  Recorder recorder;
  SampleEvery10Ms(bank, line, 60.0, recorder);
  Statistics forward;
  Statistics left;
  for (const estimation::FlowReading& reading : recorder.flow) {
    forward.Add(reading.delta_x_px);
    left.Add(reading.delta_y_px);
  }
  // 0.4 m/s forward for 20 ms: 5.41 pixels of 1.478 mm.
  EXPECT_NEAR(forward.mean(), 0.4 * 0.02 / metres_per_pixel, 0.15);
  EXPECT_NEAR(left.mean(), 0.0, 0.15);
  EXPECT_NEAR(forward.sigma(), std::sqrt(4.0 + 1.0 / 12), 0.15);
  const auto velocity = estimation::FlowToBodyVelocity(recorder.flow[10], geometry, 2.0);
  ASSERT_TRUE(velocity.ok());
  EXPECT_NEAR(velocity.value().forward_mps, 0.4, 4 * velocity.value().sigma_mps);
}

TEST(SensorBankTest, UwbRangesCarryNoiseOutliersAndDropouts) {
  SensorBankConfig config;
  config.uwb.outlier_probability = 0.05;
  SensorBank bank(config, 5);
  Recorder recorder;
  const StraightLine standing = Stationary(1.3, 2.2, 0.0);
  SampleEvery10Ms(bank, standing, 500.0, recorder);  // 5000 sweeps, 20000 ranges
  const TrueState truth = standing.At(0);
  Statistics error;
  int valid = 0;
  int large = 0;
  for (const estimation::UwbReading& sweep : recorder.uwb) {
    for (int i = 0; i < config.arena.anchor_count; ++i) {
      if ((sweep.valid_mask & (1u << i)) == 0) continue;
      ++valid;
      const estimation::Vector3<double> offset(truth.x_m - config.arena.anchors[i][0],
                                               truth.y_m - config.arena.anchors[i][1],
                                               config.arena.tag_height_m - config.arena.anchors[i][2]);
      const double range_error = sweep.range_m[i] - offset.norm();
      EXPECT_GT(range_error, -0.6);  // noise only: outliers are always long
      if (range_error > 0.45) {
        ++large;
      } else {
        error.Add(range_error);
      }
    }
  }
  const double ranges = static_cast<double>(recorder.uwb.size() * 4);
  EXPECT_NEAR(error.mean(), 0.0, 0.005);
  EXPECT_NEAR(error.sigma(), 0.10, 0.005);
  EXPECT_NEAR(large / ranges, 0.05, 0.01);
  EXPECT_NEAR(static_cast<double>(bank.uwb_outliers()) / ranges, 0.05, 0.01);
  EXPECT_NEAR(1.0 - valid / ranges, 0.01, 0.005);
  EXPECT_EQ(static_cast<uint64_t>(ranges) - valid, bank.uwb_dropouts());
}

TEST(SensorBankTest, NoiselessRangesGiveThePositionBackThroughTheClosedForm) {
  SensorBankConfig config;
  config.uwb.sigma_m = 0;
  config.uwb.outlier_probability = 0;
  config.uwb.dropout_probability = 0;
  SensorBank bank(config, 6);
  Recorder recorder;
  const StraightLine standing = Stationary(2.6, 1.1, 0.0);
  bank.Sample(0, standing.At(0), recorder);
  ASSERT_EQ(recorder.uwb.size(), 1u);
  const estimation::UwbReading& sweep = recorder.uwb[0];
  EXPECT_EQ(sweep.valid_mask, 0xFu);
  const double ranges[4] = {sweep.range_m[0], sweep.range_m[1], sweep.range_m[2], sweep.range_m[3]};
  const auto position = estimation::ClosedFormPosition(estimation::DefaultAnchorLayout<double>(), ranges);
  ASSERT_TRUE(position.ok());
  EXPECT_NEAR(position.value().x(), 2.6, 1e-5);
  EXPECT_NEAR(position.value().y(), 1.1, 1e-5);
  EXPECT_NEAR(position.value().z(), config.arena.tag_height_m, 1e-5);
}

TEST(SensorBankTest, ASwitchedOffSensorIsSilentAndLeavesTheOthersUnchanged) {
  const FigureEight eight(FigureEight::Params{});
  SensorBank reference(SensorBankConfig{}, 7);
  SensorBank quiet(SensorBankConfig{}, 7);
  Recorder reference_readings;
  Recorder quiet_readings;
  quiet.set_enabled(SensorKind::kImu, false);
  EXPECT_FALSE(quiet.enabled(SensorKind::kImu));
  SampleEvery10Ms(reference, eight, 2.0, reference_readings);
  SampleEvery10Ms(quiet, eight, 2.0, quiet_readings);
  EXPECT_TRUE(quiet_readings.imu.empty());
  ASSERT_EQ(quiet_readings.uwb.size(), reference_readings.uwb.size());
  for (size_t k = 0; k < quiet_readings.uwb.size(); ++k) {
    EXPECT_EQ(std::memcmp(&quiet_readings.uwb[k], &reference_readings.uwb[k], sizeof(estimation::UwbReading)), 0);
  }
  // Back on: the IMU stream resumes where the reference is.
  quiet.set_enabled(SensorKind::kImu, true);
  Recorder after;
  Recorder reference_after;
  quiet.Sample(2000 * kMillisecond, eight.At(2000 * kMillisecond), after);
  reference.Sample(2000 * kMillisecond, eight.At(2000 * kMillisecond), reference_after);
  ASSERT_EQ(after.imu.size(), 1u);
  EXPECT_EQ(std::memcmp(&after.imu[0], &reference_after.imu[0], sizeof(estimation::ImuReading)), 0);
}

TEST(SensorBankTest, ALateCallEmitsOnceAndCountsTheMissedReadings) {
  SensorBank bank(SensorBankConfig{}, 8);
  Recorder recorder;
  const StraightLine standing = Stationary(1.0, 1.0, 0.0);
  bank.Sample(0, standing.At(0), recorder);
  bank.Sample(55 * kMillisecond, standing.At(55 * kMillisecond), recorder);
  EXPECT_EQ(recorder.imu.size(), 2u);   // at 0 and, once, at 55 ms
  EXPECT_EQ(recorder.flow.size(), 2u);
  EXPECT_EQ(bank.missed(), 4u + 1u);    // IMU at 10..40 ms, flow at 20 ms
  EXPECT_EQ(bank.next_due_ns(), 60 * kMillisecond);
  EXPECT_EQ(recorder.flow[1].interval_ns, 40'000'000u);  // at most two periods
}

}  // namespace
}  // namespace syrof::lab::sensors
