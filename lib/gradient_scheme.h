#pragma once
// How a discrete raycast takes the gradient it shades with (lib/shading.h), as renderers do:
//   analytic  the field's exact gradient at the sample (a grid's: its trilinear interpolant's);
//   central   central differences of the field at the sample, offset h per axis,
//             (f(p + h e_a) - f(p - h e_a)) / 2h: what GPU raycasters do, h one texel;
//   nodes     central differences at the grid's nodes, interpolated trilinearly to the sample
//             (Lee & Newman's scheme; one-sided at the grid's faces): grids only.
#include <optional>
#include <string>
#include <string_view>

#include "lib/geometry.h"
#include "lib/grid_field.h"

namespace vrv {

enum class GradientScheme { analytic, central, nodes };

std::optional<GradientScheme> parse_gradient_scheme(std::string_view name);  // "analytic", "central", "nodes"
std::string gradient_scheme_list();  // its names in order, "a, b, c": the choices an error offers
std::string_view gradient_scheme_name(GradientScheme s);

// A scheme with its offset, as a configuration holds them (DiscreteConfig::gradient, gradient_offset).
struct GradientChoice {
  GradientScheme scheme = GradientScheme::central;
  std::optional<double> offset;  // central only; none: the default
};

// Where a discrete raycast shades:
//   samples  at each sample, after classifying its interpolated value (post-shading);
//   nodes    at the grid's nodes, before interpolation: each node's classified colour times S of
//            its node gradient, the shaded colours interpolated to the sample (pre-classification
//            with pre-shading, the voxel pipeline of Levoy 1988 and the lecture notes: shade the
//            voxels, then resample).  S depends on the ray's direction, so it is taken per ray at
//            the 8 nodes around each sample.
enum class ShadeAt { samples, nodes };
std::optional<ShadeAt> parse_shade_at(std::string_view name);  // "samples", "nodes"
std::string shade_at_list();  // its names in order, "a, b, c": the choices an error offers
std::string_view shade_at_name(ShadeAt s);

// The offsets of `central` per axis: `offset` where given, else one node spacing of a grid, or the
// box's extent over `dims` (the scene's nominal voxel grid) for an analytic field.
Vec3 central_offsets(const std::optional<double>& offset, const GridField* grid, const Box& box,
                     const std::array<int, 3>& dims);

// Central differences of f at p with per-axis offsets h.
template <class Value>
Vec3 central_gradient(const Value& f, const Vec3& p, const Vec3& h) {
  Vec3 g;
  for (int a = 0; a < 3; ++a) {
    Vec3 e = Vec3::Zero();
    e[a] = h[a];
    g[a] = (f(p + e) - f(p - e)) / (2 * h[a]);
  }
  return g;
}

// The three node gradients of `nodes`: central differences at the nodes (one-sided on the faces,
// 0 along an axis of one node), each a grid of the same layout, interpolated like the field.
struct NodeGradients {
  explicit NodeGradients(const GridField& grid);
  Vec3 at(const Vec3& p) const { return {x.value(p), y.value(p), z.value(p)}; }
  GridField x, y, z;
};

}  // namespace vrv
