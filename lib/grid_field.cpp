#include "lib/grid_field.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "lib/gradient_scheme.h"

namespace vrv {
namespace {

void check_grid_resolution(GridField::Index3 n, GridLayout layout) {
  const int min_n = layout == GridLayout::node ? 2 : 1;
  for (int a = 0; a < 3; ++a)
    if (n[a] < min_n)
      throw std::invalid_argument(fmt::format("grid resolution must be at least {} per axis", min_n));
}

double grid_offset(GridLayout layout) { return layout == GridLayout::node ? 0.0 : 0.5; }

Vec3 grid_spacing(const Box& box, GridField::Index3 n, GridLayout layout) {
  Vec3 h;
  for (int a = 0; a < 3; ++a) h[a] = box.extent()[a] / (layout == GridLayout::node ? n[a] - 1 : n[a]);
  return h;
}

// `source` at every node position (as GridField::node_position places them).
std::vector<double> sampled_nodes(const Box& box, GridField::Index3 n, GridLayout layout,
                            const std::function<double(const Vec3&)>& source) {
  check_grid_resolution(n, layout);
  const double offset = grid_offset(layout);
  const Vec3 h = grid_spacing(box, n, layout);
  std::vector<double> values(static_cast<std::size_t>(n[0]) * n[1] * n[2]);
  std::size_t out = 0;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        values[out++] = source(box.min + Vec3(i + offset, j + offset, k + offset).cwiseProduct(h));
  return values;
}

}  // namespace

GridField::GridField(const Box& box, Index3 resolution, GridLayout layout,
                     Interpolation interpolation, const std::function<double(const Vec3&)>& source)
    : GridField(box, resolution, layout, interpolation, sampled_nodes(box, resolution, layout, source)) {}

GridField::GridField(const Box& box, Index3 resolution, GridLayout layout,
                     Interpolation interpolation, std::vector<double> values)
    : GridField(box, resolution, layout, interpolation, GridNodes(std::move(values))) {}

GridField::GridField(const Box& box, Index3 resolution, GridLayout layout,
                     Interpolation interpolation, GridNodes nodes)
    : box_(box), n_(resolution), layout_(layout), interpolation_(interpolation),
      nodes_(std::move(nodes)) {
  init();
  summarise();
}

void GridField::init() {
  check_grid_resolution(n_, layout_);
  offset_ = grid_offset(layout_);
  spacing_ = grid_spacing(box_, n_, layout_);
  const std::size_t count = static_cast<std::size_t>(n_[0]) * n_[1] * n_[2];
  if (nodes_.size() != count)
    throw std::invalid_argument(fmt::format("{} node values for a {} x {} x {} grid", nodes_.size(),
                                            n_[0], n_[1], n_[2]));
  nodes_.visit([&](auto fetch) {
    for (std::size_t n = 0; n < count; ++n)
      if (!std::isfinite(fetch(n))) throw std::invalid_argument(fmt::format("node value {} is {}", n, fetch(n)));
  });
}

void GridField::summarise() {
  nodes_.visit([&](auto node_at) {
    double lo = node_at(0), hi = lo;
    max_slope_.setZero();
    const std::size_t sx = 1, sy = n_[0], sz = sy * n_[1];
    for (int k = 0; k < n_[2]; ++k)
      for (int j = 0; j < n_[1]; ++j)
        for (int i = 0; i < n_[0]; ++i) {
          const std::size_t n = k * sz + j * sy + i;
          const double v = node_at(n);
          lo = std::min(lo, v), hi = std::max(hi, v);
          if (i + 1 < n_[0]) max_slope_[0] = std::max(max_slope_[0], std::abs(node_at(n + sx) - v));
          if (j + 1 < n_[1]) max_slope_[1] = std::max(max_slope_[1], std::abs(node_at(n + sy) - v));
          if (k + 1 < n_[2]) max_slope_[2] = std::max(max_slope_[2], std::abs(node_at(n + sz) - v));
        }
    spread_ = hi - lo;
    max_abs_ = std::max(std::abs(lo), std::abs(hi));
    min_node_ = lo, max_node_ = hi;
  });
  max_slope_ = max_slope_.cwiseQuotient(spacing_);
}

double GridField::max_change_within(double distance) const {
  if (interpolation_ == Interpolation::nearest) return spread_;
  return distance * max_slope_.norm();
}

Vec3 GridField::piece_gradient(const Vec3& p, const Vec3& inside) const {
  if (interpolation_ == Interpolation::nearest) return Vec3::Zero();
  const std::size_t stride[3] = {1, static_cast<std::size_t>(n_[0]), static_cast<std::size_t>(n_[0]) * n_[1]};
  std::size_t base = 0, step[3];
  double w[3];
  bool free[3];
  for (int a = 0; a < 3; ++a) {
    const double u_in = (inside[a] - box_.min[a]) / spacing_[a] - offset_;
    const double u_p = (p[a] - box_.min[a]) / spacing_[a] - offset_;
    const int last = n_[a] - 1;
    free[a] = last > 0 && u_in >= 0 && u_in <= last;
    const int i0 = free[a] ? std::min(static_cast<int>(u_in), last - 1) : (u_in < 0 || last == 0 ? 0 : last - 1);
    step[a] = (last > 0 ? 1 : 0) * stride[a];
    base += static_cast<std::size_t>(i0) * stride[a];
    w[a] = free[a] ? u_p - i0 : (u_in < 0 || last == 0 ? 0.0 : 1.0);
  }
  return nodes_.visit([&](auto c) {
    const auto at = [&](int i, int j, int k) { return c(base + i * step[0] + j * step[1] + k * step[2]); };
    const auto lerp = [](double a, double b, double t) { return a + t * (b - a); };
    // d/dw_a of the trilinear form: the other two weights' bilinear blend of the differences along a.
    const auto blend = [&](auto corner, double s, double t) {
      return lerp(lerp(corner(0, 0), corner(1, 0), s), lerp(corner(0, 1), corner(1, 1), s), t);
    };
    Vec3 g;
    g.x() = blend([&](int j, int k) { return at(1, j, k) - at(0, j, k); }, w[1], w[2]);
    g.y() = blend([&](int i, int k) { return at(i, 1, k) - at(i, 0, k); }, w[0], w[2]);
    g.z() = blend([&](int i, int j) { return at(i, j, 1) - at(i, j, 0); }, w[0], w[1]);
    for (int a = 0; a < 3; ++a) g[a] = free[a] ? g[a] / spacing_[a] : 0.0;
    return g;
  });
}

GridField GridField::mapped(const std::function<double(double)>& fn) const {
  GridField out = *this;
  out.nodes_ = nodes_.mapped(fn);
  out.bricks_ = std::make_shared<BrickRanges>();
  out.gradients_ = std::make_shared<GradientCache>();
  out.summarise();
  return out;
}

Vec3 GridField::node_position(int i, int j, int k) const {
  const Vec3 index(i + offset_, j + offset_, k + offset_);
  return box_.min + index.cwiseProduct(spacing_);
}

void GridField::append_breaks(const Ray& ray, Interval iv, std::vector<double>& breaks) const {
  // Node planes for trilinear, half-way planes for nearest.
  if (interpolation_ == Interpolation::nearest) append_planes(ray, iv, offset_ + 0.5, 1, breaks);
  else append_planes(ray, iv, offset_, 1, breaks);
}

void GridField::append_planes(const Ray& ray, Interval iv, double shift, int stride,
                              std::vector<double>& out) const {
  const std::size_t first = out.size();
  for (int a = 0; a < 3; ++a) {
    const double d = ray.direction[a];
    if (d == 0) continue;
    const int planes = interpolation_ == Interpolation::nearest ? n_[a] - 1 : n_[a];
    const double x0 = ray.origin[a] + iv.t0 * d;
    const double x1 = ray.origin[a] + iv.t1 * d;
    const double u0 = (std::min(x0, x1) - box_.min[a]) / spacing_[a] - shift;
    const double u1 = (std::max(x0, x1) - box_.min[a]) / spacing_[a] - shift;
    const int lo = std::max(0, static_cast<int>(std::floor(u0 / stride)));
    const int hi = std::min((planes - 1) / stride, static_cast<int>(std::ceil(u1 / stride)));
    // Planes in the ray's order (t rises with m where d > 0), so each axis's run is sorted.
    const std::size_t run = out.size();
    for (int i = lo; i <= hi; ++i) {
      const int m = d > 0 ? i : lo + hi - i;
      const double t = (box_.min[a] + (m * stride + shift) * spacing_[a] - ray.origin[a]) / d;
      if (t > iv.t0 && t < iv.t1) out.push_back(t);
    }
    // One merge per axis leaves the planes sorted: a ray's cuts need no sort (a whole sort of
    // them was 5% of a scan's reference image).
    std::inplace_merge(out.begin() + static_cast<std::ptrdiff_t>(first), out.begin() + static_cast<std::ptrdiff_t>(run), out.end());
  }
}

std::pair<double, double> GridField::node_range_between(const Vec3& p, const Vec3& q) const {
  // Node indices floor(u) .. floor(u) + 1 of both ends per axis (the cells' corners; a point's
  // rounding into the next cell lands on their shared face, whose nodes are among these).
  int lo[3], hi[3];
  for (int a = 0; a < 3; ++a) {
    const double up = coordinate(p[a], a), uq = coordinate(q[a], a);
    const double u0 = std::min(up, uq), u1 = std::max(up, uq);
    lo[a] = std::clamp(static_cast<int>(std::floor(u0)), 0, n_[a] - 1);
    hi[a] = std::clamp(static_cast<int>(std::floor(u1)) + 1, 0, n_[a] - 1);
  }
  double mn = std::numeric_limits<double>::infinity(), mx = -mn;
  nodes_.visit([&](auto node_at) {
    for (int k = lo[2]; k <= hi[2]; ++k)
      for (int j = lo[1]; j <= hi[1]; ++j)
        for (int i = lo[0]; i <= hi[0]; ++i) {
          const double v = node_at((static_cast<std::size_t>(k) * n_[1] + j) * n_[0] + i);
          mn = std::min(mn, v), mx = std::max(mx, v);
        }
  });
  return {mn, mx};
}

const NodeGradients& GridField::node_gradients() const {
  std::call_once(gradients_->made, [&] { gradients_->value = std::make_shared<const NodeGradients>(*this); });
  return *gradients_->value;
}

const GridField::BrickRanges& GridField::bricks() const {
  std::call_once(bricks_->made, [&] {
    BrickRanges& b = *bricks_;
    for (int a = 0; a < 3; ++a) b.count[a] = std::max(1, (n_[a] - 2) / kBrickCells + 1);  // n - 1 cells
    b.range.resize(static_cast<std::size_t>(b.count[0]) * b.count[1] * b.count[2]);
    nodes_.visit([&](auto node_at) {
      std::size_t out = 0;
      for (int bk = 0; bk < b.count[2]; ++bk)
        for (int bj = 0; bj < b.count[1]; ++bj)
          for (int bi = 0; bi < b.count[0]; ++bi) {
            const int first[3] = {bi * kBrickCells - 1, bj * kBrickCells - 1, bk * kBrickCells - 1};
            int lo[3], hi[3];
            for (int a = 0; a < 3; ++a) {
              lo[a] = std::max(first[a], 0);
              hi[a] = std::min(first[a] + kBrickCells + 2, n_[a] - 1);
            }
            double mn = std::numeric_limits<double>::infinity(), mx = -mn;
            for (int k = lo[2]; k <= hi[2]; ++k)
              for (int j = lo[1]; j <= hi[1]; ++j)
                for (int i = lo[0]; i <= hi[0]; ++i) {
                  const double v = node_at((static_cast<std::size_t>(k) * n_[1] + j) * n_[0] + i);
                  mn = std::min(mn, v), mx = std::max(mx, v);
                }
            b.range[out++] = {mn, mx};
          }
    });
  });
  return *bricks_;
}

std::vector<double> GridField::brick_cuts(const Ray& ray, Interval iv) const {
  std::vector<double> cuts{iv.t0};
  append_planes(ray, iv, offset_, kBrickCells, cuts);  // trilinear only: the node planes' own t
  cuts.push_back(iv.t1);
  std::sort(cuts.begin(), cuts.end());
  return cuts;
}

std::pair<double, double> GridField::brick_range_at(const Ray& ray, double t) const {
  const BrickRanges& b = bricks();
  const Vec3 p = ray.at(t);
  int idx[3];
  for (int a = 0; a < 3; ++a)
    idx[a] = std::min(static_cast<int>(coordinate(p[a], a)) / kBrickCells, b.count[a] - 1);
  return b.range[(static_cast<std::size_t>(idx[2]) * b.count[1] + idx[1]) * b.count[0] + idx[0]];
}

}  // namespace vrv
