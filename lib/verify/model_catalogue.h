#pragma once
// The catalogue of vrv's discrete models of a renderer that the diagnosis (diagnosis.h) casts at
// the images' steps: every sample placement x segment rule; for opacity/colour transfer
// functions the renderers' convention (opacity per unit distance corrected to the sample
// distance), also with premultiplied colour; that corrected alpha rule with the transfer function
// read from N-entry tables, with and without half-texel centring; and, for
// emission/extinction, the opacity of a fixed unit distance left uncorrected.  On a shaded scene
// every model takes the gradient by central differences (the default); the diagnosis gives them
// the scheme nearest the images (with_gradient) and tries the others on its nearest model.
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "lib/discrete_raycast.h"
#include "lib/scene.h"
#include "lib/verify/verify_options.h"
#include "lib/verify/verify_report.h"

namespace vrv {

struct Model {
  Candidate label;                       // what the report says of it (rms and max still 0)
  std::vector<DiscreteConfig> per_step;  // its configuration at each of the images' steps
};

// The sample placements the diagnosis casts (step-based: they take the images' steps), each with
// the words the report names it by.
std::span<const std::pair<Strategy, const char*>> diagnosis_placements();

// The catalogue for images at `steps` (in the images' order), in the order the report lists ties.
std::vector<Model> model_catalogue(const Scene& scene, const std::vector<double>& steps, const VerifyOptions& options);

// A shaded scene's gradient schemes: central differences at the sample with the default offset
// (one voxel; first, so that ties keep it), the field's exact gradient, central differences at half
// and twice the default offset, and on a grid the node differences; none for an unshaded scene.
std::vector<GradientChoice> gradient_choices(const Scene& scene);
// `model` at every step with `gradient`, labelled for it.
Model with_gradient(const Model& model, const GradientChoice& gradient, const Scene& scene);
// `nearest` with each of gradient_choices.
std::vector<Model> gradient_variants(const Model& nearest, const Scene& scene);

// A configuration's cast on `scene` as text, with what does not change it normalised away: the
// table lookup without a table, and a centred table that holds every breakpoint of the transfer
// function on an entry (it reads the curves themselves, to rounding).  Equal keys cast the same.
std::string configuration_key(DiscreteConfig config, const Scene& scene);
// Whether two models have equal configuration keys at every step.
bool same_model(const Model& a, const Model& b, const Scene& scene);

}  // namespace vrv
