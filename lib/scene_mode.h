#pragma once
// A scene file's `mode = "xray" | "xray_classified" | "mip" | "mip_classified"`: a projection
// instead of emission-absorption, the default of `--mode` for ray, render, verify and gate
// (docs/projections.md).  Kept beside the Scene, not in it, so that emission-absorption code and
// its hashes do not see it.
#include <optional>
#include <string>
#include <string_view>

#include "lib/projection/projection_mode.h"

namespace vrv {

// The mode of a scene text that parse_scene accepted (it checks the key: one line naming the file,
// `mode` and the reason); none without the key.
std::optional<ProjectionMode> scene_mode(std::string_view toml_text);

// Why `who` ("vrv plan does", "the studies do") refuses a scene with this mode rather than draw
// emission-absorption in its place: one wording for every command and study reader.
std::string projection_refusal(ProjectionMode mode, std::string_view who);

// --mode's value for emission-absorption: it overrides a scene's mode.
inline constexpr const char* kEmissionAbsorption = "emission_absorption";

// The mode a command runs: its --mode text when given (kEmissionAbsorption: ""), else the
// scene's; "" for emission-absorption.
std::string chosen_mode(const std::string& option, std::string_view scene_text);

}  // namespace vrv
