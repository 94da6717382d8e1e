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
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "lib/geometry.h"
#include "lib/grid_nodes.h"
#include "lib/util/enum_names.h"
#include "lib/util/force_inline.h"

namespace vrv {

struct NodeGradients;  // lib/gradient_scheme.h

enum class GridLayout { node, cell };
enum class Interpolation { trilinear, nearest };
// Their names in scene and study files.
inline constexpr NameTable<GridLayout, 2> kGridLayoutNames{{{GridLayout::node, "node"}, {GridLayout::cell, "cell"}}};
inline constexpr NameTable<Interpolation, 2> kInterpolationNames{
    {{Interpolation::trilinear, "trilinear"}, {Interpolation::nearest, "nearest"}}};
static_assert(names_complete(kGridLayoutNames) && names_complete(kInterpolationNames));

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
  // Node values in their stored type (lib/grid_nodes.h: a volume's samples), node order as above.
  GridField(const Box& box, Index3 resolution, GridLayout layout, Interpolation interpolation,
            GridNodes nodes);

  // The same grid with fn applied to every node value (pre-classification).
  GridField mapped(const std::function<double(double)>& fn) const;

  // Inline (defined below): the discrete raycaster calls it once per sample.
  double value(const Vec3& p) const;
  // The grid's interpolation (as value()) of value_at(n), any value per node (n: the flat node
  // index, as nodes()), at p: pre-shaded node colours, for one.
  template <class NodeValue>
  double interpolate(const Vec3& p, NodeValue value_at) const {
    const double u[3] = {coordinate(p.x(), 0), coordinate(p.y(), 1), coordinate(p.z(), 2)};
    return interpolation_ == Interpolation::nearest ? nearest_value(u, value_at) : trilinear_value(u, value_at);
  }
  // f(fetch), fetch(p) == value(p) for every p, with the interpolation and the nodes' type
  // chosen once: a loop of many samples inside f pays no dispatch per sample.
  template <class F>
  void with_fetch(F&& f) const;
  int degree_along_ray() const { return interpolation_ == Interpolation::trilinear ? 3 : 0; }
  // Trilinear: the gradient at p of the interpolant on the cell that holds `inside`, continued to p
  // (the gradient jumps at cell faces: a point on a face takes the side of the piece it belongs
  // to).  A component is 0 along an axis where `inside` is clamped (beyond the outermost centres
  // of the cell layout, or an axis of one node).  Nearest: 0 (the value is piecewise constant).
  Vec3 piece_gradient(const Vec3& p, const Vec3& inside) const;
  // Absolute rounding of piece_gradient's components: node differences (an ulp of the largest
  // node each) blended by two lerps, over the spacing; and the weights' own rounding (an ulp of a
  // coordinate up to n), which moves a component by the mixed difference of its cell, at most
  // twice the largest node difference along another axis, over its own spacing.
  double gradient_noise(const Vec3&) const {
    constexpr double eps = std::numeric_limits<double>::epsilon();
    const double n = std::max({n_[0], n_[1], n_[2]});
    const double aspect = spacing_.maxCoeff() / spacing_.minCoeff();
    return 4 * eps * max_abs_ / spacing_.minCoeff() + 2 * eps * n * max_slope_.maxCoeff() * aspect;
  }
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
  // The smallest and largest node value of the whole grid.
  std::pair<double, double> node_range() const { return {min_node_, max_node_}; }
  // Empty space in bulk: the stretches of the ray (within iv, sorted, disjoint, each ending on a
  // brick plane or an end of iv) that cross only bricks of kBrickCells³ cells whose nodes, with a
  // one-node halo (a point's rounding into the next cell), satisfy transparent(lo, hi).  Every
  // piece between node planes inside such a stretch is one node_range_between would find
  // transparent too, so skipping the stretch whole changes no value.  Trilinear only (none for
  // nearest).  The brick ranges are made on first use and shared by copies.
  static constexpr int kBrickCells = 8;
  template <class Transparent>
  void append_transparent_spans(const Ray& ray, Interval iv, const Transparent& transparent,
                                std::vector<Interval>& spans) const;
  // Absolute rounding of value(): a weighted sum of node values, so a few ulps of the largest
  // (a grid of values near 1e-13 is as exact, relatively, as one near 1).
  double value_noise() const { return 8 * std::numeric_limits<double>::epsilon() * max_abs_; }

  const Box& box() const { return box_; }
  Index3 resolution() const { return n_; }
  GridLayout layout() const { return layout_; }
  Interpolation interpolation() const { return interpolation_; }
  Vec3 node_position(int i, int j, int k) const;
  double node(int i, int j, int k) const {
    return nodes_[(static_cast<std::size_t>(k) * n_[1] + j) * n_[0] + i];
  }
  const GridNodes& nodes() const { return nodes_; }
  // The node differences' gradient grids (lib/gradient_scheme.h), made on first use and shared by
  // the grid's copies: raycasts with node gradients (verify casts many) build none of their own.
  const NodeGradients& node_gradients() const;

 private:
  // Checks the resolution and the node count, sets spacing_ and offset_; refuses a non-finite node.
  void init();
  // Continuous node coordinate along axis a, clamped to [0, n - 1].
  VRV_FORCE_INLINE double coordinate(double x, int a) const {
    const double u = (x - box_.min[a]) / spacing_[a] - offset_;
    return std::clamp(u, 0.0, static_cast<double>(n_[a] - 1));
  }
  // The t (sorted, appended to out) at which the ray crosses, strictly inside iv, the planes
  // min + (i + shift) h for i = 0, stride, 2 stride, ... (node planes, or the half-way planes of
  // nearest): one expression for append_breaks and brick_cuts, so their planes agree to the bit.
  void append_planes(const Ray& ray, Interval iv, double shift, int stride, std::vector<double>& out) const;
  // The node planes i = 0, kBrickCells, 2 kBrickCells, ... that the ray crosses inside iv, with
  // iv's ends, sorted.
  std::vector<double> brick_cuts(const Ray& ray, Interval iv) const;
  // The value range of the brick holding ray.at(t), halo included.
  std::pair<double, double> brick_range_at(const Ray& ray, double t) const;
  template <class Nodes>
  double nearest_value(const double u[3], Nodes node_at) const;
  template <class Nodes>
  double trilinear_value(const double u[3], Nodes node_at) const;
  void summarise();  // max_slope_, spread_, max_abs_ and the node range from the node values


  Box box_;
  Index3 n_;
  GridLayout layout_;
  Interpolation interpolation_;
  Vec3 spacing_;
  double offset_;  // 0 for node layout, 1/2 for cell layout
  GridNodes nodes_;
  Vec3 max_slope_ = Vec3::Zero();  // largest |node difference| / spacing per axis
  double spread_ = 0;              // max - min node value
  double max_abs_ = 0;             // largest |node value|
  double min_node_ = 0, max_node_ = 0;
  struct BrickRanges {
    std::once_flag made;
    Index3 count{};
    std::vector<std::pair<double, double>> range;  // brick (i, j, k) at (k * count[1] + j) * count[0] + i
  };
  std::shared_ptr<BrickRanges> bricks_ = std::make_shared<BrickRanges>();
  const BrickRanges& bricks() const;
  struct GradientCache {
    std::once_flag made;
    std::shared_ptr<const NodeGradients> value;
  };
  std::shared_ptr<GradientCache> gradients_ = std::make_shared<GradientCache>();
};

template <class Transparent>
void GridField::append_transparent_spans(const Ray& ray, Interval iv, const Transparent& transparent,
                                         std::vector<Interval>& spans) const {
  if (interpolation_ != Interpolation::trilinear) return;
  const std::vector<double> cuts = brick_cuts(ray, iv);
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double a = cuts[i], b = cuts[i + 1];
    if (!(b > a)) continue;
    const auto [lo, hi] = brick_range_at(ray, 0.5 * (a + b));
    if (!transparent(lo, hi)) continue;
    if (!spans.empty() && spans.back().t1 == a) spans.back().t1 = b;
    else spans.push_back({a, b});
  }
}

VRV_FORCE_INLINE double GridField::value(const Vec3& p) const {
  const double u[3] = {coordinate(p.x(), 0), coordinate(p.y(), 1), coordinate(p.z(), 2)};
  return nodes_.visit([&](auto node_at) VRV_FORCE_INLINE_LAMBDA {
    return interpolation_ == Interpolation::nearest ? nearest_value(u, node_at) : trilinear_value(u, node_at);
  });
}

template <class F>
void GridField::with_fetch(F&& f) const {
  nodes_.visit([&](auto node_at) {
    if (interpolation_ == Interpolation::nearest) {
      f([this, node_at](const Vec3& p) VRV_FORCE_INLINE_LAMBDA {
        const double u[3] = {coordinate(p.x(), 0), coordinate(p.y(), 1), coordinate(p.z(), 2)};
        return nearest_value(u, node_at);
      });
    } else {
      f([this, node_at](const Vec3& p) VRV_FORCE_INLINE_LAMBDA {
        const double u[3] = {coordinate(p.x(), 0), coordinate(p.y(), 1), coordinate(p.z(), 2)};
        return trilinear_value(u, node_at);
      });
    }
  });
}

template <class Nodes>
VRV_FORCE_INLINE double GridField::nearest_value(const double u[3], Nodes node_at) const {
  // Node layout: round to the nearest node; cell layout: the texel that holds p.
  int idx[3];
  for (int a = 0; a < 3; ++a) {
    const double x = layout_ == GridLayout::node ? std::round(u[a]) : std::floor(u[a] + 0.5);
    idx[a] = std::clamp(static_cast<int>(x), 0, n_[a] - 1);
  }
  return node_at((static_cast<std::size_t>(idx[2]) * n_[1] + idx[1]) * n_[0] + idx[0]);
}

template <class Nodes>
VRV_FORCE_INLINE double GridField::trilinear_value(const double u[3], Nodes c) const {
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
  const std::size_t x = step[0], y = step[1], z = step[2];
  // Nested lerps: fewer operations and roundings than the expanded 8-term sum.
  auto lerp = [](double a, double b, double t) { return a + t * (b - a); };
  const double c00 = lerp(c(base), c(base + x), w[0]);
  const double c10 = lerp(c(base + y), c(base + y + x), w[0]);
  const double c01 = lerp(c(base + z), c(base + z + x), w[0]);
  const double c11 = lerp(c(base + z + y), c(base + z + y + x), w[0]);
  return lerp(lerp(c00, c10, w[1]), lerp(c01, c11, w[1]), w[2]);
}

}  // namespace vrv
