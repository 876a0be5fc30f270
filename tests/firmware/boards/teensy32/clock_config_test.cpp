// The numbers the Teensy 3.2 board writes into the MK20DX256's clock, UART,
// I2C and SPI registers, checked against the rates they must produce.
#include "syrof/board/teensy32/clock_config.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "syrof/board/teensy32/pins.h"

namespace syrof::board::teensy32 {
namespace {

TEST(Teensy32ClockTest, PllGivesCoreBusAndFlashClocks) {
  EXPECT_EQ(kPllReferenceHz, 2'000'000u);
  EXPECT_EQ(kCoreHz, 72'000'000u);
  EXPECT_EQ(kBusHz, 36'000'000u);
  EXPECT_EQ(kFlashHz, 24'000'000u);
}

TEST(Teensy32ClockTest, McgAndSimRegisterValues) {
  EXPECT_EQ(kMcgSettings.c2, 0x24);      // RANGE0 = 2 (very high), EREFS0 = 1
  EXPECT_EQ(kMcgSettings.c1_fbe, 0xA0);  // CLKS = 2 (external), FRDIV = 4 (/512)
  EXPECT_EQ(kMcgSettings.c5, 0x07);      // PRDIV0: /8
  EXPECT_EQ(kMcgSettings.c6, 0x4C);      // PLLS, VDIV0 = 12: x36
  EXPECT_EQ(kMcgSettings.c1_pee, 0x20);  // CLKS = 0 (PLL), FRDIV kept
  EXPECT_EQ(kMcgSettings.clkdiv1, 0x01020000u);  // OUTDIV1 0, OUTDIV2 1, OUTDIV4 2
}

TEST(Teensy32ClockTest, RadioUartIsExactlyOneMegabaudFromTheCoreClock) {
  const UartDivider divider = UartDividerFor(kCoreHz, 1'000'000);
  EXPECT_EQ(divider.sbr, 4);
  EXPECT_EQ(divider.brfa, 16);  // 4.5 x 16 = 72
  EXPECT_EQ(UartMillibaud(kCoreHz, divider), 1'000'000'000u);
}

TEST(Teensy32ClockTest, ConsoleUartIsExactly115200FromTheBusClock) {
  const UartDivider divider = UartDividerFor(kBusHz, 115'200);
  EXPECT_EQ(divider.sbr, 19);
  EXPECT_EQ(divider.brfa, 17);  // 19 + 17/32 = 19.53125 = 36 MHz / (16 x 115200)
  EXPECT_EQ(UartMillibaud(kBusHz, divider), 115'200'000u);
}

TEST(Teensy32ClockTest, UartRefusesRatesOutOfReach) {
  EXPECT_EQ(UartDividerFor(kBusHz, 4'000'000).sbr, 0);  // below SBR 1
  EXPECT_EQ(UartDividerFor(kCoreHz, 300).sbr, 0);       // above SBR 8191
}

TEST(Teensy32ClockTest, I2cPicksTheFastestSclNotAboveTheLimit) {
  const uint8_t icr = I2cIcrFor(kBusHz, 400'000);
  EXPECT_EQ(icr, 0x19);  // divider 96: 375 kHz; 88 (ICR 0x15) would be 409 kHz
  EXPECT_EQ(kI2cSclDividers[icr], 96);
  EXPECT_LE(kBusHz / kI2cSclDividers[icr], 400'000u);
  EXPECT_EQ(kI2cSclDividers[I2cIcrFor(kBusHz, 100'000)], 384);  // 93.75 kHz
  EXPECT_EQ(I2cIcrFor(kBusHz, 1'000), 0x3F);                    // slower than any: the slowest
}

TEST(Teensy32ClockTest, SpiClocksForTheFlowSensorAndTheUwbRadio) {
  const SpiBaud flow = SpiBaudFor(kBusHz, 2'000'000);  // PMW3901: at most 2 MHz
  EXPECT_EQ(flow.sck_hz, 2'000'000u);
  const SpiBaud uwb_fast = SpiBaudFor(kBusHz, 20'000'000);  // DWM1000 after its PLL locks
  EXPECT_EQ(uwb_fast.sck_hz, 18'000'000u);
  EXPECT_TRUE(uwb_fast.dbr);
  EXPECT_EQ(uwb_fast.pbr, 0);  // DBR only with the /2 prescaler (50% duty cycle)
  EXPECT_EQ(SpiBaudFor(kBusHz, 100).sck_hz, 0u);  // slowest: 36 MHz / (7 x 32768) = 157 Hz
}

TEST(Teensy32ClockTest, SysTickReloadIsOneMillisecond) { EXPECT_EQ(SysTickReload(kCoreHz, 1000), 71'999u); }

TEST(Teensy32PinsTest, NoPinIsUsedTwice) {
  for (size_t a = 0; a < kPins.size(); ++a) {
    for (size_t b = a + 1; b < kPins.size(); ++b) {
      EXPECT_FALSE(kPins[a].port == kPins[b].port && kPins[a].bit == kPins[b].bit)
          << kPins[a].signal << " and " << kPins[b].signal;
      EXPECT_NE(kPins[a].teensy_pin, kPins[b].teensy_pin) << kPins[a].signal << " and " << kPins[b].signal;
    }
  }
}

// docs/firmware.md's "Teensy 3.2 board" section shows the pin table; one row
// per entry of kPins, in the same words.
TEST(Teensy32PinsTest, DocsShowThePinTable) {
  std::ifstream file(SYROF_SOURCE_DIR "/docs/firmware.md");
  ASSERT_TRUE(file.is_open()) << "cannot open " SYROF_SOURCE_DIR "/docs/firmware.md";
  std::stringstream text;
  text << file.rdbuf();
  const std::string doc = text.str();
  for (const PinAssignment& pin : kPins) {
    const std::string row = "| " + std::string(pin.signal) + " | " + std::to_string(pin.teensy_pin) + " | PT" +
                            PortLetter(pin.port) + std::to_string(pin.bit) + " | " + std::to_string(pin.mux) + " | " +
                            std::string(pin.function) + " |";
    EXPECT_NE(doc.find(row), std::string::npos) << "docs/firmware.md lacks the row\n" << row;
  }
}

}  // namespace
}  // namespace syrof::board::teensy32
