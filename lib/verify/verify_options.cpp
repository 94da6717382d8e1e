#include "lib/verify/verify_options.h"

#include <cmath>

#include <fmt/format.h>

#include "lib/option_error.h"
#include "lib/reference_integrator.h"
#include "lib/util/enum_names.h"

namespace vrv {

namespace {

constexpr NameTable<AlphaMode, 3> kAlphaModes{{{AlphaMode::as_stored, "auto"},
                                               {AlphaMode::premultiplied, "premultiplied"},
                                               {AlphaMode::straight, "straight"}}};
static_assert(names_complete(kAlphaModes));

}  // namespace

std::string_view alpha_mode_name(AlphaMode mode) { return name_of(kAlphaModes, mode); }
std::optional<AlphaMode> parse_alpha_mode(std::string_view name) { return parse_name(kAlphaModes, name); }
std::string alpha_mode_list() { return name_list(kAlphaModes); }

void apply(const VerifySettings& s, VerifyOptions& o) {
  validate(ReferenceOptions{s.tol});
  if (!(s.order_tolerance > 0)) throw OptionError(Option::order_tolerance, "must be positive");
  const auto metric = parse_metric(s.order_metric);
  if (!metric || *metric == Metric::fraction_over)
    throw OptionError(Option::order_metric, fmt::format("'{}' is not one of max, mean, rms, p99", s.order_metric));
  if (!(s.unit_distance >= 0 && std::isfinite(s.unit_distance)))
    throw OptionError(Option::unit_distance, "must be positive and finite (0, the default: the largest step)");
  const auto alpha = parse_alpha_mode(s.alpha);
  if (!alpha) throw OptionError(Option::alpha, fmt::format("'{}' is not one of {}", s.alpha, alpha_mode_list()));
  o.reference_tol = s.tol;
  o.order_tolerance = s.order_tolerance;
  o.order_metric = *metric;
  o.unit_distance = s.unit_distance;
  o.alpha = *alpha;
}

}  // namespace vrv
