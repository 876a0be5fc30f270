// The MPU-9250 driver against a fake I2C bus holding the chip's registers:
// the start-up writes, identity and bus failures, and the decoding of known
// register bytes in every full-scale range and a rotated mounting.
#include "syrof/firmware/drivers/mpu9250.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace syrof::firmware::drivers {
namespace {

// Register file of one chip; reads stream from consecutive registers.
class FakeI2c : public I2cBus {
 public:
  std::array<uint8_t, 256> registers{};
  std::vector<RegisterWrite> writes;  // wait_us unused
  BusStatus fail_with = BusStatus::kOk;
  uint8_t seen_address = 0;

  BusStatus Write(uint8_t address, std::span<const uint8_t> data) override {
    seen_address = address;
    if (fail_with != BusStatus::kOk) return fail_with;
    for (size_t i = 1; i < data.size(); ++i) {
      registers[(data[0] + i - 1) & 0xFF] = data[i];
      writes.push_back({static_cast<uint8_t>(data[0] + i - 1), data[i], 0});
    }
    return BusStatus::kOk;
  }
  BusStatus WriteRead(uint8_t address, std::span<const uint8_t> command, std::span<uint8_t> response) override {
    seen_address = address;
    if (fail_with != BusStatus::kOk) return fail_with;
    for (size_t i = 0; i < response.size(); ++i) response[i] = registers[(command[0] + i) & 0xFF];
    return BusStatus::kOk;
  }
};

class FakeDelay : public Delay {
 public:
  uint64_t total_us = 0;
  void WaitUs(uint32_t microseconds) override { total_us += microseconds; }
};

std::array<uint8_t, mpu9250::kBurstBytes> Burst(const std::array<int16_t, 7>& words) {
  std::array<uint8_t, mpu9250::kBurstBytes> bytes{};
  for (size_t i = 0; i < 7; ++i) {
    bytes[2 * i] = static_cast<uint8_t>(static_cast<uint16_t>(words[i]) >> 8);
    bytes[2 * i + 1] = static_cast<uint8_t>(static_cast<uint16_t>(words[i]) & 0xFF);
  }
  return bytes;
}

TEST(Mpu9250Test, StartChecksIdentityThenWritesTheSequence) {
  FakeI2c bus;
  FakeDelay delay;
  bus.registers[mpu9250::kWhoAmI] = mpu9250::kWhoAmIValue;
  Mpu9250 imu(bus, delay, Mpu9250Config{});

  ASSERT_EQ(imu.Start(), DriverError::kOk);

  const std::vector<RegisterWrite> expected = {
      {0x6B, 0x80, 0}, {0x6B, 0x01, 0}, {0x6C, 0x00, 0}, {0x1A, 0x03, 0}, {0x19, 9, 0},
      {0x1B, 0x08, 0}, {0x1C, 0x08, 0}, {0x1D, 0x03, 0}, {0x37, 0x10, 0}, {0x38, 0x01, 0},
  };
  EXPECT_EQ(bus.writes, expected);
  EXPECT_EQ(bus.seen_address, 0x68);
  EXPECT_EQ(delay.total_us, 110'000u);
}

TEST(Mpu9250Test, SequenceCarriesTheConfiguredRanges) {
  Mpu9250Config config;
  config.accel_range = mpu9250::AccelRange::k16G;
  config.gyro_range = mpu9250::GyroRange::k2000Dps;
  config.sample_rate_divider = 4;
  const auto sequence = Mpu9250StartSequence(config);
  EXPECT_EQ(sequence[4], (RegisterWrite{mpu9250::kSampleRateDivider, 4, 0}));
  EXPECT_EQ(sequence[5], (RegisterWrite{mpu9250::kGyroConfig, 0x18, 0}));
  EXPECT_EQ(sequence[6], (RegisterWrite{mpu9250::kAccelConfig, 0x18, 0}));
}

TEST(Mpu9250Test, WrongIdentityWritesNothing) {
  FakeI2c bus;
  FakeDelay delay;
  bus.registers[mpu9250::kWhoAmI] = 0x70;  // an MPU-6500
  Mpu9250 imu(bus, delay, Mpu9250Config{});
  EXPECT_EQ(imu.Start(), DriverError::kWrongDevice);
  EXPECT_TRUE(bus.writes.empty());
  EXPECT_EQ(imu.Read(0).error(), DriverError::kNotStarted);
}

TEST(Mpu9250Test, BusFailureIsReportedWithItsStatus) {
  FakeI2c bus;
  FakeDelay delay;
  bus.fail_with = BusStatus::kNack;
  Mpu9250 imu(bus, delay, Mpu9250Config{});
  EXPECT_EQ(imu.Start(), DriverError::kBus);
  EXPECT_EQ(imu.last_bus_status(), BusStatus::kNack);
}

TEST(Mpu9250Test, RejectsAnAxisMapThatIsNoPermutation) {
  FakeI2c bus;
  FakeDelay delay;
  bus.registers[mpu9250::kWhoAmI] = mpu9250::kWhoAmIValue;
  Mpu9250Config config;
  config.body_from_chip = {{{0, 1}, {0, -1}, {2, 1}}};
  Mpu9250 imu(bus, delay, config);
  EXPECT_EQ(imu.Start(), DriverError::kBadConfig);
}

TEST(Mpu9250Test, ParsesTheBurstBigEndian) {
  const std::array<uint8_t, mpu9250::kBurstBytes> bytes = {0x12, 0x34, 0xFF, 0xFE, 0x80, 0x00, 0x00, 0x00,
                                                           0x7F, 0xFF, 0x00, 0x01, 0xC0, 0x00};
  const mpu9250::RawSample raw = mpu9250::ParseBurst(bytes);
  EXPECT_EQ(raw.accel[0], 0x1234);
  EXPECT_EQ(raw.accel[1], -2);
  EXPECT_EQ(raw.accel[2], -32768);
  EXPECT_EQ(raw.temperature, 0);
  EXPECT_EQ(raw.gyro[0], 32767);
  EXPECT_EQ(raw.gyro[1], 1);
  EXPECT_EQ(raw.gyro[2], -16384);
  EXPECT_FLOAT_EQ(mpu9250::TemperatureC(0), 21.0f);
  EXPECT_NEAR(mpu9250::TemperatureC(3339), 31.0f, 0.01f);
}

TEST(Mpu9250Test, ScalesEveryRange) {
  const float accel_lsb[] = {16384, 8192, 4096, 2048};
  const float gyro_lsb[] = {131, 65.5f, 32.8f, 16.4f};
  for (uint8_t range = 0; range < 4; ++range) {
    Mpu9250Config config;
    config.accel_range = static_cast<mpu9250::AccelRange>(range);
    config.gyro_range = static_cast<mpu9250::GyroRange>(range);
    // 1 g on z, 10 deg/s about z, in this range's counts.
    const auto az = static_cast<int16_t>(accel_lsb[range]);
    const auto gz = static_cast<int16_t>(std::lround(gyro_lsb[range] * 10));
    const estimation::ImuReading reading = DecodeMpu9250Burst(Burst({0, 0, az, 0, 0, 0, gz}), config, 5);
    EXPECT_FLOAT_EQ(reading.accel_g[2], 1.0f) << int{range};
    EXPECT_NEAR(reading.gyro_dps[2], 10.0f, 1e-5f) << int{range};
    EXPECT_EQ(reading.timestamp_ns, 5);
  }
}

TEST(Mpu9250Test, DecodesKnownBytesAtRestFacingForward) {
  // ±4 g, ±500 deg/s: 8192 counts per g, 65.5 per deg/s.
  const estimation::ImuReading reading =
      DecodeMpu9250Burst(Burst({819, -1638, 8192, 0, 655, -1310, 131}), Mpu9250Config{}, 1'000);
  EXPECT_NEAR(reading.accel_g[0], 0.1f, 1e-4f);
  EXPECT_NEAR(reading.accel_g[1], -0.2f, 1e-4f);
  EXPECT_FLOAT_EQ(reading.accel_g[2], 1.0f);
  EXPECT_FLOAT_EQ(reading.gyro_dps[0], 10.0f);
  EXPECT_FLOAT_EQ(reading.gyro_dps[1], -20.0f);
  EXPECT_FLOAT_EQ(reading.gyro_dps[2], 2.0f);
}

TEST(Mpu9250Test, MapsARotatedChipToTheBodyFrame) {
  // The chip turned 90 degrees clockwise seen from above: its x arrow points
  // to the robot's right (-y), its y arrow forward (+x).
  Mpu9250Config config;
  config.body_from_chip = {{{1, 1}, {0, -1}, {2, 1}}};
  // The robot accelerates forward (0.5 g) and turns left (+20 deg/s about z).
  const estimation::ImuReading reading = DecodeMpu9250Burst(Burst({0, 4096, 8192, 0, 0, 0, 1310}), config, 0);
  EXPECT_FLOAT_EQ(reading.accel_g[0], 0.5f);
  EXPECT_FLOAT_EQ(reading.accel_g[1], 0.0f);
  EXPECT_FLOAT_EQ(reading.accel_g[2], 1.0f);
  EXPECT_FLOAT_EQ(reading.gyro_dps[2], 20.0f);
}

TEST(Mpu9250Test, ReadDecodesTheRegisters) {
  FakeI2c bus;
  FakeDelay delay;
  bus.registers[mpu9250::kWhoAmI] = mpu9250::kWhoAmIValue;
  Mpu9250 imu(bus, delay, Mpu9250Config{});
  ASSERT_EQ(imu.Start(), DriverError::kOk);
  const auto burst = Burst({0, 0, 8192, 0, 0, 0, -655});
  std::copy(burst.begin(), burst.end(), bus.registers.begin() + mpu9250::kAccelXoutHigh);

  const auto reading = imu.Read(123'000);
  ASSERT_TRUE(reading.ok());
  EXPECT_EQ(reading.value().timestamp_ns, 123'000);
  EXPECT_FLOAT_EQ(reading.value().accel_g[2], 1.0f);
  EXPECT_FLOAT_EQ(reading.value().gyro_dps[2], -10.0f);

  bus.fail_with = BusStatus::kTimeout;
  EXPECT_EQ(imu.Read(124'000).error(), DriverError::kBus);
  EXPECT_EQ(imu.last_bus_status(), BusStatus::kTimeout);
}

}  // namespace
}  // namespace syrof::firmware::drivers
