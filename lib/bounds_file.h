#pragma once
// Bounds files (TOML): the limits a verification is gated on, read by `vrv verify --bounds` and
// `vrv gate --bounds`.  Format (docs/verify.md):
//
//   description = "..."              # optional
//   [defaults]                       # every case starts from these
//   threshold = 1e-3                 # |e| above it counts for percent_over
//   at = "finest"                    # error bounds read the finest image, or "all" (every image)
//   rms = { warn = 1e-4, fail = 1e-3, hard_fail = 1e-2 }   # any of the three levels
//   # also: max, mean, p99, percent_over (percent of pixels over threshold): upper limits;
//   # min_order (observed order against the reference, lowest channel): lower limits;
//   # max_nan (NaN or infinite pixels over all images): upper limits
//   [[case]]                         # what `vrv gate` runs; `vrv verify --bounds` uses [defaults]
//   name = "alpha-step"              #   (and the case named by --case)
//   scene = "scene.toml"             # relative to the bounds file; the embedded default without it
//   steps = [0.2, 0.1, 0.05]
//   expected_order = 2               # optional: the verdict must be convergence at it
//   render = { method = "alpha", strategy = "step" }   # vrv renders its own method at the steps
//   # or images = ["a.exr", "b.exr"] (one per step, relative to the bounds file); an images case
//   #   without steps takes each image's step from its provenance (vrv:step, lib/io/image_io.h)
//   # or study = "convergence"       (runs `vrv study NAME --quick`; gated on its checks)
//   width = 48                       # render cases: image size (default: the scene's camera)
//   height = 48
//   rms = { fail = 1e-2 }            # overrides: a case's table replaces the default's for that bound
//
// Levels must be ordered: warn <= fail <= hard_fail for upper limits, warn >= fail >= hard_fail
// for lower ones.  Unknown keys, wrong types and non-finite numbers are errors.
#include <array>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "lib/discrete_options.h"
#include "lib/verify/verify_options.h"

namespace vrv {

// "<file>: <key>: <reason>", one line.
class BoundsFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class Bound { max, mean, rms, p99, percent_over, min_order, max_nan };
std::string_view bound_name(Bound b);  // the TOML key
inline bool is_lower_limit(Bound b) { return b == Bound::min_order; }
inline constexpr std::array<Bound, 7> kAllBounds = {Bound::max, Bound::mean, Bound::rms, Bound::p99,
                                                    Bound::percent_over, Bound::min_order, Bound::max_nan};

struct Limits {
  std::optional<double> warn, fail, hard_fail;
};

struct BoundSet {
  std::map<Bound, Limits> limits;
  double threshold = VerifyOptions{}.threshold;  // verify's own default
  bool all_images = false;  // at = "all": error bounds on every image, not only the finest
};

// A case where vrv renders its own discrete method: `render = { ... }` holds the options of
// `vrv render` as keys (lib/discrete_options.h), every one but the step (the case's steps), rate
// and max_work; the method defaults to alpha and the strategy to step.  Values are checked by
// discrete_config, as the command line checks them, before any case runs (vrv gate).
struct GateRenderSpec {
  DiscreteOptions options;
};

struct GateCase {
  std::string name;
  std::filesystem::path scene;  // empty: the embedded default scene
  std::vector<double> steps;  // empty only for an images case: the images' provenance steps
  std::optional<double> expected_order;
  std::optional<GateRenderSpec> render;
  std::vector<std::filesystem::path> images;
  std::string study;
  std::optional<int> width, height;
  BoundSet bounds;  // defaults with this case's overrides
};

struct BoundsFile {
  std::filesystem::path path;
  std::string description;
  BoundSet defaults;
  std::vector<GateCase> cases;
};

BoundsFile parse_bounds(std::string_view toml_text, const std::filesystem::path& source);
BoundsFile load_bounds(const std::filesystem::path& path);

// The case named `name` (--case NAME); std::invalid_argument "--case: <file>: no case named
// '<name>'" when there is none.
const GateCase& named_case(const BoundsFile& file, const std::string& name);
// The bounds `vrv verify --bounds FILE [--case NAME]` gates on: the named case's, else [defaults].
const BoundSet& chosen_bounds(const BoundsFile& file, const std::optional<std::string>& case_name);

}  // namespace vrv
