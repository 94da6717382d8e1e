#pragma once
// What the four volume readers' fuzz targets share (lib/volume/): the input is written to a file
// with the reader's extension and read with a 1 MiB budget.  Any input gives a volume whose
// samples match its dims and whose geometry is finite and axis-aligned, or one VolumeFileError
// line naming the file; never a crash, a hang or a leak.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "lib/volume/volume.h"
#include "tests/fuzz/fuzz_limits.h"

namespace vrv::fuzz {

inline constexpr std::int64_t kVolumeBudget = std::int64_t{1} << 20;

inline void check_volume(const Volume& v) {
  if (v.count() != static_cast<std::size_t>(v.dims[0]) * v.dims[1] * v.dims[2]) std::abort();
  if (!v.origin.allFinite() || !v.spacing.allFinite() || !(v.spacing.minCoeff() > 0)) std::abort();
  bool seen[3] = {false, false, false};
  for (int a = 0; a < 3; ++a) {
    if (v.axis[a] < 0 || v.axis[a] > 2 || seen[v.axis[a]] || (v.sign[a] != 1 && v.sign[a] != -1)) std::abort();
    seen[v.axis[a]] = true;
  }
}

template <class Read>
int fuzz_volume_reader(const std::uint8_t* data, std::size_t size, const char* extension, Read read) {
  if (size > kMaxInputBytes) return -1;
  static const std::filesystem::path dir = [] {
    const auto d = scratch_root() / ("vrv-fuzz-volume-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  const auto file = dir / (std::string("volume") + extension);
  std::ofstream(file, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  try {
    check_volume(read(file, VolumeReadOptions{kVolumeBudget}));
  } catch (const VolumeFileError& e) {
    const std::string msg = e.what();
    if (msg.rfind(file.string() + ": ", 0) != 0 || msg.find('\n') != std::string::npos || msg.size() > 2000) {
      std::fprintf(stderr, "not one line naming the file: %s\n", msg.c_str());
      std::abort();
    }
  }
  return 0;
}

}  // namespace vrv::fuzz
