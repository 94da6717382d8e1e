#include "studies/cli/cli_support.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "lib/scene_file.h"
#include "lib/scene_mode.h"
#include "lib/reference_integrator.h"

namespace vrv::cli {

Vec3 parse_vec3(const std::string& text, const std::string& option) {
  Vec3 v;
  const char* p = text.data();
  const char* end = text.data() + text.size();
  for (int i = 0; i < 3; ++i) {
    while (p < end && *p == ' ') ++p;
    if (p < end && *p == '+') ++p;
    double x = 0;
    const auto [next, ec] = std::from_chars(p, end, x);
    if (ec != std::errc() || !std::isfinite(x))
      throw std::invalid_argument(
          fmt::format("{}: expected three finite comma-separated numbers, got '{}'", option, text));
    v[i] = x;
    p = next;
    while (p < end && *p == ' ') ++p;
    if (i < 2) {
      if (p == end || *p != ',')
        throw std::invalid_argument(
            fmt::format("{}: expected three comma-separated numbers, got '{}'", option, text));
      ++p;
    }
  }
  if (p != end)
    throw std::invalid_argument(
        fmt::format("{}: expected exactly three comma-separated numbers, got '{}'", option, text));
  return v;
}

Scene load_scene_or_default(const std::string& path, double max_volume_bytes) {
  return path.empty() ? default_scene() : load_scene(path, max_volume_bytes);
}

std::string scene_text_or_default(const std::string& path) {
  if (path.empty()) return std::string(default_scene_toml());
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void require_emission_absorption(const std::string& path, std::string_view what) {
  if (path.empty()) return;  // the default scene has no mode
  if (const auto mode = scene_mode(scene_text_or_default(path)))
    throw std::invalid_argument(fmt::format("{}: mode: {}", path, projection_refusal(*mode, fmt::format("{} does", what))));
}

nlohmann::ordered_json to_json(const ReferenceResult& r) {
  nlohmann::ordered_json j;
  j["value"] = finite_or_null(r.value);
  j["error_estimate"] = finite_or_null(r.error_estimate);
  j["evaluations"] = r.evaluations;
  j["t_entry"] = r.hit ? nlohmann::ordered_json(r.t_entry) : nlohmann::ordered_json(nullptr);
  j["t_exit"] = r.hit ? nlohmann::ordered_json(r.t_exit) : nlohmann::ordered_json(nullptr);
  j["optical_depth"] = finite_or_null(r.optical_depth);
  j["tolerance_met"] = r.tolerance_met;
  return j;
}


void check_threads(int threads) {
  if (threads < 0)
    throw std::invalid_argument(fmt::format("--threads: must not be negative, got {}", threads));
}

nlohmann::ordered_json finite_or_null(double x) {
  return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr);
}

}  // namespace vrv::cli
