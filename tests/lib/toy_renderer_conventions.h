#pragma once
// The toy raycaster of toy_raycaster.h (its loop: step rounded to the ray, one sample at the middle
// of each step; front-to-back alpha) reading an opacity/colour transfer function the ways renderers do,
// written without vrv's raycaster or tables: for the verify tests that vrv's diagnosis names
// the convention a renderer uses.
//   opacity a per unit distance L, corrected to the sample distance h: alpha = 1 - (1 - a)^(h/L);
//   colour straight (emitted c * alpha) or premultiplied (stored c * a, emitted as stored);
//   the two curves read from N-entry tables (entries at the N values spread evenly over the
//   curves' control-point range), centred (entry i read at its own value) or uncentred (the
//   plain texture coordinate u = (v - lo) / (hi - lo) under a linear filter whose texel centres
//   sit at (i + 1/2) / N).
#include <algorithm>
#include <cmath>
#include <vector>

#include "lib/camera.h"
#include "lib/scene.h"
#include "tests/lib/toy_raycaster.h"

namespace vrv::toy {

struct RendererConvention {
  bool premultiplied = false;
  int table_size = 0;  // 0: the curves themselves
  bool centred = true;
};

// One curve as a renderer's table; the curve itself when table_size is 0.
class Lookup {
 public:
  Lookup(const PiecewiseLinear& curve, double lo, double hi, const RendererConvention& c)
      : curve_(curve), lo_(lo), hi_(hi), centred_(c.centred) {
    for (int i = 0; i < c.table_size; ++i) entries_.push_back(curve(lo + (hi - lo) * i / (c.table_size - 1)));
  }
  double operator()(double v) const {
    if (entries_.empty()) return curve_(v);
    const double n = static_cast<double>(entries_.size());
    const double u = (v - lo_) / (hi_ - lo_);
    const double x = std::clamp(centred_ ? u * (n - 1) : u * n - 0.5, 0.0, n - 1);
    const std::size_t i = std::min(static_cast<std::size_t>(x), entries_.size() - 2);
    return entries_[i] + (x - static_cast<double>(i)) * (entries_[i + 1] - entries_[i]);
  }

 private:
  const PiecewiseLinear& curve_;
  double lo_, hi_;
  bool centred_;
  std::vector<double> entries_;
};

// Row-major values composited over the background; the scene's transfer function must be an
// opacity/colour one.
inline std::vector<double> render(const Scene& scene, const Camera& camera, double step,
                                  const RendererConvention& convention) {
  const TransferFunction& tf = scene.transfer;
  const double lo = tf.breakpoints().front(), hi = tf.breakpoints().back(), L = tf.unit_length();
  const Lookup opacity(tf.first(), lo, hi, convention), colour_of(tf.second(), lo, hi, convention);
  std::vector<double> out(static_cast<std::size_t>(camera.width) * camera.height);
  visit_field(scene, [&](const auto& field) {
    for (int y = 0; y < camera.height; ++y)
      for (int x = 0; x < camera.width; ++x) {
        double colour = 0, transparency = 1;
        for_each_sample(scene, field, camera.ray(x, y), step, 0.5, [&](double v, double h) {
          const double a = opacity(v), c = colour_of(v);
          const double alpha = -std::expm1(std::log1p(-a) * h / L);
          colour += transparency * c * (convention.premultiplied ? a : alpha);
          transparency *= 1 - alpha;
        });
        out[static_cast<std::size_t>(y) * camera.width + x] = colour + transparency * scene.background;
      }
  });
  return out;
}

}  // namespace vrv::toy
