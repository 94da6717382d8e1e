// Fuzz target: the NRRD reader (lib/volume/nrrd_reader), through a .nrrd file
// (tests/fuzz/volume_fuzz.h says what every input must give).
#include <cstddef>
#include <cstdint>

#include "lib/io/image_module.h"
#include "lib/volume/nrrd_reader.h"
#include "tests/fuzz/volume_fuzz.h"

// Teem 1.12 (Debian's libteem) leaks on some refusals, inside the library: its gzip state
// (_nrrdGzOpen, ~56 KB) when gzip data are damaged, and an airArray (~4 KB) when the magic line's
// version is malformed ("NRRD000N").  A leak per refused file, not a crash (docs/robustness.md);
// the refusal itself is still checked.  LeakSanitizer's suppressions, these among them, are
// defined once for every sanitized process, in lib/io/image_module.cpp; taking the address of a
// function of that file links it in, whether or not the reader's objects need it (in a unity
// build they do, and a second definition here would clash).
[[maybe_unused]] __attribute__((used)) static const void* const kLinkLeakSuppressions =
    reinterpret_cast<const void*>(&vrv::image_module::functions);

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return vrv::fuzz::fuzz_volume_reader(data, size, ".nrrd", [](const auto& file, const auto& options) {
    return vrv::read_nrrd(file, options);
  });
}
