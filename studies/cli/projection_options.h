#pragma once
// --mode for `ray` and `render`: X-ray and maximum intensity projections instead of the
// emission-absorption integral (lib/projection/), by the reference or, with --method, discretely.
#include <optional>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "lib/projection/discrete_projection.h"
#include "lib/projection/projection_mode.h"
#include "lib/projection/projection_result.h"
#include "lib/scene.h"
#include "studies/cli/discrete_flags.h"

namespace vrv::cli {

struct ProjectionSetup {
  ProjectionMode mode = ProjectionMode::mip;
  std::optional<DiscreteProjectionConfig> discrete;  // --method given
  // The discrete raycast whose samples count the discrete projection's work (work estimates).
  std::optional<DiscreteConfig> work;
};

// Adds --mode to the command, writing into `mode`.
void add_mode_option(CLI::App& cmd, std::string& mode);

// Nothing without --mode.  With it, --method names the X-ray rule (riemann, trapezoid, simpson)
// or, for the MIP modes, `max` (the largest sample), placed by --strategy/--rate/--step; every
// other discrete option is refused.  Throws std::invalid_argument naming the option.
std::optional<ProjectionSetup> projection_setup(const std::string& mode, const DiscreteOptions& opt, const Scene& scene);

nlohmann::ordered_json to_json(const ProjectionResult& r, ProjectionMode mode);
nlohmann::ordered_json to_json(const DiscreteProjectionResult& r, ProjectionMode mode);

}  // namespace vrv::cli
