#pragma once
// Scene files the tests write: a field in the box [-1, 1]^3 and what follows it (transfer
// function, background, shading), and the Phong lighting several tests shade with.
#include <string>
#include <string_view>

namespace vrv::test {

// [volume] the box [-1, 1]^3, then [field] with `field_keys`, then `rest` (more tables).
inline std::string unit_box_scene(std::string_view field_keys, std::string_view rest) {
  std::string text = "[volume]\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]\n[field]\n";
  text.append(field_keys).append("\n").append(rest);
  return text;
}

// Phong shading lit from +z (the normal and sides at their defaults).
inline constexpr std::string_view kPhong = R"([shading]
model = "phong"
ambient = 0.1
diffuse = 0.6
specular = 0.3
shininess = 12.0
light = [0.0, 0.0, 2.0]
)";

}  // namespace vrv::test
