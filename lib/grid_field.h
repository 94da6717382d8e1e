#pragma once
// A regular grid of samples of another field, interpolated trilinearly or to the nearest node.
//
// layout node: nodes on the box faces, x_i = min + i h, h = extent / (n - 1).
// layout cell: texel centres, x_i = min + (i + 1/2) h, h = extent / n; positions between
//              the box face and the outermost centre are clamped (as a GPU texture does).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

#include "lib/util/force_inline.h"
#include "lib/geometry.h"

namespace vrv {

enum class GridLayout { node, cell };
enum class Interpolation { trilinear, nearest };

class GridField {
 public:
  using Index3 = std::array<int, 3>;

  // Samples `source` at every node.  Throws std::invalid_argument for a resolution below
  // 2 (node layout) or 1 (cell layout) on any axis.
  GridField(const Box& box, Index3 resolution, GridLayout layout, Interpolation interpolation,
            const std::function<double(const Vec3&)>& source);

  // The given node values, node (i, j, k) at values[(k * n[1] + j) * n[0] + i].  Throws
  // std::invalid_argument as above, for a size other than the node count, or a non-finite value.
  GridField(const Box& box, Index3 resolution, GridLayout layout, Interpolation interpolation,
            std::vector<double> values);

  // The same grid with fn applied to every node value (pre-classification).
  GridField mapped(const std::function<double(double)>& fn) const;

  // Inline (defined below): the discrete raycaster calls it once per sample.
  double value(const Vec3& p) const;
  int degree_along_ray() const { return interpolation_ == Interpolation::trilinear ? 3 : 0; }
  double bandwidth() const { return 0; }
  // Trilinear: the node planes (the interpolant is a cubic in t between them).
  // Nearest: the planes half way between nodes (the value is constant between them).
  void append_breaks(const Ray& ray, Interval iv, std::vector<double>& breaks) const;
  // Trilinear: distance times the largest gradient (each partial derivative is a mean of node
  // differences over the spacing).  Nearest: the spread of the node values (a point may change cell).
  double max_change_within(double distance) const;
  // The smallest and largest node of every cell the segment p-q touches: the interpolant (either
  // kind) stays within them there.  The reference skips a stretch on which the transfer function
  // is zero over that range (empty space, exactly; lib/reference_integrator.h).
  std::pair<double, double> node_range_between(const Vec3& p, const Vec3& q) const;
  // Absolute rounding of value(): a weighted sum of node values, so a few ulps of the largest
  // (a grid of values near 1e-13 is as exact, relatively, as one near 1).
  double value_noise() const { return 8 * std::numeric_limits<double>::epsilon() * max_abs_; }

  const Box& box() const { return box_; }
  Index3 resolution() const { return n_; }
  GridLayout layout() const { return layout_; }
  Interpolation interpolation() const { return interpolation_; }
  Vec3 node_position(int i, int j, int k) const;
  double node(int i, int j, int k) const {
    return values_[(static_cast<std::size_t>(k) * n_[1] + j) * n_[0] + i];
  }

 private:
  // Checks the resolution, sets spacing_ and offset_.
  void init_geometry();
  // Continuous node coordinate along axis a, clamped to [0, n - 1].
  VRV_FORCE_INLINE double coordinate(double x, int a) const {
    const double u = (x - box_.min[a]) / spacing_[a] - offset_;
    return std::clamp(u, 0.0, static_cast<double>(n_[a] - 1));
  }
  double nearest_value(const double u[3]) const;
  double trilinear_value(const double u[3]) const;
  void summarise();  // max_slope_, spread_ and max_abs_ from the node values


  Box box_;
  Index3 n_;
  GridLayout layout_;
  Interpolation interpolation_;
  Vec3 spacing_;
  double offset_;  // 0 for node layout, 1/2 for cell layout
  std::vector<double> values_;
  Vec3 max_slope_ = Vec3::Zero();  // largest |node difference| / spacing per axis
  double spread_ = 0;              // max - min node value
  double max_abs_ = 0;             // largest |node value|
};

VRV_FORCE_INLINE double GridField::value(const Vec3& p) const {
  const double u[3] = {coordinate(p.x(), 0), coordinate(p.y(), 1), coordinate(p.z(), 2)};
  return interpolation_ == Interpolation::nearest ? nearest_value(u) : trilinear_value(u);
}

inline double GridField::nearest_value(const double u[3]) const {
  // Node layout: round to the nearest node; cell layout: the texel that holds p.
  int idx[3];
  for (int a = 0; a < 3; ++a) {
    const double x = layout_ == GridLayout::node ? std::round(u[a]) : std::floor(u[a] + 0.5);
    idx[a] = std::clamp(static_cast<int>(x), 0, n_[a] - 1);
  }
  return node(idx[0], idx[1], idx[2]);
}

VRV_FORCE_INLINE double GridField::trilinear_value(const double u[3]) const {
  // The cell's lower corner (capped at n - 2) and the step to its upper corner per axis, 0 on an
  // axis of one node; the node array addressed by strides from one base (8 loads, no index products).
  const std::size_t stride[3] = {1, static_cast<std::size_t>(n_[0]),
                                 static_cast<std::size_t>(n_[0]) * n_[1]};
  std::size_t base = 0, step[3];
  double w[3];
  for (int a = 0; a < 3; ++a) {
    const int i0 = std::min(static_cast<int>(u[a]), std::max(n_[a] - 2, 0));
    step[a] = (std::min(i0 + 1, n_[a] - 1) - i0) * stride[a];
    base += static_cast<std::size_t>(i0) * stride[a];
    w[a] = u[a] - i0;
  }
  const double* c = values_.data() + base;
  const std::size_t x = step[0], y = step[1], z = step[2];
  // Nested lerps: fewer operations and roundings than the expanded 8-term sum.
  auto lerp = [](double a, double b, double t) { return a + t * (b - a); };
  const double c00 = lerp(c[0], c[x], w[0]);
  const double c10 = lerp(c[y], c[y + x], w[0]);
  const double c01 = lerp(c[z], c[z + x], w[0]);
  const double c11 = lerp(c[z + y], c[z + y + x], w[0]);
  return lerp(lerp(c00, c10, w[1]), lerp(c01, c11, w[1]), w[2]);
}

}  // namespace vrv
