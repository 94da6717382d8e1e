#pragma once
// A tiny raycaster that is not vrv's (its own loop, its own placement and compositing), standing
// in for "a renderer vrv has never seen" in the verify tests: front-to-back alpha compositing,
// the step rounded to the nearest whole number of steps on the ray, one sample at the middle of each
// step.  It borrows only the scene (field values, transfer function), the camera's rays and the
// box clipping from vrv.  Faults can be planted:
//   half_step_offset            every sample half a step late (at the end of its step);
//   step_start                  every sample at the start of its step: first order, a fault for
//                               a renderer meant to be second order, a convention for one meant
//                               to be first order (lib/verify/conventions.h);
//   missing_opacity_correction  the opacity is that of a fixed unit distance L at every sample,
//                               whatever the step (1 - exp(-tau L) instead of 1 - exp(-tau h));
//   jitter                      each pixel's samples start at a pseudo-random fraction of a step
//                               (a fixed hash of the pixel), as jittered ray starts do.
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Geometry>  // cross
#include <boost/math/quadrature/gauss.hpp>

#include "lib/camera.h"
#include "lib/scene.h"

namespace vrv::toy {

enum class Fault { none, half_step_offset, step_start, missing_opacity_correction, jitter };

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

// How a correct renderer places its samples, besides the rounded step above (each second order):
//   partial_at_exit  steps of exactly `step` from the entry, sampled at their midpoints, and the
//                    partial step left at the exit sampled at its own midpoint for its own length;
//   exit_anchored    the same marched back to front from the exit: the partial step is at the entry;
//   one_step_in      VTK's: samples every `step` from one step inside the entry while inside the box,
//                    each for a whole step (the last partial step dropped): first order.
enum class Placement { rounded, partial_at_exit, exit_anchored, one_step_in };

// The samples of one ray front to back, as sample(v, length); false when the ray misses the box.
template <class Field, class Sample>
bool for_each_placed_sample(const Scene& scene, const Field& field, const Ray& ray, double step,
                            Placement placement, Sample sample) {
  if (placement == Placement::rounded) return for_each_sample(scene, field, ray, step, 0.5, sample);
  const auto iv = clip(ray, scene.box);
  if (!iv || !(iv->t1 > iv->t0)) return false;
  if (placement == Placement::one_step_in) {
    for (double k = 1; iv->t0 + k * step <= iv->t1; ++k) sample(field.value(ray.at(iv->t0 + k * step)), step);
    return true;
  }
  const double length = iv->t1 - iv->t0;
  const long n = static_cast<long>(std::floor(length / step));
  const double partial = length - static_cast<double>(n) * step;
  const bool at_entry = placement == Placement::exit_anchored;
  const double whole_from = at_entry ? iv->t1 - static_cast<double>(n) * step : iv->t0;
  if (at_entry && partial > 0) sample(field.value(ray.at(iv->t0 + partial / 2)), partial);
  for (long k = 0; k < n; ++k) sample(field.value(ray.at(whole_from + (static_cast<double>(k) + 0.5) * step)), step);
  if (!at_entry && partial > 0) sample(field.value(ray.at(iv->t1 - partial / 2)), partial);
  return true;
}

// The image of a correct renderer with `placement` over the scene's background: front to back,
// except exit_anchored, which composites back to front (over the background, from the exit).
inline std::vector<double> render(const Scene& scene, const Camera& camera, double step, Placement placement) {
  std::vector<double> out(static_cast<std::size_t>(camera.width) * camera.height);
  visit_field(scene, [&](const auto& field) {
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) {
        std::vector<std::pair<double, double>> layers;  // (emitted colour, alpha) front to back
        for_each_placed_sample(scene, field, camera.ray(x, y), step, placement, [&](double v, double h) {
          const double g = scene.transfer.emission(v), tau = scene.transfer.extinction(v);
          const double alpha = -std::expm1(-tau * h);
          layers.emplace_back(tau > 0 ? g / tau * alpha : g * h, alpha);
        });
        double value = scene.background;  // back to front: C = c + (1 - alpha) C
        if (placement == Placement::exit_anchored) {
          for (auto it = layers.rbegin(); it != layers.rend(); ++it) value = it->first + (1 - it->second) * value;
        } else {
          double colour = 0, transparency = 1;
          for (auto [c, alpha] : layers) colour += transparency * c, transparency *= 1 - alpha;
          value = colour + transparency * scene.background;
        }
        out[static_cast<std::size_t>(y) * camera.width + x] = value;
      }
  });
  return out;
}

// Pre-integration without a table (Engel et al.'s exact segment integral): the rounded step's
// midpoints are the nodes, with the entry and exit points as the first and last; between two nodes
// the emission g and extinction tau are linear in distance, and the segment's emission
// int_0^l g(s) exp(-int_0^s tau) ds is integrated by 20-point Gauss-Legendre (Boost.Math), its
// transparency exp(-(tau_a + tau_b) l / 2) in closed form.  Second order, like the midpoints.
inline std::vector<double> render_preintegrated(const Scene& scene, const Camera& camera, double step) {
  std::vector<double> out(static_cast<std::size_t>(camera.width) * camera.height);
  visit_field(scene, [&](const auto& field) {
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) {
        const Ray ray = camera.ray(x, y);
        double value = scene.background;
        const auto iv = clip(ray, scene.box);
        if (iv && iv->t1 > iv->t0) {
          std::vector<double> nodes{iv->t0};
          for_each_sample(scene, field, ray, step, 0.5, [&](double, double h) {
            nodes.push_back(iv->t0 + (static_cast<double>(nodes.size()) - 0.5) * h);
          });
          nodes.push_back(iv->t1);
          double colour = 0, transparency = 1;
          for (std::size_t k = 0; k + 1 < nodes.size(); ++k) {
            const double va = field.value(ray.at(nodes[k])), vb = field.value(ray.at(nodes[k + 1]));
            const double ga = scene.transfer.emission(va), gb = scene.transfer.emission(vb);
            const double ta = scene.transfer.extinction(va), tb = scene.transfer.extinction(vb);
            const double l = nodes[k + 1] - nodes[k];
            auto emitted = [&](double s) {
              const double u = s / l;
              return (ga + u * (gb - ga)) * std::exp(-(ta * s + 0.5 * (tb - ta) * s * u));
            };
            colour += transparency * boost::math::quadrature::gauss<double, 20>::integrate(emitted, 0.0, l);
            transparency *= std::exp(-0.5 * (ta + tb) * l);
          }
          value = colour + transparency * scene.background;
        }
        out[static_cast<std::size_t>(y) * camera.width + x] = value;
      }
  });
  return out;
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
                             : fault == Fault::step_start ? 0.0
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

namespace vrv::toy {

// Step-independent faults planted one at a time (the classes of vrv's fitted fault catalogue,
// lib/verify/fault_fit.h), each written here without vrv's raycaster: the rounded step, midpoints,
// front-to-back alpha of render() above, then
struct Planted {
  bool flip_rows = false, flip_columns = false, transpose = false;  // the finished image
  bool srgb = false;           // the sRGB curve on the result
  double gamma = 0;            // value^(1 / gamma) on the result; 0: none
  double fov_scale = 1;        // the camera's field of view times this
  double tf_scale = 1;         // the transfer function read at v * tf_scale + tf_offset * (its range)
  double tf_offset = 0;
  double termination = 0;      // stop once the opacity reaches it; 0: never
  double opacity_ratio = 1;    // each sample's opacity for opacity_ratio times its length
  bool nearest = false;        // grid scenes: the nearest node's value instead of trilinear
  double box_grow = 0;         // the box this many voxels (grid spacings) larger on each side
  double pixel_shift = 0;      // rays this many pixels off the pixel centres on both axes (perspective)
  int table_bits = 0;          // the transfer function from 256-entry tables of this many bits; 0: none
};

// The toy's own perspective camera (not Camera::ray): the ray through image point (px, py) in
// pixel units, the frame right = forward x up, true up = right x forward (lib/camera.h's convention).
inline Ray toy_ray(const Camera& c, double px, double py) {
  const Vec3 forward = (c.target - c.eye).normalized();
  const Vec3 right = forward.cross(c.up).normalized();
  const Vec3 up = right.cross(forward);
  const double half_h = std::tan(c.fov_degrees * 3.14159265358979323846 / 360);
  const double half_w = half_h * c.width / c.height;
  const double u = 2 * px / c.width - 1, v = 1 - 2 * py / c.height;
  const Vec3 d = (forward + u * half_w * right + v * half_h * up).normalized();
  return Ray{c.eye, d};
}

// A curve read from a table of 256 entries over [lo, lo + range], each rounded to `bits` bits of
// the curve's largest entry, with linear interpolation between entries (clamped at the ends).
struct ToyTable {
  double lo = 0, range = 1;
  std::vector<double> entries;
  template <class Curve>
  ToyTable(Curve curve, double lo_, double range_, int bits) : lo(lo_), range(range_) {
    for (int i = 0; i < 256; ++i) entries.push_back(curve(lo + range * i / 255.0));
    const double top = *std::max_element(entries.begin(), entries.end());
    const double levels = std::pow(2.0, bits) - 1;
    if (top > 0)
      for (double& e : entries) e = std::nearbyint(e / top * levels) * top / levels;
  }
  double operator()(double v) const {
    const double u = std::clamp((v - lo) / range * 255.0, 0.0, 255.0);
    const int i = std::min(static_cast<int>(u), 254);
    return entries[i] + (u - i) * (entries[i + 1] - entries[i]);
  }
};

// A grid's nearest node to p (node layout), by the toy's own arithmetic.
inline double nearest_node(const GridField& g, const Vec3& p) {
  int idx[3];
  for (int a = 0; a < 3; ++a) {
    const int n = g.resolution()[a];
    const double h = (g.box().max[a] - g.box().min[a]) / (n - 1);
    idx[a] = std::clamp(static_cast<int>(std::lround((p[a] - g.box().min[a]) / h)), 0, n - 1);
  }
  return g.node(idx[0], idx[1], idx[2]);
}

// The finished image moved as planted (rows, columns, transpose).
inline std::vector<double> moved(const std::vector<double>& in, int w, int h, const Planted& f) {
  std::vector<double> out(in.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      int sx = f.flip_columns ? w - 1 - x : x, sy = f.flip_rows ? h - 1 - y : y;
      if (f.transpose) std::swap(sx, sy);
      out[static_cast<std::size_t>(y) * w + x] = in[static_cast<std::size_t>(sy) * w + sx];
    }
  return out;
}

inline std::vector<double> render(const Scene& scene, const Camera& camera, double step, const Planted& f) {
  Scene grown = scene;
  const GridField* grid = std::get_if<GridField>(&scene.field);
  for (int a = 0; a < 3 && grid; ++a) {
    const double h = (grid->box().max[a] - grid->box().min[a]) / (grid->resolution()[a] - 1);
    grown.box.min[a] -= f.box_grow * h, grown.box.max[a] += f.box_grow * h;
  }
  Camera cam = camera;
  cam.fov_degrees *= f.fov_scale;
  const TransferFunction& tf = scene.transfer;
  const double lo = tf.breakpoints().front(), range = tf.breakpoints().back() - lo;
  const int bits = f.table_bits > 0 ? f.table_bits : 30;  // unused without a table
  const ToyTable emission([&](double v) { return tf.emission(v); }, lo, range, bits);
  const ToyTable extinction([&](double v) { return tf.extinction(v); }, lo, range, bits);
  std::vector<double> out(static_cast<std::size_t>(camera.width) * camera.height);
  visit_field(scene, [&](const auto& field) {
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) {
        double colour = 0, transparency = 1;
        const Ray ray = f.pixel_shift != 0 ? toy_ray(cam, x + 0.5 + f.pixel_shift, y + 0.5 + f.pixel_shift) : cam.ray(x, y);
        const auto iv = clip(ray, grown.box);
        if (iv && iv->t1 > iv->t0) {
          const long n = std::max(1L, std::lround((iv->t1 - iv->t0) / step));
          const double h = (iv->t1 - iv->t0) / static_cast<double>(n);
          for (long k = 0; k < n && !(f.termination > 0 && 1 - transparency >= f.termination); ++k) {
            const Vec3 p = ray.at(iv->t0 + (static_cast<double>(k) + 0.5) * h);
            const double v = (f.nearest && grid ? nearest_node(*grid, p) : field.value(p)) * f.tf_scale +
                             f.tf_offset * range;
            const double g = f.table_bits > 0 ? emission(v) : tf.emission(v);
            const double tau = f.table_bits > 0 ? extinction(v) : tf.extinction(v);
            const double alpha = -std::expm1(-tau * h * f.opacity_ratio);
            colour += transparency * (tau > 0 ? g / tau * alpha : g * h * f.opacity_ratio);
            transparency *= 1 - alpha;
          }
        }
        double value = colour + transparency * scene.background;
        if (f.srgb) value = value <= 0.0031308 ? 12.92 * value : 1.055 * std::pow(value, 1 / 2.4) - 0.055;
        if (f.gamma > 0) value = std::pow(std::max(value, 0.0), 1 / f.gamma);
        out[static_cast<std::size_t>(y) * camera.width + x] = value;
      }
  });
  return moved(out, camera.width, camera.height, f);
}

}  // namespace vrv::toy
