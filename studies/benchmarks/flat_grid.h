#pragma once
// Benchmark support: a flat copy of a node-layout grid and a minimal trilinear fetch on it
// (clamped coordinates, the cell's lower corner capped at n - 2, nested lerps: the arithmetic
// of GridField::value), the "bare loop" the discrete raycaster is measured against.
#include <algorithm>
#include <cstddef>
#include <vector>

#include "lib/grid_field.h"

namespace vrv::bench {

struct FlatGrid {
  std::vector<double> v;
  int n[3];
  double lo[3], h[3];
  explicit FlatGrid(const GridField& g) {
    const auto r = g.resolution();
    for (int a = 0; a < 3; ++a) {
      n[a] = r[a];
      lo[a] = g.box().min[a];
      h[a] = g.box().extent()[a] / (r[a] - 1);
    }
    v.resize(static_cast<std::size_t>(n[0]) * n[1] * n[2]);
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i) v[(static_cast<std::size_t>(k) * n[1] + j) * n[0] + i] = g.node(i, j, k);
  }
  double fetch(double x, double y, double z) const {
    const double p[3] = {x, y, z};
    int i[3];
    double w[3];
    for (int a = 0; a < 3; ++a) {
      const double u = std::clamp((p[a] - lo[a]) / h[a], 0.0, static_cast<double>(n[a] - 1));
      i[a] = std::min(static_cast<int>(u), n[a] - 2);
      w[a] = u - i[a];
    }
    const std::size_t sy = static_cast<std::size_t>(n[0]), sz = sy * n[1];
    const double* c = v.data() + i[2] * sz + i[1] * sy + i[0];
    auto lerp = [](double a, double b, double t) { return a + t * (b - a); };
    const double c00 = lerp(c[0], c[1], w[0]);
    const double c10 = lerp(c[sy], c[sy + 1], w[0]);
    const double c01 = lerp(c[sz], c[sz + 1], w[0]);
    const double c11 = lerp(c[sz + sy], c[sz + sy + 1], w[0]);
    return lerp(lerp(c00, c10, w[1]), lerp(c01, c11, w[1]), w[2]);
  }
};

}  // namespace vrv::bench
