#pragma once
// Verifying any renderer from its images (`vrv verify`, docs/verify.md).
//
// Given a scene and a renderer's images of it at several sample distances, verify_images
//  1. renders the reference image for the images' size (once per size; cached on disk when
//     VerifyOptions::cache_dir and scene_text are given) and fails if it misses its tolerance;
//  2. per image and channel, the signed error against it and its statistics (lib/metrics.h) over
//     the whole image and over regions: `silhouette` (pixels within silhouette_band pixels of the
//     volume's outline, from which pixels' rays hit the box), `tf_jump` (other pixels whose ray
//     crosses a value where the transfer function jumps), `interior` (the remaining pixels that
//     hit the box) and `outside` (the remaining pixels that miss it);
//  3. across images: the observed order against the reference and the self-convergence order
//     (differences of successive images, no reference), each with its standard error, and a
//     verdict per channel and overall (the worst);
//  4. a diagnosis: vrv casts its own discrete models at the same steps and lists them by RMS
//     difference from the images, and the known faults whose pattern the errors match.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lib/camera.h"
#include "lib/discrete_raycast.h"
#include "lib/io/image_channels.h"
#include "lib/metrics.h"
#include "lib/scene.h"

namespace vrv {

// A renderer's image and the sample distance (world units) it was rendered with.
struct ImageWithStep {
  std::string name;  // the file, or a label: every message names it
  double step = 0;
  ChannelImage image;
};

enum class AlphaMode {
  premultiplied,  // colour channels are premultiplied by alpha (OpenEXR's convention)
  straight,       // colour channels are not premultiplied: they are multiplied by alpha here
};

struct VerifyOptions {
  // The camera the images were rendered with; default: the scene's [camera], else
  // default_camera(scene.box).  Width and height are always the images'.
  std::optional<Camera> camera;
  double reference_tol = 1e-10;   // absolute tolerance on I per reference pixel
  std::optional<double> expected_order;  // K: anything but convergence at K fails
  double order_tolerance = 0.25;  // observed >= K - tolerance converges at K
  Metric order_metric = Metric::rms;  // the statistic the order fits read
  double threshold = 1e-3;        // ErrorStats::fraction_over counts |e| > threshold
  // With an alpha channel, colour is taken as rendered over nothing, and vrv composites it over
  // the scene's background: C + background * (1 - A); the alpha channel itself is compared with
  // the reference opacity 1 - exp(-optical depth).
  AlphaMode alpha = AlphaMode::premultiplied;
  int silhouette_band = 2;        // pixels (Chebyshev distance) on each side of the outline
  int jump_samples = 512;         // field samples per ray to find transfer-function jump crossings
  bool diagnose = true;           // run the diagnosis (vrv's own models at the same steps)
  // The unit distance the uncorrected-opacity models take their opacity for; 0: the largest step.
  double unit_distance = 0;
  // Transfer-function table sizes the diagnosis models (each read with and without half-texel
  // centring, lib/transfer_table.h): 256 and 1024 entries are the common 1D texture and lookup
  // table sizes (8-bit scalars, VTK's and most GPU renderers' colour and opacity textures).
  std::vector<int> table_sizes = {256, 1024};
  // On-disk reference cache: the directory (created if missing) and the text that identifies
  // the scene (its TOML).  The key hashes scene_text, the camera, the size and reference_tol.
  // Either empty: no cache.
  std::filesystem::path cache_dir;
  std::string scene_text;
  bool progress = false;  // progress bars on stderr
  // NaN or infinite pixels: false refuses them (VerifyInputError naming the first); true counts
  // them (ChannelReport::nan_count, for a gate that bounds it) and leaves them out of every statistic.
  bool allow_nan = false;
};

// What `vrv verify`'s options and vrv.verify's keywords set alike, from their text, checked in
// this order; each problem is one std::invalid_argument naming the command-line option.
struct VerifySettings {
  double tol = 1e-10;            // --tol: positive and finite
  double order_tolerance = 0.25;  // --order-tolerance: positive
  std::string order_metric = "rms";  // --order-metric: max, mean, rms or p99
  double unit_distance = 0;      // --unit-distance: not negative
};
void apply(const VerifySettings& settings, VerifyOptions& options);

// Bad input (wrong size, NaN pixels, a missing step, ...): one line naming the image and reason.
class VerifyInputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

struct RegionStats {
  std::string region;  // "all", "silhouette", "interior", "tf_jump", "outside"
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
  std::vector<RegionStats> regions;
  std::vector<float> error;    // signed error image (value - reference), row-major; NaN where the pixel is
  const ErrorStats& all() const { return regions.front().stats; }
};

struct OrderReport {
  std::string channel;
  std::string kind;  // "reference" (against the reference) or "self" (successive differences)
  OrderFit fit;
  Judgement judgement;       // reference only; self: the verdict of the self-convergence sequence
  std::vector<double> steps, errors;  // the points fitted (self: differences, one fewer)
};

struct Candidate {
  std::string name;       // e.g. "inviwo placement, alpha rule, opacity corrected to the sample distance"
  std::string placement, rule, opacity;
  std::string color = "straight";  // alpha rule: "premultiplied" when colour is stored times opacity
  std::string table = "none";      // transfer function read from tables: "256 centred", "1024 uncentred"
  double rms = 0, max = 0;  // RMS over all images of the per-pixel difference, and its max
};

struct Fault {
  std::string name;      // "half-step offset", "missing opacity correction", "constant floor", ...
  std::string evidence;  // one sentence with the numbers
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

// Throws VerifyInputError for bad input (no images, images of different sizes, a non-positive
// or repeated step, NaN pixels when allow_nan is false); std::invalid_argument for bad options.
VerifyReport verify_images(const Scene& scene, const std::vector<ImageWithStep>& images,
                           const VerifyOptions& options);

nlohmann::ordered_json to_json(const VerifyReport& report);

// The reference image for a camera: per pixel value, error estimate and optical depth.
struct ReferenceImage {
  int width = 0, height = 0;
  std::vector<double> value, error_estimate, optical_depth;
  bool from_cache = false;
  std::string cache_file;
};
ReferenceImage reference_image(const Scene& scene, const Camera& camera, const VerifyOptions& options);

// The camera images of w x h pixels are judged with: VerifyOptions::camera, else the scene's, else
// default_camera(scene.box), at the images' size; VerifyInputError when it is not valid.
Camera verify_camera(const Scene& scene, const VerifyOptions& options, int width, int height);

// A discrete raycast of every pixel (vrv's own model of a renderer).
std::vector<double> discrete_image(const Scene& scene, const Camera& camera, const DiscreteConfig& config);

}  // namespace vrv
