#include "lib/verify/channel_errors.h"

#include <cmath>
#include <limits>

namespace vrv {

ChannelReport channel_report(const ImageWithStep& im, int c, const ReferenceImage& ref,
                             const PixelGeometry& geo, double background, const VerifyOptions& opt) {
  ChannelReport r;
  r.image = im.name;
  r.channel = im.image.names[c];
  r.step = im.step;
  r.alpha = c == im.image.alpha;
  // An 8- or 16-bit framebuffer saved as float has its integers' floor (effective_quantum).
  r.quantum = effective_quantum(im.image);
  r.floor_max = r.quantum / 2;
  r.floor_rms = r.quantum / std::sqrt(12.0);
  const std::size_t n = ref.pixel_count();
  r.error.assign(n, std::numeric_limits<float>::quiet_NaN());
  std::vector<double> by_region[4], all;  // indexed by the pixel regions (outside ... tf_jump)
  for (std::size_t i = 0; i < n; ++i) {
    const double v = comparable(im.image, c, i, background, opt.alpha);
    if (!std::isfinite(v)) {
      ++r.nan_count;
      continue;
    }
    const double truth = r.alpha ? -std::expm1(-ref.optical_depth[i]) : ref.pixels[i];
    const double e = v - truth;
    r.error[i] = static_cast<float>(e);
    all.push_back(e);
    by_region[static_cast<int>(geo.region[i])].push_back(e);
  }
  r.regions.push_back({Region::all, static_cast<long>(all.size()), error_stats(all, opt.threshold)});
  for (Region k : {Region::silhouette, Region::interior, Region::tf_jump, Region::outside}) {
    const std::vector<double>& errors = by_region[static_cast<int>(k)];
    if (!errors.empty() || k != Region::tf_jump)
      r.regions.push_back({k, static_cast<long>(errors.size()), error_stats(errors, opt.threshold)});
  }
  const double floor = opt.order_metric == Metric::max ? r.floor_max : r.floor_rms;
  r.at_floor = r.quantum > 0 && metric_value(r.all(), opt.order_metric) <= 2 * floor;
  return r;
}

double difference_metric(const ChannelImage& a, const ChannelImage& b, int c, double background,
                         const VerifyOptions& opt) {
  std::vector<double> d;
  for (std::size_t i = 0; i < a.pixel_count(); ++i) {
    const double x = comparable(a, c, i, background, opt.alpha) - comparable(b, c, i, background, opt.alpha);
    if (std::isfinite(x)) d.push_back(x);
  }
  return metric_value(error_stats(d, opt.threshold), opt.order_metric);
}

}  // namespace vrv
