#include "lib/grid_field.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

namespace vrv {

GridField::GridField(const Box& box, Index3 resolution, GridLayout layout,
                     Interpolation interpolation, const std::function<double(const Vec3&)>& source)
    : box_(box), n_(resolution), layout_(layout), interpolation_(interpolation) {
  init_geometry();
  values_.resize(static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]);
  for (int k = 0; k < n_[2]; ++k)
    for (int j = 0; j < n_[1]; ++j)
      for (int i = 0; i < n_[0]; ++i)
        values_[(static_cast<std::size_t>(k) * n_[1] + j) * n_[0] + i] =
            source(node_position(i, j, k));
  summarise();
}

GridField::GridField(const Box& box, Index3 resolution, GridLayout layout,
                     Interpolation interpolation, std::vector<double> values)
    : box_(box), n_(resolution), layout_(layout), interpolation_(interpolation),
      values_(std::move(values)) {
  init_geometry();
  const std::size_t nodes = static_cast<std::size_t>(n_[0]) * n_[1] * n_[2];
  if (values_.size() != nodes)
    throw std::invalid_argument(fmt::format("{} node values for a {} x {} x {} grid", values_.size(),
                                            n_[0], n_[1], n_[2]));
  for (std::size_t n = 0; n < nodes; ++n)
    if (!std::isfinite(values_[n]))
      throw std::invalid_argument(fmt::format("node value {} is {}", n, values_[n]));
  summarise();
}

void GridField::init_geometry() {
  const int min_n = layout_ == GridLayout::node ? 2 : 1;
  for (int a = 0; a < 3; ++a)
    if (n_[a] < min_n)
      throw std::invalid_argument(fmt::format("grid resolution must be at least {} per axis", min_n));
  offset_ = layout_ == GridLayout::node ? 0.0 : 0.5;
  for (int a = 0; a < 3; ++a)
    spacing_[a] = box_.extent()[a] / (layout_ == GridLayout::node ? n_[a] - 1 : n_[a]);
}

void GridField::summarise() {
  const auto [lo, hi] = std::minmax_element(values_.begin(), values_.end());
  spread_ = *hi - *lo;
  max_abs_ = std::max(std::abs(*lo), std::abs(*hi));
  max_slope_.setZero();
  for (int k = 0; k < n_[2]; ++k)
    for (int j = 0; j < n_[1]; ++j)
      for (int i = 0; i < n_[0]; ++i) {
        const double v = node(i, j, k);
        if (i + 1 < n_[0]) max_slope_[0] = std::max(max_slope_[0], std::abs(node(i + 1, j, k) - v));
        if (j + 1 < n_[1]) max_slope_[1] = std::max(max_slope_[1], std::abs(node(i, j + 1, k) - v));
        if (k + 1 < n_[2]) max_slope_[2] = std::max(max_slope_[2], std::abs(node(i, j, k + 1) - v));
      }
  max_slope_ = max_slope_.cwiseQuotient(spacing_);
}

double GridField::max_change_within(double distance) const {
  if (interpolation_ == Interpolation::nearest) return spread_;
  return distance * max_slope_.norm();
}

GridField GridField::mapped(const std::function<double(double)>& fn) const {
  GridField out = *this;
  for (double& v : out.values_) v = fn(v);
  out.summarise();
  return out;
}

Vec3 GridField::node_position(int i, int j, int k) const {
  const Vec3 index(i + offset_, j + offset_, k + offset_);
  return box_.min + index.cwiseProduct(spacing_);
}

void GridField::append_breaks(const Ray& ray, Interval iv, std::vector<double>& breaks) const {
  // Planes at min + (i + shift) h: node planes for trilinear, half-way planes for nearest.
  const double shift = offset_ + (interpolation_ == Interpolation::nearest ? 0.5 : 0.0);
  for (int a = 0; a < 3; ++a) {
    const double d = ray.direction[a];
    if (d == 0) continue;
    const int planes = interpolation_ == Interpolation::nearest ? n_[a] - 1 : n_[a];
    const double x0 = ray.origin[a] + iv.t0 * d;
    const double x1 = ray.origin[a] + iv.t1 * d;
    const double u0 = (std::min(x0, x1) - box_.min[a]) / spacing_[a] - shift;
    const double u1 = (std::max(x0, x1) - box_.min[a]) / spacing_[a] - shift;
    const int lo = std::max(0, static_cast<int>(std::floor(u0)));
    const int hi = std::min(planes - 1, static_cast<int>(std::ceil(u1)));
    for (int i = lo; i <= hi; ++i) {
      const double t = (box_.min[a] + (i + shift) * spacing_[a] - ray.origin[a]) / d;
      if (t > iv.t0 && t < iv.t1) breaks.push_back(t);
    }
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
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i) {
        const double v = node(i, j, k);
        mn = std::min(mn, v), mx = std::max(mx, v);
      }
  return {mn, mx};
}

}  // namespace vrv
