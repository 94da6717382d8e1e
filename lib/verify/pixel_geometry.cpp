#include "lib/verify/pixel_geometry.h"

#include <algorithm>
#include <cmath>

#include "lib/image_loop.h"

namespace vrv {
namespace {

std::vector<double> jump_values(const TransferFunction& tf) {
  std::vector<double> v;
  for (double b : tf.breakpoints()) {
    const auto j = tf.jump_at(b);
    if (j.emission > 0 || j.extinction > 0) v.push_back(b);
  }
  return v;
}

// One pixel's ray: whether it hits the box, its sensitivities, whether it crosses a jump.
struct Trace {
  unsigned char hit = 0, crosses = 0;
  double d_entry = 0, d_exit = 0;
};

template <class Field>
Trace trace(const Field& field, const Scene& scene, const std::vector<double>& jumps, int jump_samples,
            const Ray& ray, double value, double optical_depth) {
  Trace t;
  const auto iv = clip(ray, scene.box);
  if (!iv || !(iv->t1 > iv->t0)) return t;
  const TransferFunction& tf = scene.transfer;
  t.hit = 1;
  const double f0 = field.value(ray.at(iv->t0)), f1 = field.value(ray.at(iv->t1));
  const double T1 = std::exp(-optical_depth);
  t.d_entry = -tf.emission(f0) + tf.extinction(f0) * value;
  t.d_exit = T1 * (tf.emission(f1) - scene.background * tf.extinction(f1));
  if (jumps.empty()) return t;
  const int m = std::max(2, jump_samples);
  double prev = f0;
  for (int k = 1; k < m && !t.crosses; ++k) {
    const double f = field.value(ray.at(iv->t0 + (iv->t1 - iv->t0) * k / (m - 1)));
    for (double v : jumps)
      if ((prev - v) * (f - v) <= 0 && prev != f) t.crosses = 1;
    prev = f;
  }
  return t;
}

// Hit, sensitivities and whether the ray crosses a jump (`crosses`), per pixel.
void trace_pixels(const Scene& scene, const Camera& camera, const ReferenceImage& ref, int jump_samples,
                  PixelGeometry& g, std::vector<unsigned char>& crosses) {
  const std::vector<double> jumps = jump_values(scene.transfer);
  visit_field(scene, [&](const auto& field) {
    image_loop_into(
        camera, {},
        [&](const Ray& ray, long i) {
          return trace(field, scene, jumps, jump_samples, ray, ref.pixels[i], ref.optical_depth[i]);
        },
        [&](long i, const Trace& t) {
          g.hit[i] = t.hit, crosses[i] = t.crosses, g.d_entry[i] = t.d_entry, g.d_exit[i] = t.d_exit;
        });
  });
}

// Whether a pixel within `band` (Chebyshev distance) of (x, y) differs from it in hitting the box.
bool near_outline(const std::vector<unsigned char>& hit, int w, int h, int x, int y, int band) {
  const long i = static_cast<long>(y) * w + x;
  for (int dy = -band; dy <= band; ++dy)
    for (int dx = -band; dx <= band; ++dx) {
      const int xx = x + dx, yy = y + dy;
      if (xx >= 0 && yy >= 0 && xx < w && yy < h && hit[static_cast<long>(yy) * w + xx] != hit[i]) return true;
    }
  return false;
}

}  // namespace

PixelGeometry pixel_geometry(const Scene& scene, const Camera& camera, const ReferenceImage& ref,
                             const VerifyOptions& opt) {
  const int w = camera.width, h = camera.height;
  const long n = static_cast<long>(w) * h;
  PixelGeometry g{std::vector<unsigned char>(n), std::vector<Region>(n, Region::outside),
                  std::vector<double>(n), std::vector<double>(n)};
  std::vector<unsigned char> crosses(n);
  trace_pixels(scene, camera, ref, opt.jump_samples, g, crosses);
  const int band = std::max(0, opt.silhouette_band);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const long i = static_cast<long>(y) * w + x;
      g.region[i] = near_outline(g.hit, w, h, x, y, band) ? Region::silhouette
                    : !g.hit[i]                           ? Region::outside
                    : crosses[i]                          ? Region::tf_jump
                                                          : Region::interior;
    }
  return g;
}

}  // namespace vrv
