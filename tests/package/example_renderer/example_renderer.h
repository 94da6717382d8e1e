#pragma once
// An example renderer, written as a renderer's author would: its own ray-box clipping, its own
// sample placement and its own compositing, none of vrv's raycaster.  It takes only the scene
// (field values and transfer function) and the camera's rays from vrv, so that its image can be
// verified against vrv's reference in-process (tests/package/consumer/example_renderer_test.cpp).
//
// Samples: the clipped ray [t0, t1] is cut into n = ceil((t1 - t0) / step) equal segments and
// each is sampled at its midpoint; g and tau there are taken as constant over the segment, whose
// emission escapes as (g / tau) (1 - e^{-tau h}).  That is the midpoint rule: second order.
// The test suite builds a copy with a planted half-step offset (samples at segment starts,
// first order) and checks that verification catches it.
#include <algorithm>
#include <cmath>
#include <vector>

#include <vrv/vrv.h>

namespace example {

// The part [t0, t1] of the ray (t >= 0) inside the box; false when it misses.
inline bool clip_to_box(const vrv::Ray& ray, const vrv::Box& box, double& t0, double& t1) {
  t0 = 0;
  t1 = INFINITY;
  for (int a = 0; a < 3; ++a) {
    const double inv = 1 / ray.direction[a];
    double near = (box.min[a] - ray.origin[a]) * inv, far = (box.max[a] - ray.origin[a]) * inv;
    if (near > far) std::swap(near, far);
    if (std::isnan(near) || std::isnan(far)) {  // parallel to this slab and on its face
      if (ray.origin[a] < box.min[a] || ray.origin[a] > box.max[a]) return false;
      continue;
    }
    t0 = std::max(t0, near);
    t1 = std::min(t1, far);
  }
  return t0 < t1;
}

template <class Field>
double cast(const vrv::Scene& scene, const Field& field, const vrv::Ray& ray, double step) {
  double t0 = 0, t1 = 0;
  if (!clip_to_box(ray, scene.box, t0, t1)) return scene.background;
  const int n = std::max(1, static_cast<int>(std::ceil((t1 - t0) / step)));
  const double h = (t1 - t0) / n;
  double color = 0, transmittance = 1;
  for (int i = 0; i < n; ++i) {
    const double t = t0 + (i + 0.5) * h;
    const double v = field.value(ray.at(t));
    const double g = scene.transfer.emission(v), tau = scene.transfer.extinction(v);
    const double alpha = -std::expm1(-tau * h);
    color += transmittance * (tau > 0 ? g / tau * alpha : g * h);
    transmittance *= 1 - alpha;
  }
  return color + transmittance * scene.background;
}

// One value per pixel of `camera`, row-major from the top-left, as vrv::ValueImage.
inline vrv::ValueImage render(const vrv::Scene& scene, const vrv::Camera& camera, double step) {
  const std::vector<vrv::Ray> rays = vrv::camera_rays(camera);
  vrv::ValueImage image{camera.width, camera.height, std::vector<double>(rays.size())};
  vrv::visit_field(scene, [&](const auto& field) {
    for (std::size_t i = 0; i < rays.size(); ++i) image.pixels[i] = cast(scene, field, rays[i], step);
  });
  return image;
}

}  // namespace example
