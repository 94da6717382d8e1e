#pragma once
// The options several commands share, each documented once here: the reference's tolerance
// (vrv render, ray, demo, plan, verify) and an image's size (render, plan).  The command line adds
// their flags from here (studies/cli/discrete_flags.h add_shared_option), and their checks are the
// library's: check_tolerance (lib/reference_integrator.h) and the camera's sides (lib/camera.h).
// Each command keeps its own default, which its help shows: a reference for one image or ray is a
// truth at 1e-12 (ReferenceOptions' own default); verify and plan, made for many images, take
// kImagesReferenceTol.  The command line and the Python module take them from here and from the
// library's option structs, never spelled again.
#include <string_view>

#include "lib/option_error.h"

namespace vrv {

inline constexpr double kImagesReferenceTol = 1e-10;

// What a shared option means, for a help line (tol, width, height).  Throws std::invalid_argument
// for another option: the discrete options' help is in their own table (lib/discrete_options.h).
std::string_view shared_option_help(Option option);

}  // namespace vrv
