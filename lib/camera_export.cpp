#include "lib/camera_export.h"

#include <vector>

#include "lib/camera_frame.h"
#include "lib/io/npy.h"

namespace vrv {
namespace {

nlohmann::ordered_json vec(const Vec3& v) { return {v[0], v[1], v[2]}; }

}  // namespace

nlohmann::ordered_json camera_json(const Camera& c) {
  nlohmann::ordered_json j;
  j["projection"] = std::string(to_string(c.projection));
  j["eye"] = vec(c.eye);
  if (c.projection != Projection::fan) {
    j["target"] = vec(c.target);
    j["up"] = vec(c.up);
    const CameraFrame f = camera_frame(c);
    j["frame"] = {{"forward", vec(f.forward)}, {"right", vec(f.right)}, {"up", vec(f.up)}};
  }
  if (c.projection == Projection::perspective) j["fov_degrees"] = c.fov_degrees;
  if (c.projection == Projection::orthographic) j["extent"] = c.extent;
  if (c.projection == Projection::fan) {
    j["fov_degrees"] = c.fov_degrees;
    j["angle_degrees"] = c.angle_degrees;
  }
  j["width"] = c.width;
  j["height"] = c.height;
  switch (c.projection) {
    case Projection::perspective:
      j["fov_is"] = "vertical, full angle";
      j["pixel_convention"] =
          "pixel (x, y): x to the right, y downwards, row 0 at the top; the ray of a pixel passes "
          "through its centre: u = 2 (x + 0.5) / width - 1, v = 1 - 2 (y + 0.5) / height, "
          "direction = normalize(forward + u tan(fov/2) (width/height) right + v tan(fov/2) up), origin = eye";
      break;
    case Projection::orthographic:
      j["pixel_convention"] =
          "pixel (x, y): x to the right, y downwards, row 0 at the top; rays through pixel centres: "
          "u = 2 (x + 0.5) / width - 1, v = 1 - 2 (y + 0.5) / height, origin = eye + u (extent/2) "
          "(width/height) right + v (extent/2) up, direction = forward";
      break;
    case Projection::fan:
      j["pixel_convention"] =
          "ray x of width in the plane z = eye.z, at angle angle - fov/2 + fov (x + 0.5) / width "
          "degrees from +x; height is 1";
      break;
  }
  j["frame_is"] = "forward = normalize(target - eye), right = normalize(forward x up), up = right x forward";
  j["rays_file"] = "rays.npy: float64, shape (height, width, 2, 3), [y, x, 0] origin, [y, x, 1] unit direction";
  return j;
}

std::string rays_npy(const Camera& c) {
  std::vector<double> v;
  v.reserve(static_cast<std::size_t>(c.width) * c.height * 6);
  for (int y = 0; y < c.height; ++y)
    for (int x = 0; x < c.width; ++x) {
      const Ray r = c.ray(x, y);
      for (int a = 0; a < 3; ++a) v.push_back(r.origin[a]);
      for (int a = 0; a < 3; ++a) v.push_back(r.direction[a]);
    }
  return npy_bytes(v, {static_cast<std::size_t>(c.height), static_cast<std::size_t>(c.width), 2, 3});
}

}  // namespace vrv
