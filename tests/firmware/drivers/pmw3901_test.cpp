// The PMW3901 driver against a fake SPI device: the start-up, the motion
// burst's decoding and axis mapping, the quality gate, and the intervals.
#include "syrof/firmware/drivers/pmw3901.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

namespace syrof::firmware::drivers {
namespace {

// A PMW3901 on SPI: the first byte after Select() is an address (bit 7 set
// for a write); a read's data comes in the next transfer.
class FakeSpi : public SpiBus {
 public:
  std::array<uint8_t, 128> registers{};
  std::array<uint8_t, pmw3901::kBurstBytes> burst{};
  std::vector<RegisterWrite> writes;  // wait_us unused
  std::vector<uint8_t> reads;
  int selected = 0;
  BusStatus fail_with = BusStatus::kOk;

  void Select() override {
    ++selected;
    address_known_ = false;
  }
  void Deselect() override { --selected; }
  BusStatus Transfer(std::span<const uint8_t> out, std::span<uint8_t> in) override {
    EXPECT_EQ(selected, 1) << "transfer outside a selection";
    if (fail_with != BusStatus::kOk) return fail_with;
    if (!address_known_) {
      address_ = out[0];
      address_known_ = true;
      if (address_ & pmw3901::kWriteBit) {
        const auto reg = static_cast<uint8_t>(address_ & 0x7F);
        registers[reg] = out[1];
        writes.push_back({reg, out[1], 0});
      } else {
        reads.push_back(address_);
      }
      return BusStatus::kOk;
    }
    for (size_t i = 0; i < in.size(); ++i) {
      in[i] = address_ == pmw3901::kMotionBurst ? burst[i] : registers[address_];
    }
    return BusStatus::kOk;
  }

 private:
  uint8_t address_ = 0;
  bool address_known_ = false;
};

class RecordingDelay : public Delay {
 public:
  std::vector<uint32_t> waits;
  void WaitUs(uint32_t microseconds) override { waits.push_back(microseconds); }
};

std::array<uint8_t, pmw3901::kBurstBytes> Burst(int16_t delta_x, int16_t delta_y, uint8_t squal, uint16_t shutter) {
  const auto x = static_cast<uint16_t>(delta_x);
  const auto y = static_cast<uint16_t>(delta_y);
  return {pmw3901::kMotionOccurred, 0,     static_cast<uint8_t>(x & 0xFF), static_cast<uint8_t>(x >> 8),
          static_cast<uint8_t>(y & 0xFF), static_cast<uint8_t>(y >> 8), squal, 0x40, 0x80, 0x10,
          static_cast<uint8_t>(shutter >> 8), static_cast<uint8_t>(shutter & 0xFF)};
}

FakeSpi SensorPresent() {
  FakeSpi bus;
  bus.registers[pmw3901::kProductId] = pmw3901::kProductIdValue;
  bus.registers[pmw3901::kInverseProductId] = pmw3901::kInverseProductIdValue;
  return bus;
}

TEST(Pmw3901Test, ParsesTheBurstLittleEndianDeltasAndBigEndianShutter) {
  const pmw3901::MotionBurst burst = pmw3901::ParseMotionBurst(Burst(5, -3, 0x50, 0x0123));
  EXPECT_EQ(burst.motion, pmw3901::kMotionOccurred);
  EXPECT_EQ(burst.delta_x, 5);
  EXPECT_EQ(burst.delta_y, -3);
  EXPECT_EQ(burst.squal, 0x50);
  EXPECT_EQ(burst.shutter, 0x0123);
}

TEST(Pmw3901Test, StartResetsChecksIdentityAndWritesTheTuning) {
  FakeSpi bus = SensorPresent();
  RecordingDelay delay;
  const RegisterWrite tuning[] = {{0x7F, 0x00, 0}, {0x61, 0xAD, 0}, {0x7F, 0x03, 10}};
  Pmw3901Config config;
  config.tuning = tuning;
  Pmw3901 flow(bus, delay, config);

  ASSERT_EQ(flow.Start(0), DriverError::kOk);

  ASSERT_EQ(bus.writes.size(), 4u);
  EXPECT_EQ(bus.writes[0], (RegisterWrite{pmw3901::kPowerUpReset, pmw3901::kPowerUpResetValue, 0}));
  EXPECT_EQ(bus.writes[3], (RegisterWrite{0x7F, 0x03, 0}));
  EXPECT_EQ(bus.reads, (std::vector<uint8_t>{0x00, 0x5F, 0x02, 0x03, 0x04, 0x05, 0x06}));
  EXPECT_EQ(delay.waits.front(), pmw3901::kResetWaitUs);
  EXPECT_EQ(delay.waits.back(), 10u);
  EXPECT_EQ(bus.selected, 0);
}

TEST(Pmw3901Test, WrongIdentityIsReported) {
  FakeSpi bus;
  bus.registers[pmw3901::kProductId] = pmw3901::kProductIdValue;  // the inverse reads 0
  RecordingDelay delay;
  Pmw3901 flow(bus, delay, Pmw3901Config{});
  EXPECT_EQ(flow.Start(0), DriverError::kWrongDevice);
  EXPECT_EQ(flow.Read(1).error(), DriverError::kNotStarted);
}

TEST(Pmw3901Test, BusFailureReleasesChipSelect) {
  FakeSpi bus = SensorPresent();
  bus.fail_with = BusStatus::kError;
  RecordingDelay delay;
  Pmw3901 flow(bus, delay, Pmw3901Config{});
  EXPECT_EQ(flow.Start(0), DriverError::kBus);
  EXPECT_EQ(flow.last_bus_status(), BusStatus::kError);
  EXPECT_EQ(bus.selected, 0);
}

TEST(Pmw3901Test, DecodesIntoTheBodyFrame) {
  const auto reading = DecodePmw3901Burst(Burst(5, -3, 0x50, 0x0100), Pmw3901Config{}, 40'000'000, 20'000'000);
  ASSERT_TRUE(reading.ok());
  EXPECT_EQ(reading.value().timestamp_ns, 40'000'000);
  EXPECT_EQ(reading.value().interval_ns, 20'000'000u);
  EXPECT_EQ(reading.value().delta_x_px, 5);
  EXPECT_EQ(reading.value().delta_y_px, -3);

  // Mounted turned: body x is the sensor's -y, body y its x.
  Pmw3901Config turned;
  turned.body_from_sensor = {{{1, -1}, {0, 1}}};
  const auto mapped = DecodePmw3901Burst(Burst(5, -3, 0x50, 0x0100), turned, 0, 1);
  ASSERT_TRUE(mapped.ok());
  EXPECT_EQ(mapped.value().delta_x_px, 3);
  EXPECT_EQ(mapped.value().delta_y_px, 5);

  // -(-32768) does not fit an int16: it saturates.
  const auto saturated = DecodePmw3901Burst(Burst(0, -32768, 0x50, 0x0100), turned, 0, 1);
  ASSERT_TRUE(saturated.ok());
  EXPECT_EQ(saturated.value().delta_x_px, 32767);
}

TEST(Pmw3901Test, GatesDarkFeaturelessBursts) {
  const Pmw3901Config config;
  EXPECT_EQ(DecodePmw3901Burst(Burst(9, 9, 0x18, 0x1F00), config, 0, 1).error(), DriverError::kLowQuality);
  EXPECT_EQ(DecodePmw3901Burst(Burst(9, 9, 0x00, 0xFFFF), config, 0, 1).error(), DriverError::kLowQuality);
  // Either condition alone is not enough (the datasheet's rule is both).
  EXPECT_TRUE(DecodePmw3901Burst(Burst(9, 9, 0x18, 0x1EFF), config, 0, 1).ok());
  EXPECT_TRUE(DecodePmw3901Burst(Burst(9, 9, 0x19, 0x1FFF), config, 0, 1).ok());
}

TEST(Pmw3901Test, ReadCoversTheIntervalSinceThePreviousRead) {
  FakeSpi bus = SensorPresent();
  RecordingDelay delay;
  Pmw3901 flow(bus, delay, Pmw3901Config{});
  ASSERT_EQ(flow.Start(1'000), DriverError::kOk);

  bus.burst = Burst(4, 0, 0x60, 0x0200);
  delay.waits.clear();
  const auto first = flow.Read(20'001'000);
  ASSERT_TRUE(first.ok());
  EXPECT_EQ(first.value().interval_ns, 20'000'000u);
  EXPECT_EQ(first.value().delta_x_px, 4);
  EXPECT_EQ(delay.waits, std::vector<uint32_t>{pmw3901::kReadWaitUs});

  bus.burst = Burst(4, 0, 0x02, 0x1FFF);  // lens covered
  EXPECT_EQ(flow.Read(40'001'000).error(), DriverError::kLowQuality);

  bus.burst = Burst(-2, 1, 0x60, 0x0200);
  const auto third = flow.Read(60'001'000);
  ASSERT_TRUE(third.ok());
  EXPECT_EQ(third.value().interval_ns, 20'000'000u);  // from the rejected burst, whose counts were cleared
  EXPECT_EQ(third.value().delta_x_px, -2);

  EXPECT_EQ(flow.Read(60'001'000).error(), DriverError::kBadTimestamp);
  EXPECT_EQ(flow.Read(60'001'000 + 5'000'000'000).error(), DriverError::kBadTimestamp);
}

}  // namespace
}  // namespace syrof::firmware::drivers
