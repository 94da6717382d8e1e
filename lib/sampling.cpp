#include "lib/sampling.h"

#include "lib/option_error.h"
#include "lib/util/enum_names.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace vrv {

bool step_based(Strategy st) {
  return st == Strategy::step || st == Strategy::vtk || st == Strategy::inviwo || st == Strategy::partial ||
         st == Strategy::exit_anchored;
}

namespace {

constexpr NameTable<Strategy, 9> kStrategyNames{{
    {Strategy::eye, "eye"},
    {Strategy::entry, "entry"},
    {Strategy::entry_exit, "entry_exit"},
    {Strategy::entry_exit_corner, "entry_exit_corner"},
    {Strategy::step, "step"},
    {Strategy::vtk, "vtk"},
    {Strategy::inviwo, "inviwo"},
    {Strategy::partial, "partial"},
    {Strategy::exit_anchored, "exit_anchored"},
}};
static_assert(names_complete(kStrategyNames));

// More samples than this on one ray is a configuration error, not a plan.
constexpr double kMaxSamples = 1e12;

bool rate_based(Strategy s) {
  return s == Strategy::eye || s == Strategy::entry || s == Strategy::entry_exit ||
         s == Strategy::entry_exit_corner;
}

std::string number(double x) { return fmt::format("{}", x); }

// A plan with no samples: t(0) = t_end, so the loop predicate t(k) < t_end is false at once.
SamplePlan empty_plan(double t_end) { return SamplePlan{t_end, 0, t_end, 0}; }

// Samples t_first + k * dt (k = 0, 1, ...) while < t_end.  The count is found for exactly the
// expression SamplePlan::t(k) evaluates; that expression is non-decreasing in k (a product and a
// sum, each correctly rounded, are monotone), so the samples that pass form a prefix.
SamplePlan make_plan(double t_first, double dt, double t_end, Option option) {
  if (!std::isfinite(t_first) || !std::isfinite(t_end) || !std::isfinite(dt) || !(dt > 0)) {
    return empty_plan(t_end);
  }
  SamplePlan plan{t_first, dt, t_end, 0};
  if (!(t_first < t_end)) return plan;
  const double estimate = std::ceil((t_end - t_first) / dt);
  if (!(estimate <= kMaxSamples)) {
    throw OptionError(option, "gives more than 1e12 samples on one ray");
  }
  long n = std::max(1L, static_cast<long>(estimate));
  while (n > 0 && !(plan.t(n - 1) < t_end)) --n;
  while (plan.t(n) < t_end) ++n;
  plan.count = n;
  return plan;
}

void check_positive(double value, Option option) {
  if (!(std::isfinite(value) && value > 0))
    throw OptionError(option, "must be a positive finite number, got " + number(value));
}

double fract(double x) { return x - std::floor(x); }

// Listings 1-4 of Steneteg et al., in texture space (box -> [0,1]^3), mapped back to world units.
SamplePlan plan_rate(const SamplingConfig& c, const Ray& ray, Interval iv, const Box& box) {
  const Vec3 ext = box.extent();
  if (!ext.allFinite() || !(ext.minCoeff() > 0)) {
    throw std::invalid_argument("the volume box must have a positive, finite extent");
  }
  for (int d : c.dims) {
    if (d < 1) throw std::invalid_argument("the sampling grid dims must be at least 1 in every direction");
  }
  const Vec3 dim(c.dims[0], c.dims[1], c.dims[2]);
  const double length = iv.length();  // world length of the chord

  // ray = exitPoint - entryPoint with exitPoint = tex(ray.at(t1)), entryPoint = tex(ray.at(t0)).
  // Computed as (t1 - t0) d / extent, equal in exact arithmetic and free of the cancellation
  // that subtracting two nearby texture points would suffer on short corner chords.
  const Vec3 ray_tex = (length * ray.direction).cwiseQuotient(ext);
  const double t_end_tex = ray_tex.norm();  // tEnd
  if (!(t_end_tex > 0) || !std::isfinite(t_end_tex)) return empty_plan(iv.t1);

  double samples = 0;
  switch (c.strategy) {
    case Strategy::eye:
    case Strategy::entry:
      samples = ray_tex.cwiseProduct(dim).norm() * c.rate;
      break;
    case Strategy::entry_exit:
      samples = std::floor(ray_tex.cwiseProduct(dim).norm() * c.rate);
      break;
    case Strategy::entry_exit_corner:
      samples = std::ceil(c.rate * ray_tex.cwiseProduct(dim - Vec3::Ones()).norm());
      break;
    default:
      break;
  }
  // samples == 0: Listing 3 drops a chord shorter than one step (tIncr = tEnd / 0); Listing 4
  // only gets here when dims - 1 is 0 along the whole ray (dims of 1).
  if (!(samples > 0)) return empty_plan(iv.t1);
  if (!(samples <= kMaxSamples)) {
    throw OptionError(Option::rate, "gives more than 1e12 samples on one ray");
  }

  // World step: tIncr = tEnd / samples in texture units; the texture length tEnd of the chord
  // maps linearly onto its world length, so the world step is length / samples.
  const double dt = length / samples;
  double first_fraction = 0.5;  // tStart / tIncr
  if (c.strategy == Strategy::eye) {
    const Vec3 entry = (ray.at(iv.t0) - box.min).cwiseQuotient(ext);
    const Vec3 eye = (c.eye.value_or(ray.origin) - box.min).cwiseQuotient(ext);
    const double t_incr_tex = t_end_tex / samples;
    const double num_steps = (entry - eye).norm() / t_incr_tex;
    first_fraction = 1 - fract(num_steps);  // in (0, 1]: the entry itself is never sampled
  }
  return make_plan(iv.t0 + first_fraction * dt, dt, iv.t1, Option::rate);
}

// n = floor(length / h) whole steps at their midpoints and the partial step r = length - n h at
// its own: after them from the entry, or, anchored at the exit, before them.
SamplePlan plan_with_partial_step(bool from_exit, double h, Interval iv, double length) {
  const double ratio = length / h;
  if (!(ratio <= kMaxSamples)) throw OptionError(Option::step, "gives more than 1e12 samples on one ray");
  const double n = std::floor(ratio);
  const double r = length - n * h;
  const double t0 = from_exit ? iv.t1 - n * h : iv.t0;  // where the whole steps start
  // t_end closes the whole steps, so count stays exact for t(k) < t_end.
  SamplePlan plan = n > 0 ? make_plan(t0 + 0.5 * h, h, t0 + n * h, Option::step) : empty_plan(iv.t1);
  if (r > 0) {
    plan.partial = r;
    plan.partial_first = from_exit;
    plan.t_partial = from_exit ? iv.t0 + 0.5 * r : iv.t1 - 0.5 * r;
  }
  return plan;
}

}  // namespace

std::optional<Strategy> parse_strategy(std::string_view name) { return parse_name(kStrategyNames, name); }
std::string strategy_list() { return name_list(kStrategyNames); }
std::string strategy_list(std::span<const Strategy> strategies) {
  std::string s;
  for (const Strategy st : strategies) s.append(s.empty() ? "" : ", ").append(strategy_name(st));
  return s;
}

std::string_view strategy_name(Strategy s) { return name_of(kStrategyNames, s); }

std::vector<Strategy> strategies_where(bool (*keep)(Strategy)) {
  std::vector<Strategy> out;
  for (const auto& [s, name] : kStrategyNames)
    if (keep(s)) out.push_back(s);
  return out;
}

void check_sampling(const SamplingConfig& config) {
  if (rate_based(config.strategy)) check_positive(config.rate, Option::rate);
  else check_positive(config.step, Option::step);
}

SamplePlan plan_samples(const SamplingConfig& config, const Ray& ray, Interval iv, const Box& box) {
  const bool by_rate = rate_based(config.strategy);
  check_sampling(config);
  if (!std::isfinite(iv.t0) || !std::isfinite(iv.t1)) {
    throw std::invalid_argument("plan_samples: the clipped ray interval must be finite");
  }
  // A degenerate chord (a ray grazing an edge or corner) carries no length: no samples.
  if (!(iv.length() > 0)) return empty_plan(iv.t1);

  if (by_rate) return plan_rate(config, ray, iv, box);

  const double h = config.step;
  const double length = iv.length();
  switch (config.strategy) {
    case Strategy::step:
      return make_plan(iv.t0 + 0.5 * h, h, iv.t1, Option::step);
    case Strategy::vtk:
      // First sample one full step inside; a sample exactly on the exit is kept (t <= t1).
      return make_plan(iv.t0 + h, h, std::nextafter(iv.t1, std::numeric_limits<double>::infinity()),
                       Option::step);
    case Strategy::inviwo: {
      const double ratio = length / h;
      if (!(ratio <= kMaxSamples)) {
        throw OptionError(Option::step, "gives more than 1e12 samples on one ray");
      }
      const double n = std::max(1.0, std::round(ratio));
      const double dt = length / n;
      return make_plan(iv.t0 + 0.5 * dt, dt, iv.t1, Option::step);
    }
    case Strategy::partial:
    case Strategy::exit_anchored:
      return plan_with_partial_step(config.strategy == Strategy::exit_anchored, h, iv, length);
    default:
      break;
  }
  throw std::invalid_argument("plan_samples: unknown strategy");
}

}  // namespace vrv
