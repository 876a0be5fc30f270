// The Teensy 3.2's pin map: which MK20DX256 port pin each robot signal uses
// and which multiplexer alternative (PORTx_PCRn.MUX) selects its function.
// One table for the board code and for docs/firmware.md ("Teensy 3.2
// board"), which a host test compares with this one.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace syrof::board::teensy32 {

enum class Port : uint8_t { kA, kB, kC, kD, kE };

/// PORTx_PCRn.MUX values used here (K20 signal multiplexing table).
inline constexpr uint8_t kMuxGpio = 1;

struct PinAssignment {
  std::string_view signal;   ///< what the robot uses it for
  uint8_t teensy_pin;        ///< the number printed on the Teensy 3.2
  Port port;
  uint8_t bit;               ///< n in PTxn
  uint8_t mux;               ///< PCR.MUX alternative
  std::string_view function; ///< the MK20's name for that alternative
};

// Indices into kPins, for the board code.
enum PinIndex : uint8_t {
  kRadioRx,
  kRadioTx,
  kConsoleRx,
  kConsoleTx,
  kI2cScl,
  kI2cSda,
  kImuInterrupt,
  kSpiSck,
  kSpiMosi,
  kSpiMiso,
  kFlowChipSelect,
  kUwbChipSelect,
  kUwbInterrupt,
  kUwbReset,
  kPinCount,
};

inline constexpr std::array<PinAssignment, kPinCount> kPins{{
    {"nRF51822 radio link, M4 receives", 0, Port::kB, 16, 3, "UART0_RX"},
    {"nRF51822 radio link, M4 sends", 1, Port::kB, 17, 3, "UART0_TX"},
    {"debug console, M4 receives", 7, Port::kD, 2, 3, "UART2_RX"},
    {"debug console, M4 sends", 8, Port::kD, 3, 3, "UART2_TX"},
    {"I2C SCL (MPU-9250)", 19, Port::kB, 2, 2, "I2C0_SCL"},
    {"I2C SDA (MPU-9250)", 18, Port::kB, 3, 2, "I2C0_SDA"},
    {"MPU-9250 INT (data ready)", 2, Port::kD, 0, kMuxGpio, "PTD0"},
    {"SPI SCK", 13, Port::kC, 5, 2, "SPI0_SCK"},
    {"SPI MOSI", 11, Port::kC, 6, 2, "SPI0_SOUT"},
    {"SPI MISO", 12, Port::kC, 7, 2, "SPI0_SIN"},
    {"PMW3901 chip select", 10, Port::kC, 4, kMuxGpio, "PTC4"},
    {"DWM1000 chip select", 15, Port::kC, 0, kMuxGpio, "PTC0"},
    {"DWM1000 IRQ", 14, Port::kD, 1, kMuxGpio, "PTD1"},
    {"DWM1000 RSTn", 16, Port::kB, 0, kMuxGpio, "PTB0"},
}};

constexpr char PortLetter(Port port) { return static_cast<char>('A' + static_cast<int>(port)); }

}  // namespace syrof::board::teensy32
