#pragma once
// What a verification reports (lib/verify.h's verify_images), and its JSON.  Every kind that logic
// depends on (a region, an order's series, a fault) is an enum; its text is in one table here.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "lib/camera.h"
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
};
// "quantisation", "half-step offset", "constant floor", "first-order border band", "jitter",
// "error at transfer-function jumps", "missing opacity correction"
std::string_view fault_name(FaultKind kind);

struct Fault {
  FaultKind kind = FaultKind::quantisation;
  std::string evidence;  // one sentence with the numbers
  std::string name() const { return std::string(fault_name(kind)); }
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
  bool pass = true;  // reference within tolerance and, with an expected order, convergence at it
  std::vector<std::string> failures;  // why not, one line each
  std::vector<float> reference_image;  // the reference values (for writing), row-major
};

nlohmann::ordered_json to_json(const VerifyReport& report);

}  // namespace vrv
