#pragma once
// Where each pixel's ray goes: whether it hits the volume's box, its region (silhouette band,
// transfer-function jump crossing, interior, outside; lib/verify/verify_report.h) and the
// sensitivities of I to moving the ray's start and end (the half-step offset's signature,
// fault_hints.h).
#include <vector>

#include "lib/camera.h"
#include "lib/scene.h"
#include "lib/verify/reference_image.h"
#include "lib/verify/verify_report.h"

namespace vrv {

struct PixelGeometry {
  std::vector<unsigned char> hit;  // 1 where the pixel's ray crosses the box
  std::vector<Region> region;      // outside, interior, silhouette or tf_jump (never all)
  // dI/d(entry shift) and dI/d(exit shift) per hit pixel (0 elsewhere).
  std::vector<double> d_entry, d_exit;
};

// Per pixel of `camera`; `ref` gives each ray's value and optical depth.  The silhouette band is
// options.silhouette_band pixels wide; jump crossings are looked for at options.jump_samples.
PixelGeometry pixel_geometry(const Scene& scene, const Camera& camera, const ReferenceImage& ref,
                             const VerifyOptions& options);

}  // namespace vrv
