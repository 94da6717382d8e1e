#pragma once
// CRC-64 (ECMA-182 polynomial) of bytes: Boost.CRC, stable across platforms, builds and runs
// (std::hash is not).  What the reference cache's file names and the checksums of caches and
// checkpoints are taken over; it finds damage and edits, not a forger.
#include <cstdint>
#include <string>
#include <string_view>

#include <boost/crc.hpp>
#include <fmt/format.h>

namespace vrv {

// Fed piece by piece (process_bytes), e.g. a file read in chunks.
using Crc64 = boost::crc_optimal<64, 0x42F0E1EBA9EA3693ULL, 0, 0, false, false>;

inline std::uint64_t crc64(std::string_view bytes) {
  Crc64 crc;
  crc.process_bytes(bytes.data(), bytes.size());
  return crc.checksum();
}

// As 16 hex digits.
inline std::string crc64_hex(std::string_view bytes) { return fmt::format("{:016x}", crc64(bytes)); }

}  // namespace vrv
