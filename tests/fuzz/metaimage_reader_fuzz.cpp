// Fuzz target: the MetaImage reader (lib/volume/metaimage_reader), through a .mha file
// (tests/fuzz/volume_fuzz.h says what every input must give).
#include <cstddef>
#include <cstdint>

#include "lib/volume/metaimage_reader.h"
#include "tests/fuzz/volume_fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return vrv::fuzz::fuzz_volume_reader(data, size, ".mha", [](const auto& file, const auto& options) {
    return vrv::read_metaimage(file, options);
  });
}
