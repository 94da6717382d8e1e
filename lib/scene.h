#pragma once
// A scene: the volume box, one scalar field, a transfer function and a background; grey (one
// channel) or RGB (three channels sharing one extinction).
#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "analytic/linear_ramp.h"
#include "analytic/marschner_lobb.h"
#include "lib/camera.h"
#include "lib/geometry.h"
#include "lib/grid_field.h"
#include "lib/shading.h"
#include "lib/transfer_function.h"

namespace vrv {

using AnalyticField = std::variant<LinearRamp, MarschnerLobb>;
using Field = std::variant<LinearRamp, MarschnerLobb, GridField>;

// An RGB scene's channels, red, green and blue: a transfer function each, all with the scene's one
// extinction (or opacity), so the channels differ only in emission, and a background each.
struct ColorChannels {
  std::array<TransferFunction, 3> transfer;
  std::array<double, 3> background{};
};

struct Scene {
  Box box;
  // Nominal voxel grid for sampling rates; a grid field's own resolution wins.
  std::array<int, 3> dims{64, 64, 64};
  Field field = MarschnerLobb{};
  TransferFunction transfer;
  double background = 0;
  // For a field read from files (kind = "volume"): their names and CRC-64s (files_digest,
  // lib/volume/volume_grid.h), which the scene hash covers; empty otherwise.
  std::string field_files;
  // The [camera] table, if the scene file has one (vrv render falls back to default_camera).
  std::optional<Camera> camera;
  // Set for an RGB scene (three-valued emission or colour points); `transfer` and `background`
  // are then its red channel, and what draws one channel refuses the scene (require_grey).
  std::optional<ColorChannels> color;
  // The [shading] table, if the scene shades its emission with the field's gradient (lib/shading.h).
  std::optional<Shading> shading;

  int channel_count() const { return color ? 3 : 1; }
  // The shading for the field-typed integrators: nullptr when the scene does not shade.
  const Shading* shading_or_null() const { return shading ? &*shading : nullptr; }
};

// Channel c of the scene as a grey scene (the field shared, not copied); the scene itself for
// c = 0 of a grey scene.  Throws std::out_of_range for a channel the scene does not have.
Scene channel_scene(const Scene& scene, int c);

// Throws std::invalid_argument naming `source` and `what` when the scene is RGB: for the
// commands and calls that handle one channel (demo, plan, projections, the grey library calls),
// so that a colour scene is refused, never reduced silently to its red channel.
void require_grey(const Scene& scene, std::string_view source, std::string_view what);

// Throws std::invalid_argument naming `source` and `what` when the scene shades: for what does
// not shade yet (the discrete raycaster, verify, export, the studies), so that a [shading] table is
// refused, never ignored.
void require_unshaded(const Scene& scene, std::string_view source, std::string_view what);

// Calls f(field) with the concrete field type, so integrators are instantiated per type.
template <class F>
decltype(auto) visit_field(const Scene& scene, F&& f) {
  return std::visit(std::forward<F>(f), scene.field);
}

// A grid sampled from an analytic field.
GridField make_grid(const Box& box, const AnalyticField& source, GridField::Index3 resolution,
                    GridLayout layout, Interpolation interpolation);


}  // namespace vrv
