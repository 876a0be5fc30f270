// The Teensy 3.2's clock tree and the peripheral dividers derived from it,
// as compile-time arithmetic (no register access), so the host tests check
// every number the board writes into the MK20DX256's registers.
//
// Clock tree (K20 reference manual, MCG and SIM chapters):
//   16 MHz crystal -> OSC0 -> MCG PLL: / (PRDIV0 + 1) = 2 MHz reference
//   (the PLL accepts 2..4 MHz), x (VDIV0 + 24) = 72 MHz (MCGOUTCLK)
//   MCGOUTCLK / (OUTDIV1 + 1) = 72 MHz core and system clock
//   MCGOUTCLK / (OUTDIV2 + 1) = 36 MHz bus clock (limit 50 MHz)
//   MCGOUTCLK / (OUTDIV4 + 1) = 24 MHz flash clock (limit 25 MHz)
// UART0 and UART1 run from the system clock, UART2, I2C0 and SPI0 from the
// bus clock.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace syrof::board::teensy32 {

inline constexpr uint32_t kCrystalHz = 16'000'000;

/// MCG_C5.PRDIV0 and MCG_C6.VDIV0: the PLL's input divider and multiplier.
inline constexpr uint8_t kPllInputDivider = 8;    // PRDIV0 = 7
inline constexpr uint8_t kPllMultiplier = 36;     // VDIV0 = 12 (the field adds 24)
inline constexpr uint32_t kPllReferenceHz = kCrystalHz / kPllInputDivider;
inline constexpr uint32_t kPllOutputHz = kPllReferenceHz * kPllMultiplier;

/// SIM_CLKDIV1's dividers (the register fields hold divider - 1).
inline constexpr uint8_t kCoreDivider = 1;   // OUTDIV1
inline constexpr uint8_t kBusDivider = 2;    // OUTDIV2
inline constexpr uint8_t kFlashDivider = 3;  // OUTDIV4

inline constexpr uint32_t kCoreHz = kPllOutputHz / kCoreDivider;
inline constexpr uint32_t kBusHz = kPllOutputHz / kBusDivider;
inline constexpr uint32_t kFlashHz = kPllOutputHz / kFlashDivider;

static_assert(kPllReferenceHz >= 2'000'000 && kPllReferenceHz <= 4'000'000, "PLL reference out of 2..4 MHz");
static_assert(kPllMultiplier >= 24 && kPllMultiplier <= 55, "VDIV0 encodes 24..55");
static_assert(kCoreHz == 72'000'000, "the MK20DX256VLH7 runs at 72 MHz");
static_assert(kBusHz <= 50'000'000, "bus clock above the chip's 50 MHz");
static_assert(kFlashHz <= 25'000'000, "flash clock above the chip's 25 MHz");

/// The register values of the clock switch, one definition for the startup
/// code and the tests.
struct McgSettings {
  uint8_t c2;        ///< RANGE0 = very high (8..32 MHz crystal), EREFS0 = crystal
  uint8_t c1_fbe;    ///< CLKS = external reference, FRDIV = /512, IREFS = 0
  uint8_t c5;        ///< PRDIV0
  uint8_t c6;        ///< PLLS | VDIV0
  uint8_t c1_pee;    ///< CLKS = PLL output (FLL/PLL), FRDIV kept
  uint32_t clkdiv1;  ///< SIM_CLKDIV1: OUTDIV1, OUTDIV2, OUTDIV4
};

inline constexpr McgSettings kMcgSettings{
    .c2 = (2u << 4) | (1u << 2),
    .c1_fbe = (2u << 6) | (4u << 3),
    .c5 = static_cast<uint8_t>(kPllInputDivider - 1),
    .c6 = static_cast<uint8_t>((1u << 6) | (kPllMultiplier - 24)),
    .c1_pee = (0u << 6) | (4u << 3),
    .clkdiv1 = (static_cast<uint32_t>(kCoreDivider - 1) << 28) | (static_cast<uint32_t>(kBusDivider - 1) << 24) |
               (static_cast<uint32_t>(kFlashDivider - 1) << 16),
};

// FRDIV = /512 on a very-high-range crystal: 16 MHz / 512 = 31.25 kHz, the
// FLL's 31.25..39.0625 kHz input range, in case the FLL is ever selected.
static_assert(kCrystalHz / 512 >= 31'250 && kCrystalHz / 512 <= 39'063);

/// A UART's baud-rate divider: baud = clock / (16 x (SBR + BRFA / 32)).
struct UartDivider {
  uint16_t sbr;  ///< 13 bits (UART_BDH[4:0], UART_BDL)
  uint8_t brfa;  ///< 5 bits (UART_C4[4:0])
};

/// The divider nearest to `baud`; sbr is 0 when the baud rate cannot be
/// reached (sbr must be 1..8191).
constexpr UartDivider UartDividerFor(uint32_t clock_hz, uint32_t baud) {
  // In 32nds: clock * 2 / baud = 32 x (clock / (16 baud)), rounded.
  const uint64_t thirty_seconds = (static_cast<uint64_t>(clock_hz) * 2 + baud / 2) / baud;
  const uint64_t sbr = thirty_seconds / 32;
  if (sbr < 1 || sbr > 8191) return {0, 0};
  return {static_cast<uint16_t>(sbr), static_cast<uint8_t>(thirty_seconds % 32)};
}

/// The baud rate a divider produces, in millibaud (for error checks).
constexpr uint64_t UartMillibaud(uint32_t clock_hz, UartDivider divider) {
  const uint64_t thirty_seconds = static_cast<uint64_t>(divider.sbr) * 32 + divider.brfa;
  return thirty_seconds == 0 ? 0 : static_cast<uint64_t>(clock_hz) * 2 * 1000 / thirty_seconds;
}

/// The I2C SCL divider of each ICR value (I2C_F[5:0]) with MULT = 1, from
/// the K20 reference manual's I2C divider and hold values table.
inline constexpr std::array<uint16_t, 64> kI2cSclDividers{
    20,   22,   24,   26,   28,   30,   34,   40,   28,   32,   36,   40,   44,   48,   56,   68,
    48,   56,   64,   72,   80,   88,   104,  128,  80,   96,   112,  128,  144,  160,  192,  240,
    160,  192,  224,  256,  288,  320,  384,  480,  320,  384,  448,  512,  576,  640,  768,  960,
    640,  768,  896,  1024, 1152, 1280, 1536, 1920, 1280, 1536, 1792, 2048, 2304, 2560, 3072, 3840};

/// The ICR whose SCL frequency is the fastest not above `scl_hz`; 0x3F
/// (the slowest) when none is that slow.
constexpr uint8_t I2cIcrFor(uint32_t bus_hz, uint32_t scl_hz) {
  int best = -1;
  for (int icr = 0; icr < 64; ++icr) {
    const uint32_t divider = kI2cSclDividers[static_cast<size_t>(icr)];
    if (static_cast<uint64_t>(divider) * scl_hz < bus_hz) continue;  // too fast
    if (best < 0 || divider < kI2cSclDividers[static_cast<size_t>(best)]) best = icr;
  }
  return static_cast<uint8_t>(best < 0 ? 0x3F : best);
}

/// SPI's SCK divider fields in SPIx_CTARn: SCK = bus / PBR x (1 + DBR) / BR.
struct SpiBaud {
  uint8_t pbr;  ///< field value 0..3 for prescalers 2, 3, 5, 7
  uint8_t br;   ///< field value 0..15 for scalers 2, 4, 6, 8, 16 ... 32768
  bool dbr;     ///< double the rate (duty cycle stays 50% only with PBR = 2)
  uint32_t sck_hz;
};

inline constexpr std::array<uint8_t, 4> kSpiPrescalers{2, 3, 5, 7};
inline constexpr std::array<uint16_t, 16> kSpiScalers{2,   4,   6,    8,    16,   32,   64,    128,
                                                      256, 512, 1024, 2048, 4096, 8192, 16384, 32768};

/// The fastest SCK not above `max_hz`; sck_hz is 0 when none is that slow.
constexpr SpiBaud SpiBaudFor(uint32_t bus_hz, uint32_t max_hz) {
  SpiBaud best{0, 0, false, 0};
  for (uint8_t pbr = 0; pbr < kSpiPrescalers.size(); ++pbr) {
    for (uint8_t br = 0; br < kSpiScalers.size(); ++br) {
      for (int dbr = 0; dbr < 2; ++dbr) {
        // DBR keeps a 50% duty cycle only with the /2 prescaler.
        if (dbr == 1 && pbr != 0) continue;
        const uint32_t sck =
            static_cast<uint32_t>(static_cast<uint64_t>(bus_hz) * (1 + dbr) / (kSpiPrescalers[pbr] * kSpiScalers[br]));
        if (sck <= max_hz && sck > best.sck_hz) best = {pbr, br, dbr == 1, sck};
      }
    }
  }
  return best;
}

/// SysTick's reload for one tick of `tick_hz` from the core clock.
constexpr uint32_t SysTickReload(uint32_t core_hz, uint32_t tick_hz) { return core_hz / tick_hz - 1; }

}  // namespace syrof::board::teensy32
