#pragma once
// What a verification is asked to do (`vrv verify`'s options, vrv.verify's keywords), and the
// error for bad input.  The steps are lib/verify.h's overview.
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "lib/camera.h"
#include "lib/metrics.h"
#include "lib/projection/projection_mode.h"
#include "lib/shared_options.h"

namespace vrv {

enum class AlphaMode {
  as_stored,      // as the file declares: straight where it says so (PNG), else premultiplied
  premultiplied,  // colour channels are premultiplied by alpha (OpenEXR's convention)
  straight,       // colour channels are not premultiplied: they are multiplied by alpha here
};
std::string_view alpha_mode_name(AlphaMode mode);               // "auto", "premultiplied", "straight"
std::optional<AlphaMode> parse_alpha_mode(std::string_view name);
std::string alpha_mode_list();                                  // "auto, premultiplied, straight"

struct VerifyOptions {
  // The camera the images were rendered with; default: the scene's [camera], else
  // default_camera(scene.box).  Width and height are always the images'.
  std::optional<Camera> camera;
  double reference_tol = kImagesReferenceTol;  // absolute tolerance on I per reference pixel
  std::optional<double> expected_order;  // K: anything but convergence at K fails
  double order_tolerance = 0.25;  // observed >= K - tolerance converges at K
  Metric order_metric = Metric::rms;  // the statistic the order fits read
  double threshold = 1e-3;        // ErrorStats::fraction_over counts |e| > threshold
  // With an alpha channel, colour is taken as rendered over nothing, and vrv composites it over
  // the scene's background: C + background * (1 - A); the alpha channel itself is compared with
  // the reference opacity 1 - exp(-optical depth).
  AlphaMode alpha = AlphaMode::as_stored;
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
  // A projection instead of emission-absorption (lib/verify/projection_models.h): the reference,
  // the expected order when none is given, and the diagnosis are the mode's.
  std::optional<ProjectionMode> mode;
};

// What `vrv verify`'s options and vrv.verify's keywords set alike, from their text, checked in
// this order; each problem is one OptionError naming the option.  The defaults are VerifyOptions'
// own, as the user would type them: the command line and the Python module bind these fields.
struct VerifySettings {
  double tol = VerifyOptions{}.reference_tol;                 // --tol: positive and finite
  double order_tolerance = VerifyOptions{}.order_tolerance;   // --order-tolerance: positive
  std::string order_metric{metric_name(VerifyOptions{}.order_metric)};  // --order-metric: max, mean, rms or p99
  double unit_distance = VerifyOptions{}.unit_distance;       // --unit-distance: not negative
  std::string alpha{alpha_mode_name(VerifyOptions{}.alpha)};  // --alpha: auto, premultiplied or straight
};
void apply(const VerifySettings& settings, VerifyOptions& options);

// Bad input (wrong size, NaN pixels, a missing step, ...): one line naming the image and reason.
class VerifyInputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace vrv
