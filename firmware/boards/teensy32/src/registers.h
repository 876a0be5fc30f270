// MK20DX256 peripheral registers the board uses: addresses and bits from the
// K20 (72 MHz) reference manual, only what this board touches. Private to
// the board's sources.
#pragma once

#include <cstdint>

namespace syrof::board::teensy32::reg {

template <typename T>
inline volatile T& At(uintptr_t address) {
  return *reinterpret_cast<volatile T*>(address);
}
inline volatile uint8_t& R8(uintptr_t address) { return At<uint8_t>(address); }
inline volatile uint16_t& R16(uintptr_t address) { return At<uint16_t>(address); }
inline volatile uint32_t& R32(uintptr_t address) { return At<uint32_t>(address); }

// Watchdog.
inline constexpr uintptr_t kWdogStctrlh = 0x40052000;
inline constexpr uintptr_t kWdogUnlock = 0x4005200E;
inline constexpr uint16_t kWdogUnlockKey1 = 0xC520;
inline constexpr uint16_t kWdogUnlockKey2 = 0xD928;
inline constexpr uint16_t kWdogAllowUpdate = 1u << 4;  // STCTRLH.ALLOWUPDATE; WDOGEN (bit 0) clear

// System integration module: clock gates and dividers.
inline constexpr uintptr_t kSimScgc4 = 0x40048034;
inline constexpr uintptr_t kSimScgc5 = 0x40048038;
inline constexpr uintptr_t kSimScgc6 = 0x4004803C;
inline constexpr uintptr_t kSimClkdiv1 = 0x40048044;
inline constexpr uint32_t kScgc4I2c0 = 1u << 6;
inline constexpr uint32_t kScgc4Uart0 = 1u << 10;
inline constexpr uint32_t kScgc4Uart1 = 1u << 11;
inline constexpr uint32_t kScgc4Uart2 = 1u << 12;
inline constexpr uint32_t kScgc5PortA = 1u << 9;  // ... PORTE = bit 13
inline constexpr uint32_t kScgc6Spi0 = 1u << 12;

// Oscillator and multipurpose clock generator.
inline constexpr uintptr_t kOsc0Cr = 0x40065000;
inline constexpr uint8_t kOscSc8p = 1u << 1;  // 8 pF load
inline constexpr uint8_t kOscSc2p = 1u << 3;  // 2 pF load
inline constexpr uintptr_t kMcgC1 = 0x40064000;
inline constexpr uintptr_t kMcgC2 = 0x40064001;
inline constexpr uintptr_t kMcgC5 = 0x40064004;
inline constexpr uintptr_t kMcgC6 = 0x40064005;
inline constexpr uintptr_t kMcgS = 0x40064006;
inline constexpr uint8_t kMcgSOscInit = 1u << 1;
inline constexpr uint8_t kMcgSClkstMask = 3u << 2;
inline constexpr uint8_t kMcgSClkstExternal = 2u << 2;
inline constexpr uint8_t kMcgSClkstPll = 3u << 2;
inline constexpr uint8_t kMcgSIrefst = 1u << 4;
inline constexpr uint8_t kMcgSPllst = 1u << 5;
inline constexpr uint8_t kMcgSLock = 1u << 6;

// Port control (pin multiplexing): PORTx_PCRn = base + 0x1000 x port + 4 n.
inline constexpr uintptr_t kPortABase = 0x40049000;
inline constexpr uint32_t kPcrPullSelectUp = 1u << 0;  // PS
inline constexpr uint32_t kPcrPullEnable = 1u << 1;    // PE
inline constexpr uint32_t kPcrOpenDrain = 1u << 5;     // ODE
inline constexpr uint32_t kPcrDriveStrength = 1u << 6; // DSE
inline constexpr uint32_t PcrMux(uint32_t alternative) { return (alternative & 7u) << 8; }
// GPIO: GPIOx base = 0x400FF000 + 0x40 x port; PSOR +4, PCOR +8, PDIR +0x10, PDDR +0x14.
inline constexpr uintptr_t kGpioABase = 0x400FF000;

// UARTs (8-bit registers).
inline constexpr uintptr_t kUart0Base = 0x4006A000;
inline constexpr uintptr_t kUart1Base = 0x4006B000;
inline constexpr uintptr_t kUart2Base = 0x4006C000;
inline constexpr uintptr_t kUartBdh = 0x00, kUartBdl = 0x01, kUartC1 = 0x02, kUartC2 = 0x03, kUartS1 = 0x04,
                           kUartD = 0x07, kUartC4 = 0x0A;
inline constexpr uint8_t kUartC2Re = 1u << 2, kUartC2Te = 1u << 3, kUartC2Rie = 1u << 5, kUartC2Tie = 1u << 7;
inline constexpr uint8_t kUartS1Or = 1u << 3, kUartS1Rdrf = 1u << 5, kUartS1Tdre = 1u << 7;

// I2C0 (8-bit registers).
inline constexpr uintptr_t kI2c0Base = 0x40066000;
inline constexpr uintptr_t kI2cF = 0x01, kI2cC1 = 0x02, kI2cS = 0x03, kI2cD = 0x04;
inline constexpr uint8_t kI2cC1Iicen = 1u << 7, kI2cC1Mst = 1u << 5, kI2cC1Tx = 1u << 4, kI2cC1Txak = 1u << 3,
                         kI2cC1Rsta = 1u << 2;
inline constexpr uint8_t kI2cSRxak = 1u << 0, kI2cSIicif = 1u << 1, kI2cSArbl = 1u << 4, kI2cSBusy = 1u << 5;

// SPI0 (32-bit registers).
inline constexpr uintptr_t kSpi0Base = 0x4002C000;
inline constexpr uintptr_t kSpiMcr = 0x00, kSpiCtar0 = 0x0C, kSpiSr = 0x2C, kSpiPushr = 0x34, kSpiPopr = 0x38;
inline constexpr uint32_t kSpiMcrMstr = 1u << 31, kSpiMcrClrTxf = 1u << 11, kSpiMcrClrRxf = 1u << 10,
                          kSpiMcrHalt = 1u << 0, kSpiMcrPcsisAll = 0x1Fu << 16;
inline constexpr uint32_t kSpiSrTcf = 1u << 31, kSpiSrTfff = 1u << 25, kSpiSrRfdf = 1u << 17,
                          kSpiSrRfof = 1u << 19, kSpiSrTfuf = 1u << 27, kSpiSrEoqf = 1u << 28;
inline constexpr uint32_t kSpiCtarCpol = 1u << 26, kSpiCtarCpha = 1u << 25, kSpiCtarDbr = 1u << 31;
inline constexpr uint32_t SpiCtarFrameSize(uint32_t bits) { return (bits - 1) << 27; }

// Cortex-M4 system control space.
inline constexpr uintptr_t kSystCsr = 0xE000E010, kSystRvr = 0xE000E014, kSystCvr = 0xE000E018;
inline constexpr uintptr_t kNvicIser = 0xE000E100;  // + 4 x (irq / 32)
inline constexpr uintptr_t kNvicIpr = 0xE000E400;   // one byte per irq
inline constexpr uintptr_t kScbShpr3 = 0xE000ED20;  // SysTick priority in bits 31..24

// Interrupt numbers (vector index - 16) of the MK20DX256 (the 72 MHz K20's
// 95-entry map; the 50 MHz MK20DX128's shorter map numbers them 16 and 20).
inline constexpr int kIrqUart0Status = 45;
inline constexpr int kIrqUart2Status = 49;
inline constexpr int kIrqDmaChannel0 = 0;  // channels 0..15 are interrupts 0..15
inline constexpr int kIrqPit0 = 68;        // PIT channels 0..3 are interrupts 68..71

inline void EnableIrq(int irq, uint8_t level) {
  R8(kNvicIpr + static_cast<uintptr_t>(irq)) = static_cast<uint8_t>(level << 4);  // 4 priority bits
  R32(kNvicIser + 4u * static_cast<uintptr_t>(irq / 32)) = 1u << (irq % 32);
}

}  // namespace syrof::board::teensy32::reg
