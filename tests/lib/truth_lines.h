#pragma once
// The truth files of the adversarial tests: JSON lines written by the mpmath generators beside
// them (a header line, then one line per ray), with exact doubles written as hex.
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "lib/geometry.h"
#include "lib/scene_file.h"

namespace vrv::test {

inline double hex_double(const std::string& s) { return std::strtod(s.c_str(), nullptr); }

inline Vec3 hex_vec3(const nlohmann::json& xyz) {
  return Vec3(hex_double(xyz[0]), hex_double(xyz[1]), hex_double(xyz[2]));
}

// Every line of VRV_SOURCE_DIR/`relative` but the header, parsed; the header into `header` when
// given.  Throws std::runtime_error when the file cannot be read.
inline std::vector<nlohmann::json> truth_lines(const std::string& relative, nlohmann::json* header = nullptr) {
  const std::string path = std::string(VRV_SOURCE_DIR) + "/" + relative;
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + path);
  std::vector<nlohmann::json> lines;
  std::string line;
  while (std::getline(in, line)) {
    nlohmann::json j = nlohmann::json::parse(line);
    if (j.contains("header")) {
      if (header) *header = j["header"];
      continue;
    }
    lines.push_back(std::move(j));
  }
  return lines;
}

// A truth line's grid scene: its nodes as the generator computed them ("grid_nodes", hex) are the
// doubles vrv's scene reader makes (the truth integrates the same grid).
inline void expect_grid_nodes_are_the_truths(const std::string& scene_toml, const std::vector<double>& nodes,
                                             const std::string& tag) {
  const Scene scene = parse_scene(scene_toml, tag);
  const auto& grid = std::get<GridField>(scene.field);
  const auto n = grid.resolution();
  ASSERT_EQ(nodes.size(), static_cast<std::size_t>(n[0]) * n[1] * n[2]) << tag;
  std::size_t idx = 0;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) EXPECT_EQ(grid.node(i, j, k), nodes[idx++]) << tag;
}

}  // namespace vrv::test
