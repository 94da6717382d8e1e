#pragma once
// A regular grid of samples of another field, interpolated trilinearly or to the nearest node.
//
// layout node: nodes on the box faces, x_i = min + i h, h = extent / (n - 1).
// layout cell: texel centres, x_i = min + (i + 1/2) h, h = extent / n; positions between
//              the box face and the outermost centre are clamped (as a GPU texture does).
#include <array>
#include <functional>
#include <limits>
#include <vector>

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

  double value(const Vec3& p) const;
  int degree_along_ray() const { return interpolation_ == Interpolation::trilinear ? 3 : 0; }
  double bandwidth() const { return 0; }
  // Trilinear: the node planes (the interpolant is a cubic in t between them).
  // Nearest: the planes half way between nodes (the value is constant between them).
  void append_breaks(const Ray& ray, Interval iv, std::vector<double>& breaks) const;
  // Trilinear: distance times the largest gradient (each partial derivative is a mean of node
  // differences over the spacing).  Nearest: the spread of the node values (a point may change cell).
  double max_change_within(double distance) const;
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
  double coordinate(double x, int a) const;
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

}  // namespace vrv
