#pragma once
// The camera written for other renderers: its parameters and pixel convention as JSON, and
// every pixel's ray as a .npy array for renderers whose camera model differs.
#include <string>

#include <nlohmann/json.hpp>

#include "lib/camera.h"

namespace vrv {

// {"projection", "eye", "target", "up", "fov_degrees" (vertical; perspective) or "extent"
//  (orthographic) or "angle_degrees" (fan), "width", "height", "frame": {forward, right, up}
//  (the orthonormal frame the rays are built from), "pixel_convention": text, "rays_file"}.
// Numbers are written to round trip (nlohmann-json prints doubles with 17 significant digits).
nlohmann::ordered_json camera_json(const Camera& camera);

// float64, shape (height, width, 2, 3): rays[y, x, 0] is the origin and rays[y, x, 1] the unit
// direction of camera.ray(x, y), bit for bit; row y = 0 is the top of the image.
std::string rays_npy(const Camera& camera);

}  // namespace vrv
