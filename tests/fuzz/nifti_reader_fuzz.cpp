// Fuzz target: the NIfTI reader (lib/volume/nifti_reader), through a .nii file
// (tests/fuzz/volume_fuzz.h says what every input must give).
#include <cstddef>
#include <cstdint>

#include "lib/volume/nifti_reader.h"
#include "tests/fuzz/volume_fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return vrv::fuzz::fuzz_volume_reader(data, size, ".nii", [](const auto& file, const auto& options) {
    return vrv::read_nifti(file, options);
  });
}
