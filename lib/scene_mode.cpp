#include "lib/scene_mode.h"

#include <fmt/format.h>
#include <toml++/toml.h>

namespace vrv {

std::optional<ProjectionMode> scene_mode(std::string_view toml_text) {
  toml::table doc;
  try {
    doc = toml::parse(toml_text);
  } catch (const toml::parse_error&) {
    return std::nullopt;  // parse_scene reports it
  }
  const std::optional<std::string_view> name = doc["mode"].value<std::string_view>();
  return name ? parse_projection_mode(*name) : std::nullopt;
}

std::string projection_refusal(ProjectionMode mode, std::string_view who) {
  return fmt::format("the scene asks for the {} projection (its key mode), which {} not draw (emission-absorption "
                     "only); vrv ray, render, verify and gate project it", projection_mode_name(mode), who);
}

std::string chosen_mode(const std::string& option, std::string_view scene_text) {
  if (option == kEmissionAbsorption) return {};
  if (!option.empty()) return option;
  const auto m = scene_mode(scene_text);
  return m ? std::string(projection_mode_name(*m)) : std::string();
}

}  // namespace vrv
