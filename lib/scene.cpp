#include "lib/scene.h"

namespace vrv {

GridField make_grid(const Box& box, const AnalyticField& source, GridField::Index3 resolution,
                    GridLayout layout, Interpolation interpolation) {
  return GridField(box, resolution, layout, interpolation, [&](const Vec3& p) {
    return std::visit([&](const auto& f) { return f.value(p); }, source);
  });
}

}  // namespace vrv
