#pragma once
// A scene: the volume box, one scalar field, a transfer function and a background.
#include <array>
#include <optional>
#include <string>
#include <variant>

#include "analytic/linear_ramp.h"
#include "analytic/marschner_lobb.h"
#include "lib/camera.h"
#include "lib/geometry.h"
#include "lib/grid_field.h"
#include "lib/transfer_function.h"

namespace vrv {

using AnalyticField = std::variant<LinearRamp, MarschnerLobb>;
using Field = std::variant<LinearRamp, MarschnerLobb, GridField>;

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
};

// Calls f(field) with the concrete field type, so integrators are instantiated per type.
template <class F>
decltype(auto) visit_field(const Scene& scene, F&& f) {
  return std::visit(std::forward<F>(f), scene.field);
}

// A grid sampled from an analytic field.
GridField make_grid(const Box& box, const AnalyticField& source, GridField::Index3 resolution,
                    GridLayout layout, Interpolation interpolation);


}  // namespace vrv
