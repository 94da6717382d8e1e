#include "lib/gradient_scheme.h"

#include <vector>

#include "lib/util/enum_names.h"

namespace vrv {
namespace {

constexpr NameTable<GradientScheme, 3> kSchemes{{{GradientScheme::analytic, "analytic"},
                                                 {GradientScheme::central, "central"},
                                                 {GradientScheme::nodes, "nodes"}}};
static_assert(names_complete(kSchemes));
constexpr NameTable<ShadeAt, 2> kShadeAt{{{ShadeAt::samples, "samples"}, {ShadeAt::nodes, "nodes"}}};
static_assert(names_complete(kShadeAt));

// The spacing of the grid's nodes along axis a (as GridField places them).
double spacing(const GridField& g, int a) {
  const int n = g.resolution()[a];
  const double extent = g.box().extent()[a];
  return g.layout() == GridLayout::node ? extent / std::max(n - 1, 1) : extent / n;
}

// Central differences along axis a at every node: one-sided on the first and last node.
GridField node_derivative(const GridField& g, int a) {
  const auto n = g.resolution();
  const double h = spacing(g, a);
  std::vector<double> values(static_cast<std::size_t>(n[0]) * n[1] * n[2]);
  std::size_t m = 0;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i, ++m) {
        int idx[3] = {i, j, k};
        if (n[a] < 2) {
          values[m] = 0;
          continue;
        }
        const int lo = std::max(idx[a] - 1, 0), hi = std::min(idx[a] + 1, n[a] - 1);
        int at_lo[3] = {i, j, k}, at_hi[3] = {i, j, k};
        at_lo[a] = lo, at_hi[a] = hi;
        values[m] = (g.node(at_hi[0], at_hi[1], at_hi[2]) - g.node(at_lo[0], at_lo[1], at_lo[2])) / ((hi - lo) * h);
      }
  return GridField(g.box(), n, g.layout(), g.interpolation(), std::move(values));
}

}  // namespace

std::optional<GradientScheme> parse_gradient_scheme(std::string_view name) { return parse_name(kSchemes, name); }
std::string gradient_scheme_list() { return name_list(kSchemes); }
std::string_view gradient_scheme_name(GradientScheme s) { return name_of(kSchemes, s); }
std::optional<ShadeAt> parse_shade_at(std::string_view name) { return parse_name(kShadeAt, name); }
std::string shade_at_list() { return name_list(kShadeAt); }
std::string_view shade_at_name(ShadeAt s) { return name_of(kShadeAt, s); }

Vec3 central_offsets(const std::optional<double>& offset, const GridField* grid, const Box& box,
                     const std::array<int, 3>& dims) {
  if (offset) return Vec3::Constant(*offset);
  if (grid) return {spacing(*grid, 0), spacing(*grid, 1), spacing(*grid, 2)};
  const Vec3 extent = box.extent();
  return {extent[0] / dims[0], extent[1] / dims[1], extent[2] / dims[2]};
}

NodeGradients::NodeGradients(const GridField& grid)
    : x(node_derivative(grid, 0)), y(node_derivative(grid, 1)), z(node_derivative(grid, 2)) {}

}  // namespace vrv
