#pragma once
// The verification tests' toy renderer (tests/lib/toy_raycaster.h, not vrv's raycaster) on a small
// Marschner-Lobb scene, its images written to EXR and read back as a user's files would be, and
// the helpers the tests of lib/verify share.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "lib/io/image_channels.h"
#include "lib/io/image_io.h"
#include "lib/scene_file.h"
#include "lib/verify.h"
#include "tests/lib/toy_raycaster.h"

namespace vrv::verify_toy {

inline constexpr const char* kScene = R"(
[volume]
min = [-1.0, -1.0, -1.0]
max = [1.0, 1.0, 1.0]
[field]
kind = "marschner_lobb"
[transfer]
emission = [[0.0, 0.0], [1.0, 1.0]]
extinction = [[0.0, 0.0], [1.0, 2.0]]
[background]
intensity = 0.2
[camera]
eye = [1.5, 1.0, -4.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 40.0
width = 32
height = 32
)";

inline const std::vector<double> kSteps{0.1, 0.05, 0.025, 0.0125};
inline const std::vector<double> kThreeSteps{0.1, 0.05, 0.025};  // the diagnosis tests' steps

inline std::filesystem::path scratch() {
  const std::filesystem::path d = std::filesystem::path(VRV_BINARY_DIR) / "tests" / "verify_scratch";
  std::filesystem::create_directories(d);
  return d;
}

// A renderer's images at every step (render(h): row-major values), through EXR files.
template <class Render>
std::vector<ImageWithStep> images_through_exr(const Scene& scene, Render render, const std::string& tag) {
  std::vector<ImageWithStep> out;
  for (double h : kSteps) {
    const std::vector<double> v = render(h);
    Image im(scene.camera->width, scene.camera->height);
    std::transform(v.begin(), v.end(), im.pixels.begin(), [](double x) { return static_cast<float>(x); });
    const std::filesystem::path file = scratch() / (tag + "_" + std::to_string(h) + ".exr");
    write_exr(im, file);
    out.push_back({file.string(), h, read_channel_image(file)});
  }
  return out;
}

// An image of one plane per channel (row-major), named `names`.
inline ChannelImage planar_image(int w, int h, const std::vector<std::vector<double>>& planes,
                                 std::vector<std::string> names) {
  ImageF64 image(w, h, 0.0, static_cast<int>(planes.size()));
  for (int c = 0; c < image.channels; ++c)
    for (std::size_t i = 0; i < image.pixel_count(); ++i) image.value(i, c) = planes[c].at(i);
  return ChannelImage(std::move(image), std::move(names));
}

// A renderer's images at every step in double, as in-memory images (no file quantisation).
template <class Render>
std::vector<ImageWithStep> images_in_memory(const Scene& scene, Render render, const std::string& tag,
                                            const std::vector<double>& steps = kSteps) {
  std::vector<ImageWithStep> out;
  for (double h : steps) {
    ChannelImage im(ImageF64(scene.camera->width, scene.camera->height, render(h)));
    im.pixel_type = "double";
    out.push_back({tag + "_" + std::to_string(h), h, std::move(im)});
  }
  return out;
}

// The toy's images at every step, through EXR files.
inline std::vector<ImageWithStep> toy_images(const Scene& scene, toy::Fault fault, const std::string& tag) {
  return images_through_exr(
      scene, [&](double h) { return toy::render(scene, *scene.camera, h, fault, kSteps.front()); }, tag);
}

// A correct toy with its own placement, through EXR files.
inline std::vector<ImageWithStep> toy_images(const Scene& scene, toy::Placement placement, const std::string& tag) {
  return images_through_exr(scene, [&](double h) { return toy::render(scene, *scene.camera, h, placement); }, tag);
}

// Expecting order 2.
inline VerifyOptions options() {
  VerifyOptions o;
  o.expected_order = 2;
  return o;
}

// The report's first fault of `kind`, or nullptr.
inline const Fault* fault_of(const VerifyReport& r, FaultKind kind) {
  for (const Fault& f : r.faults)
    if (f.kind == kind) return &f;
  return nullptr;
}

inline bool has_fault(const VerifyReport& r, FaultKind kind) { return fault_of(r, kind) != nullptr; }

class VerifyToy : public ::testing::Test {
 protected:
  Scene scene = parse_scene(kScene, "toy.toml");
};

}  // namespace vrv::verify_toy
