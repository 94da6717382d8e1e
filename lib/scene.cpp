#include "lib/scene.h"

#include <stdexcept>

#include <fmt/format.h>

namespace vrv {

GridField make_grid(const Box& box, const AnalyticField& source, GridField::Index3 resolution,
                    GridLayout layout, Interpolation interpolation) {
  return GridField(box, resolution, layout, interpolation, [&](const Vec3& p) {
    return std::visit([&](const auto& f) { return f.value(p); }, source);
  });
}

Scene channel_scene(const Scene& scene, int c) {
  if (c < 0 || c >= scene.channel_count())
    throw std::out_of_range(fmt::format("channel {} of a scene with {}", c, scene.channel_count()));
  Scene one = scene;
  one.color.reset();
  if (scene.color) {
    one.transfer = scene.color->transfer[c];
    one.background = scene.color->background[c];
  }
  return one;
}

void require_grey(const Scene& scene, std::string_view source, std::string_view what) {
  if (!scene.color) return;
  throw std::invalid_argument(fmt::format(
      "{}: transfer: the scene is RGB (three-valued points), which {} does not handle yet (grey scenes "
      "only); vrv render and vrv ray integrate RGB scenes, vrv export writes them, vrv verify and vrv gate "
      "judge their images, vrv study studies each channel, and the library integrates them",
      source, what));
}

void require_unshaded(const Scene& scene, std::string_view source, std::string_view what) {
  if (!scene.shading) return;
  throw std::invalid_argument(fmt::format(
      "{}: shading: the scene shades its emission ([shading]), which {} does not handle yet; the reference "
      "does (vrv ray, vrv render --reference, and the library's integrate_reference)",
      source, what));
}

}  // namespace vrv
