#pragma once
// What a verification reports (lib/verify.h's verify_images), and its JSON.  Every kind that logic
// depends on (a region, an order's series, a fault) is an enum; its text is in one table here.
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "lib/camera.h"
#include "lib/gradient_scheme.h"
#include "lib/metrics.h"

namespace vrv {

// The pixels a statistic covers: `silhouette` (within silhouette_band pixels of the volume's
// outline), `tf_jump` (other pixels whose ray crosses a value where the transfer function jumps),
// `interior` (the remaining pixels that hit the box), `outside` (the remaining ones), or all.
enum class Region : unsigned char { outside, interior, silhouette, tf_jump, all };
std::string_view region_name(Region region);  // "outside", "interior", "silhouette", "tf_jump", "all"

struct RegionStats {
  Region region = Region::all;
  long pixels = 0;
  ErrorStats stats;
};

struct ChannelReport {
  std::string image, channel;  // image name, channel name
  double step = 0;
  bool alpha = false;          // compared with the reference opacity, not the value
  long nan_count = 0;          // non-finite pixels (left out of every statistic)
  double quantum = 0, floor_max = 0, floor_rms = 0;  // the file's quantisation (0 for none)
  bool at_floor = false;       // the order metric is within 2x its quantisation floor: no order from it
  std::vector<RegionStats> regions;  // all first, then silhouette, interior, tf_jump (if any), outside
  std::vector<float> error;    // signed error image (value - reference), row-major; NaN where the pixel is
  const ErrorStats& all() const { return regions.front().stats; }
  const RegionStats* region(Region region) const;  // nullptr when not reported
};

// Which errors an order is fitted to.
enum class OrderKind {
  reference,  // against the reference
  self,       // differences of successive images (no reference)
};
std::string_view order_kind_name(OrderKind kind);  // "reference", "self"

struct OrderReport {
  std::string channel;
  OrderKind kind = OrderKind::reference;
  OrderEstimate fit;
  Judgement judgement;       // reference only; self: the verdict of the self-convergence sequence
  std::vector<double> steps, errors;  // the points fitted (self: differences, one fewer)
};

struct Candidate {
  std::string name;       // e.g. "inviwo placement, alpha rule, opacity corrected to the sample distance"
  std::string placement, rule, opacity;
  std::string color = "straight";  // alpha rule: "premultiplied" when colour is stored times opacity
  std::string table = "none";      // transfer function read from tables: "256 centred", "1024 uncentred"
  // A shaded scene's gradient scheme (lib/gradient_scheme.h): "analytic", "central" (the default
  // offset), "central 0.0156" (another offset), "nodes"; empty for an unshaded scene.
  std::string gradient;
  std::optional<GradientChoice> gradient_choice;  // the same, for logic; none when unshaded
  // false when the model takes an opacity per sample whatever the sample distance (no correction)
  bool opacity_corrected = true;
  double rms = 0, max = 0;  // RMS over all images of the per-pixel difference, and its max
  long pixels = 0;          // the pixels per image rms and max are over (lib/verify/diagnosis.h)
};

enum class FaultKind {
  quantisation,
  half_step_offset,
  constant_floor,
  first_order_border_band,
  jitter,
  error_at_tf_jumps,
  missing_opacity_correction,
  swapped_channels,  // an RGB image whose colour channels match the reference in another order
  gradient_floor,    // a shaded image whose floor is its gradient scheme's (lib/verify/fault_hints.h)
  fitted,  // an entry of the fitted fault catalogue (lib/verify/fault_fit.h); behaviour says which
};
// "quantisation", "half-step offset", "constant floor", "first-order border band", "jitter",
// "error at transfer-function jumps", "missing opacity correction", "swapped channels", "gradient floor",
// "fitted fault"
std::string_view fault_name(FaultKind kind);

struct Fault {
  Fault() = default;
  Fault(FaultKind k, std::string why, std::string does = {},
        double order = std::numeric_limits<double>::quiet_NaN())
      : kind(k), evidence(std::move(why)), behaviour(std::move(does)), implied_order(order) {}
  FaultKind kind = FaultKind::quantisation;
  std::string evidence;  // one sentence with the numbers
  // For a placement or rule: what the renderer does, in words ("samples at the start of each
  // step"), and the order of convergence that implies (NaN: none; lib/verify/conventions.h).
  std::string behaviour;
  double implied_order = std::numeric_limits<double>::quiet_NaN();
  std::string name() const { return std::string(fault_name(kind)); }
};

// One entry of the fitted fault catalogue (lib/verify/fault_fit.h), fitted to the finest image.
struct FaultFit {
  std::string id, name;    // "fov_scale", "field of view scale"
  std::string parameter;   // "scale"; empty for an entry without one
  double value = std::numeric_limits<double>::quiet_NaN();      // the fitted parameter
  double explained = std::numeric_limits<double>::quiet_NaN();  // 1 - SS(fit) / SS(model), on the subset
  double confirmed = std::numeric_limits<double>::quiet_NaN();  // the same on the diagnosis pixels (leaders)
  long pixels = 0, confirm_pixels = 0;
  std::string description;  // "field of view 2.0 % wider"
};

struct ReferenceInfo {
  double tol = 0;
  double max_error_estimate = 0;
  long missed = 0;                          // pixels whose estimate exceeds tol
  std::vector<std::pair<int, int>> missed_pixels;  // up to 10 of them, (x, y)
  bool from_cache = false;
  std::string cache_file;
  long hit_pixels = 0, silhouette_pixels = 0, jump_pixels = 0;
};

struct VerifyReport {
  int width = 0, height = 0;
  Camera camera;
  double threshold = 0;  // VerifyOptions::threshold, which fraction_over counts against
  Metric order_metric = Metric::rms;  // VerifyOptions::order_metric
  ReferenceInfo reference;
  std::vector<ChannelReport> channels;  // image-major (images sorted by decreasing step), then channel
  std::vector<OrderReport> orders;      // per channel: reference, then self
  Judgement verdict;                    // the worst channel's
  std::string verdict_channel;
  std::vector<Candidate> diagnosis;     // nearest first
  std::vector<Fault> faults;
  std::vector<FaultFit> fault_fits;     // ranked, best first; empty without a floor
  // Placements or rules consistent with the expected order: the renderer's convention, not a
  // fault (lib/verify/conventions.h).
  std::vector<Fault> conventions;
  std::optional<double> expected_order;  // VerifyOptions::expected_order
  bool pass = true;  // reference within tolerance and, with an expected order, convergence at it
  std::vector<std::string> failures;  // why not, one line each
  std::vector<float> reference_image;  // the reference values (for writing), row-major, interleaved
  int reference_channels = 1;          // 1 (grey) or 3 (an RGB scene: red, green, blue)
  // An RGB scene's channel the diagnosis, fault hints and floor decomposition read (the colour
  // channel with the largest error in the finest image); unset for a grey scene (the first
  // colour channel).
  std::optional<std::string> diagnosis_channel;
  std::optional<std::string> mode;     // a projection's mode (VerifyOptions::mode); none for EA
  std::vector<std::string> notes;      // what was not run, and why (projections)
};

nlohmann::ordered_json to_json(const VerifyReport& report);

}  // namespace vrv
