#pragma once
// Small pieces shared by the subcommands: parsing vectors as users type them, loading the
// scene (or the embedded default), and turning results into JSON.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "lib/reference_integrator.h"
#include "lib/scene.h"

namespace vrv::cli {

// "x,y,z" -> Vec3; throws std::invalid_argument naming `option` and the reason.
Vec3 parse_vec3(const std::string& text, const std::string& option);
// The scene file, or the embedded default when `path` is empty.
Scene load_scene_or_default(const std::string& path);
nlohmann::ordered_json to_json(const ReferenceResult& r);
// Validates --tol: positive and finite.
void check_tolerance(double tol);

}  // namespace vrv::cli
