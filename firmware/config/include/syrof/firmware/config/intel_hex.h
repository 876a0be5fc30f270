// Intel HEX, as teensy-loader-cli flashes it: data records (type 00) of up
// to 16 bytes, an extended linear address record (04) before the first
// record and wherever the upper 16 address bits change, the start address
// when given (03 when it fits in 20 bits, as objcopy writes it, else 05), and
// the end of file (01); each line's checksum is
// the two's complement of its bytes' sum. Lines end with "\r\n", as objcopy
// writes them. The data records are objcopy's (`objcopy -O ihex` of the
// same ELF gives the same bytes at the same addresses, and the same lines
// but for the address records: objcopy writes 02 below 1 MB, this 04).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "syrof/firmware/config/elf_file.h"

namespace syrof::firmware::config {

/// The records of `chunks` (their ranges must not overlap nor pass 4 GiB),
/// then the start address and the end record.
std::string WriteIntelHex(std::span<const LoadChunk> chunks, std::optional<uint32_t> start_address);

}  // namespace syrof::firmware::config
