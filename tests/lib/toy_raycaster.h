#pragma once
// A tiny raycaster that is not vrv's (its own loop, its own placement and compositing), standing
// in for "a renderer vrv has never seen" in the verify tests: front-to-back alpha compositing,
// the step rounded to the nearest whole number of steps on the ray, one sample at the middle of each
// step.  It borrows only the scene (field values, transfer function), the camera's rays and the
// box clipping from vrv.  Two faults can be planted:
//   half_step_offset            every sample half a step late (at the end of its step);
//   missing_opacity_correction  the opacity is that of a fixed unit distance L at every sample,
//                               whatever the step (1 - exp(-tau L) instead of 1 - exp(-tau h));
//   jitter                      each pixel's samples start at a pseudo-random fraction of a step
//                               (a fixed hash of the pixel), as jittered ray starts do.
#include <algorithm>
#include <cmath>
#include <vector>

#include "lib/camera.h"
#include "lib/scene.h"

namespace vrv::toy {

enum class Fault { none, half_step_offset, missing_opacity_correction, jitter };

// A fixed pseudo-random number in [0, 1) per pixel (splitmix64 of the index).
inline double pixel_random(long i) {
  unsigned long long z = static_cast<unsigned long long>(i) + 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-53;
}

// The toy's loop over one pixel's ray: the clipped ray cut into round(length / step) equal steps
// h, one field value per step at (k + shift) h from the entry, passed to sample(v, h).  False when
// the ray misses the box.
template <class Field, class Sample>
bool for_each_sample(const Scene& scene, const Field& field, const Ray& ray, double step, double shift,
                     Sample sample) {
  const auto iv = clip(ray, scene.box);
  if (!iv || !(iv->t1 > iv->t0)) return false;
  const double length = iv->t1 - iv->t0;
  const long n = std::max(1L, std::lround(length / step));
  const double h = length / static_cast<double>(n);
  for (long k = 0; k < n; ++k) sample(field.value(ray.at(iv->t0 + (static_cast<double>(k) + shift) * h)), h);
  return true;
}

// The image composited over the scene's background; with `alpha`, the colour over nothing
// (premultiplied) and the opacity 1 - transparency per pixel in *alpha.
inline std::vector<double> render(const Scene& scene, const Camera& camera, double step, Fault fault,
                                  double unit_distance, std::vector<double>* alpha = nullptr) {
  if (alpha) alpha->assign(static_cast<std::size_t>(camera.width) * camera.height, 0.0);
  std::vector<double> out(static_cast<std::size_t>(camera.width) * camera.height);
  visit_field(scene, [&](const auto& field) {
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) {
        const double shift = fault == Fault::half_step_offset ? 1.0
                             : fault == Fault::jitter ? pixel_random(static_cast<long>(y) * camera.width + x)
                                                      : 0.5;
        double colour = 0, transparency = 1;
        for_each_sample(scene, field, camera.ray(x, y), step, shift, [&](double v, double h) {
          const double d = fault == Fault::missing_opacity_correction ? unit_distance : h;
          const double g = scene.transfer.emission(v), tau = scene.transfer.extinction(v);
          const double alpha = -std::expm1(-tau * d);
          colour += transparency * (tau > 0 ? g / tau * alpha : g * d);
          transparency *= 1 - alpha;
        });
        const std::size_t i = static_cast<std::size_t>(y) * camera.width + x;
        out[i] = alpha ? colour : colour + transparency * scene.background;
        if (alpha) (*alpha)[i] = 1 - transparency;
      }
  });
  return out;
}

}  // namespace vrv::toy
