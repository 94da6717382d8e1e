// Fuzz target: the VTK XML image data reader (lib/volume/vti_reader), through a .vti file
// (tests/fuzz/volume_fuzz.h says what every input must give).
#include <cstddef>
#include <cstdint>

#include "lib/volume/vti_reader.h"
#include "tests/fuzz/volume_fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return vrv::fuzz::fuzz_volume_reader(data, size, ".vti", [](const auto& file, const auto& options) {
    return vrv::read_vti(file, options);
  });
}
