// Study kind "sampling": reads the study file (the paper's set-up, the strategies, the rates, the
// images and the bounds) into a Study; run.cpp runs it and writes the outputs.
#include <algorithm>

#include <fmt/format.h>

#include "lib/camera.h"
#include "lib/geometry.h"
#include "studies/engine/study_driver.h"
#include "studies/sampling/fan.h"
#include "studies/sampling/run.h"

namespace vrv::sampling_study {
namespace {

std::array<double, 2> pair(const StudyReader& r, const toml::table& t, std::string_view key,
                           std::string_view path) {
  const std::vector<double> v = r.numbers(t, key, path, -1e6, 1e6);
  if (v.size() != 2) r.fail(StudyReader::child(path, key), "expected two numbers (x, y)");
  return {v[0], v[1]};
}

FanSetup read_setup(const StudyReader& r, const toml::table& doc) {
  const toml::table& t = r.table(r.require(doc, "setup", ""), "setup");
  r.check_keys(t, "setup", {"eye", "centre", "rotation_degrees", "angle_degrees", "fov_degrees", "rays"});
  FanSetup s;
  s.eye = pair(r, t, "eye", "setup");
  s.centre = pair(r, t, "centre", "setup");
  s.rotation_degrees = r.number(r.require(t, "rotation_degrees", "setup"), "setup.rotation_degrees");
  s.angle_degrees = r.number_or(t, "angle_degrees", "setup", 0);
  s.fov_degrees = r.number(r.require(t, "fov_degrees", "setup"), "setup.fov_degrees");
  if (!(s.fov_degrees > 0 && s.fov_degrees < 180))
    r.fail("setup.fov_degrees", fmt::format("must be in (0, 180), got {}", s.fov_degrees));
  s.rays = static_cast<int>(r.integer(r.require(t, "rays", "setup"), "setup.rays", 1, 100000));
  return s;
}

std::vector<Strategy> read_strategies(const StudyReader& r, const toml::table& t, std::string_view key,
                                      std::string_view path) {
  const std::vector<Strategy> rate_based = strategies_where([](Strategy s) { return !step_based(s); });
  return read_choices<Strategy>(r, t, key, path, rate_based, parse_strategy, strategy_name);
}

// Strategies named under [checks] must be among the study's strategies.
std::vector<Strategy> read_subset(const StudyReader& r, const toml::table& t, std::string_view key,
                                  const std::vector<Strategy>& all) {
  if (!t.contains(key)) return {};
  const std::vector<Strategy> v = read_strategies(r, t, key, "checks");
  for (std::size_t i = 0; i < v.size(); ++i)
    if (std::find(all.begin(), all.end(), v[i]) == all.end())
      r.fail(fmt::format("checks.{}[{}]", key, i), "not among the study's strategies");
  return v;
}

// The paper's f is a linear ramp sampled on the grid; the ramp itself is kept for the identity
// check (trilinear interpolation of a linear function is exact).
LinearRamp read_ramp(const StudyReader& r, const toml::table& doc, const Scene& scene) {
  const toml::table& field = r.table(*doc.at_path("scene.field").node(), "scene.field");
  const toml::node* source = field.get("source");
  if (!std::holds_alternative<GridField>(scene.field) || !source)
    r.fail("scene.field", "must be a grid (kind = \"grid\") sampled from a linear_ramp");
  const toml::table& src = r.table(*source, "scene.field.source");
  if (r.string(r.require(src, "kind", "scene.field.source"), "scene.field.source.kind") != "linear_ramp")
    r.fail("scene.field.source.kind", "must be linear_ramp (the paper's f = (x + 1.5)/3)");
  LinearRamp ramp;
  ramp.gradient = r.vec3(src, "gradient", "scene.field.source");
  ramp.offset = r.number_or(src, "offset", "scene.field.source", 0);
  return ramp;
}

// orders.rules: sample rules only (riemann first: the paper's eq. (5), used by curves and images).
std::vector<SegmentRule> read_rules(const StudyReader& r, const toml::table& orders) {
  const toml::array& a = r.array(r.require(orders, "rules", "orders"), "orders.rules");
  std::vector<SegmentRule> out;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string p = fmt::format("orders.rules[{}]", i);
    const auto rule = parse_segment_rule(r.string(*a.get(i), p));
    if (!rule || is_segment_rule(*rule))
      r.fail(p, "expected a sample rule (riemann or alpha): segment rules place nodes, not samples");
    if (std::find(out.begin(), out.end(), *rule) != out.end()) r.fail(p, "listed twice");
    out.push_back(*rule);
  }
  if (out.empty() || out.front() != SegmentRule::riemann)
    r.fail("orders.rules", "must start with riemann (the paper's eq. (5), used by curves and images)");
  return out;
}

// [[checks.order]] {rule, strategies, min_order} (a lower bound on the observed orders) and
// [[checks.exact]] {rule, strategies, max_error} (configurations that reproduce the continuous
// solution up to rounding): the same shape, read once.  Bound is Study::OrderBound or ExactBound;
// `read_value` is StudyReader::number (an order: any bound can fail, a slope can be negative) or
// non_negative (an error).
template <class Bound>
std::vector<Bound> read_bounds(const StudyReader& r, const toml::table& checks, const Study& st,
                               std::string_view key, std::string_view value_key,
                               double (StudyReader::*read_value)(const toml::node&, std::string_view) const) {
  std::vector<Bound> out;
  const toml::node* n = checks.get(key);
  if (!n) return out;
  const std::string at = fmt::format("checks.{}", key);
  const toml::array& a = r.array(*n, at);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const std::string p = fmt::format("{}[{}]", at, i);
    const toml::table& t = r.table(*a.get(i), p);
    r.check_keys(t, p, {"rule", "strategies", value_key});
    const auto rule = parse_segment_rule(r.string(r.require(t, "rule", p), p + ".rule"));
    if (!rule || std::find(st.rules.begin(), st.rules.end(), *rule) == st.rules.end())
      r.fail(p + ".rule", "not among orders.rules");
    Bound b{*rule, read_strategies(r, t, "strategies", p),
            (r.*read_value)(r.require(t, value_key, p), StudyReader::child(p, value_key))};
    for (Strategy s : b.strategies)
      if (std::find(st.strategies.begin(), st.strategies.end(), s) == st.strategies.end())
        r.fail(p + ".strategies", fmt::format("{} is not among the study's strategies", strategy_name(s)));
    out.push_back(std::move(b));
  }
  return out;
}

std::vector<double> read_rates(const StudyReader& r, const toml::table& t, std::string_view path) {
  std::vector<double> v = r.numbers(t, "rates", path, 1e-3, 1e4);
  for (std::size_t i = 1; i < v.size(); ++i)
    if (!(v[i] > v[i - 1]))
      r.fail(StudyReader::child(path, "rates"), "must be strictly increasing");
  return v;
}

StudyPlan parse_sampling_study(const StudyInput& in) {
  const StudyReader& r = in.reader;
  const toml::table& doc = in.doc;
  r.check_keys(doc, "", {"kind", "name", "description", "reference_tol", "strategies", "scene",
                         "setup", "curves", "orders", "images", "checks"});
  Study st;
  st.name = in.name;
  st.scene = read_study_scene(r, doc, "", st.scene_toml);
  st.ramp = read_ramp(r, doc, st.scene);
  st.reference_tol = read_reference_tol(r, doc, "");
  st.strategies = read_strategies(r, doc, "strategies", "");
  st.setup = read_setup(r, doc);
  // A fan that misses the square measures nothing: every order would be NaN after the run.  A ray
  // counts as the run counts it (fan.cpp): with a chord of positive length, not one grazing a corner.
  const std::vector<Ray> fan = camera_rays(fan_camera(st.setup));
  const auto crosses = [&](const Ray& ray) {
    const std::optional<Interval> chord = clip(ray, st.scene.box);
    return chord && chord->length() > 0;
  };
  if (std::none_of(fan.begin(), fan.end(), crosses))
    r.fail("setup", fmt::format("none of the {} fan rays meets the volume (see eye, centre, angle_degrees and "
                                "fov_degrees): there is nothing to measure", fan.size()));

  const toml::table& curves = r.table(r.require(doc, "curves", ""), "curves");
  r.check_keys(curves, "curves", {"rates"});
  st.curve_rates = read_rates(r, curves, "curves");

  const toml::table& orders = r.table(r.require(doc, "orders", ""), "orders");
  r.check_keys(orders, "orders", {"rates", "rules"});
  st.order_rates = read_rates(r, orders, "orders");
  st.rules = read_rules(r, orders);
  if (st.order_rates.size() < 2) r.fail("orders.rates", "an order needs at least two rates");
  for (double rate : st.curve_rates)
    if (std::find(st.order_rates.begin(), st.order_rates.end(), rate) == st.order_rates.end())
      r.fail("curves.rates", fmt::format("rate {:g} is not among orders.rates", rate));

  const toml::table& images = r.table(r.require(doc, "images", ""), "images");
  r.check_keys(images, "images", {"width", "height", "quick_width", "quick_height", "rates"});
  st.width = static_cast<int>(r.integer(r.require(images, "width", "images"), "images.width", 1, 4096));
  st.height = static_cast<int>(r.integer(r.require(images, "height", "images"), "images.height", 1, 4096));
  st.quick_width = static_cast<int>(
      r.integer(r.require(images, "quick_width", "images"), "images.quick_width", 1, 4096));
  st.quick_height = static_cast<int>(
      r.integer(r.require(images, "quick_height", "images"), "images.quick_height", 1, 4096));
  st.image_rates = read_rates(r, images, "images");

  const toml::table& checks = r.table(r.require(doc, "checks", ""), "checks");
  r.check_keys(checks, "checks", {"identity_tol", "closed_form_kappa", "order", "exact", "keeps_every_ray",
                                  "drops_corner_rays"});
  st.identity_tol = r.number(r.require(checks, "identity_tol", "checks"), "checks.identity_tol");
  if (checks.contains("closed_form_kappa")) {
    const double kappa = r.number(*checks.get("closed_form_kappa"), "checks.closed_form_kappa");
    const TransferFunction& tf = st.scene.transfer;
    const auto& g = tf.first().points();
    const auto& tau = tf.second().points();
    bool proportional = tf.convention() == Convention::emission_extinction && g.size() == 2 &&
                        tau.size() == 2 && g[0].v == tau[0].v && g[1].v == tau[1].v;
    for (std::size_t i = 0; proportional && i < 2; ++i) proportional = g[i].y == kappa * tau[i].y;
    if (!proportional)
      r.fail("checks.closed_form_kappa",
             "needs emission = kappa * extinction, each given by the same two control points");
    st.closed_form_kappa = kappa;
  }
  st.order_bounds = read_bounds<Study::OrderBound>(r, checks, st, "order", "min_order", &StudyReader::number);
  st.exact_bounds = read_bounds<Study::ExactBound>(r, checks, st, "exact", "max_error", &StudyReader::non_negative);
  st.keeps_every_ray = read_subset(r, checks, "keeps_every_ray", st.strategies);
  st.drops_corner_rays = read_subset(r, checks, "drops_corner_rays", st.strategies);
  return {[st](const StudyRun& run) { return run_sampling_study(st, run); },
          [st](bool quick) { return sampling_work(st, quick); }};
}

const RegisterStudyKind kSampling{"sampling", parse_sampling_study};

}  // namespace
}  // namespace vrv::sampling_study
