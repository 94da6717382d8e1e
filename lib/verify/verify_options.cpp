#include "lib/verify/verify_options.h"

#include <fmt/format.h>

#include "lib/option_error.h"
#include "lib/reference_integrator.h"

namespace vrv {

void apply(const VerifySettings& s, VerifyOptions& o) {
  validate(ReferenceOptions{s.tol});
  if (!(s.order_tolerance > 0)) throw OptionError(Option::order_tolerance, "must be positive");
  const auto metric = parse_metric(s.order_metric);
  if (!metric || *metric == Metric::fraction_over)
    throw OptionError(Option::order_metric, fmt::format("'{}' is not one of max, mean, rms, p99", s.order_metric));
  if (s.unit_distance < 0) throw OptionError(Option::unit_distance, "must be positive");
  if (s.alpha != "auto" && s.alpha != "premultiplied" && s.alpha != "straight")
    throw OptionError(Option::alpha, fmt::format("'{}' is not auto, premultiplied or straight", s.alpha));
  o.reference_tol = s.tol;
  o.order_tolerance = s.order_tolerance;
  o.order_metric = *metric;
  o.unit_distance = s.unit_distance;
  o.alpha = s.alpha == "straight" ? AlphaMode::straight
            : s.alpha == "premultiplied" ? AlphaMode::premultiplied : AlphaMode::as_stored;
}

}  // namespace vrv
