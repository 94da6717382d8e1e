#pragma once
// The truth files of the adversarial tests: JSON lines written by the mpmath generators beside
// them (a header line, then one line per ray), with exact doubles written as hex.
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lib/geometry.h"

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

}  // namespace vrv::test
