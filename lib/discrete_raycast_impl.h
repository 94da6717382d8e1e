#pragma once
// Template definitions for lib/discrete_raycast.h.
#include <algorithm>
#include <vector>

#include "lib/option_error.h"

namespace vrv {
namespace detail {

// Front to back (with early termination and skipping) or back to front (eq. 1 and 2 of Lee &
// Newman): both combine the same (emission, transparency) pairs.
// The configuration's options are copied in, not read through a reference, so that the sample
// loop keeps them in registers (a store to the running value could otherwise alias them).
template <class Real>
class Compositor {
 public:
  explicit Compositor(const DiscreteConfig& c)
      : skip_(c.skip_below.has_value()),
        terminate_(c.termination.has_value()),
        back_to_front_(c.compositing == Compositing::back_to_front),
        skip_below_(c.skip_below ? Real(*c.skip_below) : Real(0)),
        termination_(c.termination ? Real(*c.termination) : Real(0)) {}
  VRV_FORCE_INLINE void add(Composite<Real> c) {
    if (skip_ && Real(1) - c.transparency < skip_below_) return;
    if (back_to_front_) {
      stack_.push_back(c);
      return;
    }
    value_ += transmittance_ * c.emission;
    transmittance_ *= c.transparency;
    if (terminate_ && Real(1) - transmittance_ >= termination_) done_ = true;
  }
  // What most configurations ask (no skipping, no termination, front to back): add_plain then
  // does the same operations as add without its per-sample checks.
  bool plain() const { return !skip_ && !terminate_ && !back_to_front_; }
  VRV_FORCE_INLINE void add_plain(Composite<Real> c) {
    value_ += transmittance_ * c.emission;
    transmittance_ *= c.transparency;
  }
  bool done() const { return done_; }
  // The value over `background`, and the transparencies' product in the order it composites
  // them: bitwise the value of the same samples with no emission over a background of 1.
  struct Finished {
    Real value, transmittance;
  };
  Finished finish(Real background) const {
    if (!back_to_front_) return {value_ + transmittance_ * background, transmittance_};
    Real value = background, t = 1;
    for (auto it = stack_.rbegin(); it != stack_.rend(); ++it) {
      value = it->emission + it->transparency * value;
      t = it->transparency * t;
    }
    return {value, t};
  }

 private:
  bool skip_, terminate_, back_to_front_;
  Real skip_below_, termination_;
  Real value_ = 0, transmittance_ = 1;
  bool done_ = false;
  std::vector<Composite<Real>> stack_;
};

// Samples every dt / N, while below the same end: from the same first sample (Lee & Newman's
// alpha_u1 = alpha_o1), or centred, at the midpoints of the N equal parts of the step the unit
// sample stands for (the first (N - 1) dt / (2N) before it).
inline SamplePlan oversampled(const SamplePlan& plan, int N, bool centred = false) {
  if (N == 1) return plan;
  SamplePlan fine = plan;
  fine.dt = plan.dt / N;
  if (centred) fine.t_first = plan.t_first - (plan.dt - fine.dt) / 2;
  fine.count = 0;
  if (plan.count == 0) return fine;
  // The first n with t(n) >= t_end, found from its estimate as make_plan (lib/sampling.cpp) does:
  // the same count as stepping from 0, without a loop as long as the ray (work estimates call it
  // for runs they are about to refuse).
  long n = std::max(0L, static_cast<long>(std::ceil((fine.t_end - fine.t_first) / fine.dt)));
  while (n > 0 && !(fine.t(n - 1) < fine.t_end)) --n;
  while (fine.t(n) < fine.t_end) ++n;
  fine.count = n;
  return fine;
}

// Lee & Newman's correction aims at the unit sample's transparency; with centred oversamples the
// unit sample is not among them, so each group of the alpha rule looks it up once more.
inline bool looks_up_unit_samples(const DiscreteConfig& c) {
  const bool lee_newman = c.correction == Correction::lee_newman || c.correction == Correction::lee_newman_quadratic;
  return c.rule == SegmentRule::alpha && lee_newman && c.centred_oversamples && c.oversample > 1;
}

// A sample's position, formed in the raycast's precision (a GPU forms it in single precision).
template <class Real>
VRV_FORCE_INLINE Vec3 sample_position(const Ray& ray, Real t) {
  if constexpr (std::is_same_v<Real, float>) {
    const Eigen::Vector3f q = ray.origin.cast<float>() + t * ray.direction.cast<float>();
    return q.cast<double>();
  } else {
    return ray.at(t);
  }
}

// The Riemann loop as most configurations ask for it (post-classified, Compositor::plain): its
// own function, so that its few values stay in registers.
template <class Real, ScalarField F>
VRV_NOINLINE void plain_riemann(const F& field, const Ray& ray, const SamplePlan& fine, const Classifier& classes,
                                Compositor<Real>& out) {
  const Real dx = Real(fine.dt);
  const auto loop = [&](const auto& fetch) {
    for (long m = 0; m < fine.count; ++m) {
      const Real t = Real(fine.t_first) + Real(m) * dx;
      const auto c = classes.from_value<Real>(fetch(sample_position(ray, t)));
      out.add_plain(riemann_sample(c.g, c.tau, dx));
    }
  };
  if constexpr (std::is_same_v<F, GridField>) field.with_fetch(loop);
  else loop([&](const Vec3& p) VRV_FORCE_INLINE_LAMBDA { return field.value(p); });
}

// One segment between two classified nodes h apart, by the segment rules.
template <class Real>
Composite<Real> segment(SegmentRule rule, const Classified<Real>& a, const Classified<Real>& b, Real h) {
  switch (rule) {
    case SegmentRule::trapezoid:
      return trapezoid_segment(h, a.g, b.g, a.tau, b.tau);
    case SegmentRule::exact_linear:
      return exact_linear_segment(h, a.g, b.g, a.tau, b.tau);
    default:  // moreland: the node opacities over this segment's length
      return moreland_segment(a.color, b.color, Real(-std::expm1(-a.tau * h)),
                              Real(-std::expm1(-b.tau * h)));
  }
}

}  // namespace detail

template <ScalarField F>
DiscreteRaycaster<F>::DiscreteRaycaster(const F& field, const Box& box, const TransferFunction& tf,
                                        double background, DiscreteConfig config, const Shading* shading,
                                        std::array<int, 3> dims)
    : field_(field), box_(box), tf_(tf), background_(background), config_(std::move(config)), shading_(shading) {
  validate(config_, std::is_same_v<F, GridField>, tf);
  if (shading_) {
    const GridField* grid = nullptr;
    if constexpr (std::is_same_v<F, GridField>) {
      grid = &field;
      if (config_.gradient == GradientScheme::nodes) node_gradients_ = &field.node_gradients();
    }
    if constexpr (!requires(const Vec3& p) { field.piece_gradient(p, p); }) {
      if (config_.gradient == GradientScheme::analytic)
        throw OptionError(Option::gradient, "analytic: this field has no exact gradient");
    }
    central_offsets_ = central_offsets(config_.gradient_offset, grid, box, dims);
  }
  if (config_.table_size > 0) {
    const double lo = tf.breakpoints().front(), hi = tf.breakpoints().back();
    table_first_.emplace(tf.first(), lo, hi, config_.table_size, config_.table_lookup);
    table_second_.emplace(tf.second(), lo, hi, config_.table_size, config_.table_lookup);
  }
  if constexpr (std::is_same_v<F, GridField>) {
    if (config_.classification == Classification::pre) {
      // Classify once at the nodes; samples then interpolate the classes (premultiplied colour:
      // the product colour * opacity is what is interpolated).
      const bool oc = tf.convention() == Convention::opacity_color;
      const bool table = table_first_.has_value();
      auto first = [&](double v) { return table ? (*table_first_)(v) : oc ? tf.first()(v) : tf.emission(v); };
      auto second = [&](double v) { return table ? (*table_second_)(v) : oc ? tf.second()(v) : tf.extinction(v); };
      const bool premultiplied = oc && config_.color == ColorConvention::premultiplied;
      pre_first_ = field.mapped(first);
      pre_second_ = field.mapped([&](double v) { return premultiplied ? first(v) * second(v) : second(v); });
    }
  }
}

template <ScalarField F>
template <class Real>
VRV_FORCE_INLINE detail::Classified<Real> DiscreteRaycaster<F>::classify(const Ray& ray, Real t,
                                                        const detail::Classifier& classes) const {
  const Vec3 p = detail::sample_position(ray, t);
  if (pre_first_) {
    const double a = pre_first_->value(p), b = pre_second_->value(p);
    if (tf_.convention() != Convention::opacity_color) return classes.from_emission_extinction<Real>(a, b);
    const bool premultiplied = config_.color == ColorConvention::premultiplied;
    return classes.from_opacity_color<Real>(a, premultiplied ? (a > 0 ? b / a : 0.0) : b);
  }
  return classes.from_value<Real>(field_.value(p));
}

template <ScalarField F>
template <class Real>
detail::Classified<Real> DiscreteRaycaster<F>::classify_shaded_nodes(const Ray& ray, Real t,
                                                                     const detail::Classifier& classes,
                                                                     const ShadingFactor& factor,
                                                                     detail::NodeShadeCache& cache) const {
  const Vec3 p = detail::sample_position(ray, t);
  const NodeGradients& g = *node_gradients_;
  const auto shade = [&](std::size_t n) { return factor(Vec3(g.x.nodes()[n], g.y.nodes()[n], g.z.nodes()[n])); };
  const auto s = [&](std::size_t n) { return cache(n, shade); };
  const GridNodes &first = pre_first_->nodes(), &second = pre_second_->nodes();
  if (tf_.convention() != Convention::opacity_color)  // the emission is shaded, the extinction not
    return classes.from_emission_extinction<Real>(pre_first_->interpolate(p, [&](std::size_t n) { return first[n] * s(n); }),
                                                  pre_second_->value(p));
  // The colour (premultiplied: colour x opacity) is shaded, the opacity not.
  const double a = pre_first_->value(p), b = pre_second_->interpolate(p, [&](std::size_t n) { return second[n] * s(n); });
  const bool premultiplied = config_.color == ColorConvention::premultiplied;
  return classes.from_opacity_color<Real>(a, premultiplied ? (a > 0 ? b / a : 0.0) : b);
}

template <ScalarField F>
Vec3 DiscreteRaycaster<F>::gradient_at(const Vec3& p) const {
  switch (config_.gradient) {
    case GradientScheme::analytic:
      if constexpr (requires { field_.piece_gradient(p, p); }) return field_.piece_gradient(p, p);
      else return Vec3::Zero();  // refused by the constructor
    case GradientScheme::nodes:
      return node_gradients_->at(p);
    default:
      return central_gradient([&](const Vec3& q) { return field_.value(q); }, p, central_offsets_);
  }
}

template <ScalarField F>
template <class Real>
void DiscreteRaycaster<F>::shade(detail::Classified<Real>& c, const Vec3& p, const ShadingFactor& factor) const {
  const Real s = Real(factor(gradient_at(p)));
  c.g *= s;
  c.color *= s;
}

template <ScalarField F>
DiscreteResult DiscreteRaycaster<F>::cast(const Ray& ray) const {
  const auto iv = clip(ray, box_);
  if (!iv) return {background_, 0, 1.0};
  return config_.precision == Precision::single_precision ? cast_in<float>(ray, *iv)
                                                          : cast_in<double>(ray, *iv);
}

template <ScalarField F>
template <class Real>
DiscreteResult DiscreteRaycaster<F>::cast_in(const Ray& ray, Interval iv) const {
  const SamplePlan plan = plan_samples(config_.sampling, ray, iv, box_);
  const double unit_step = plan.dt;  // the strategy's step; N oversamples divide it
  const int N = config_.oversample;
  const SamplePlan fine = detail::oversampled(plan, N, config_.centred_oversamples);
  const Real dx = Real(fine.dt);
  auto t_of = [&](long m) { return Real(fine.t_first) + Real(m) * dx; };
  detail::Compositor<Real> out(config_);
  const bool with_color = config_.rule == SegmentRule::alpha || config_.rule == SegmentRule::moreland;
  const detail::TransferLookup lookup{config_.opacity_unit, table_first_ ? &*table_first_ : nullptr,
                                      table_second_ ? &*table_second_ : nullptr};
  const detail::Classifier classes(tf_, unit_step, with_color, lookup);
  // Shaded scenes: S for this ray's direction (light, view and half vectors are fixed along it).
  std::optional<ShadingFactor> factor;
  if (shading_) factor.emplace(*shading_, ray.direction);
  const bool shade_nodes = factor && config_.shade_at == ShadeAt::nodes;
  std::optional<detail::NodeShadeCache> node_shades;
  if (shade_nodes) node_shades.emplace();
  // A sample's classes, shaded at the sample or from the shaded nodes.
  auto shaded = [&](Real t, const detail::Classifier& cl) VRV_FORCE_INLINE_LAMBDA {
    if (shade_nodes) return classify_shaded_nodes<Real>(ray, t, cl, *factor, *node_shades);
    auto c = classify<Real>(ray, t, cl);
    if (factor) shade(c, detail::sample_position(ray, t), *factor);
    return c;
  };
  long samples = 0;
  auto result = [&] {
    const auto finished = out.finish(Real(background_));
    return DiscreteResult{static_cast<double>(finished.value), samples, static_cast<double>(finished.transmittance)};
  };
  auto sample = [&](Real t) VRV_FORCE_INLINE_LAMBDA {
    ++samples;
    return shaded(t, classes);
  };
  // The partial step's sample (plan.partial > 0), for its own length (riemann and alpha).
  const bool partial_first = plan.partial > 0 && plan.partial_first, partial_last = plan.partial > 0 && !plan.partial_first;
  auto add_partial = [&] {
    if (out.done()) return;
    const detail::Classifier own(tf_, plan.partial, with_color, lookup);
    ++samples;
    const auto c = shaded(Real(plan.t_partial), own);
    if (config_.rule == SegmentRule::riemann) return out.add(riemann_sample(c.g, c.tau, Real(plan.partial)));
    const bool premultiplied = config_.color == ColorConvention::premultiplied;
    out.add({c.color * (premultiplied ? c.alpha_stored : c.alpha_unit), Real(1) - c.alpha_unit});
  };
  // The segment rules take it as one more node (below).
  const bool per_sample_rule = config_.rule == SegmentRule::riemann || config_.rule == SegmentRule::alpha;
  if (partial_first && per_sample_rule) add_partial();

  switch (config_.rule) {
    case SegmentRule::riemann:
      if (out.plain() && !pre_first_ && !shading_) {
        // The loop most configurations ask for, without the checks they do not need: a third
        // of the grid raycast's cost over a bare loop (issue 23's ablation), the same values.
        detail::plain_riemann(field_, ray, fine, classes, out);
        samples += fine.count;
        break;
      }
      for (long m = 0; m < fine.count && !out.done(); ++m) {
        const auto c = sample(t_of(m));
        out.add(riemann_sample(c.g, c.tau, dx));
      }
      break;
    case SegmentRule::alpha: {
      std::vector<double> alphas(N), colors(N), stored(N);
      const bool premultiplied = config_.color == ColorConvention::premultiplied;
      for (long m0 = 0; m0 < fine.count && !out.done(); m0 += N) {
        const long n = std::min<long>(N, fine.count - m0);
        for (long j = 0; j < n; ++j) {
          const auto c = sample(t_of(m0 + j));
          alphas[j] = c.alpha_unit;
          colors[j] = c.color;
          stored[j] = c.alpha_stored;
        }
        // Centred oversamples straddle the unit sample, so Lee & Newman's target (the unit
        // sample's transparency) costs one more lookup; the last, partial group of a ray may have
        // no unit sample inside the ray, and then aims at its first oversample.
        std::optional<double> unit_alpha;
        if (detail::looks_up_unit_samples(config_) && m0 / N < plan.count)
          unit_alpha = sample(Real(plan.t(m0 / N))).alpha_unit;
        correct_group(config_.correction, std::span(alphas).first(n), std::span(colors).first(n), N,
                      unit_alpha);
        for (long j = 0; j < n && !out.done(); ++j)
          out.add({Real(colors[j]) * Real(premultiplied ? stored[j] : alphas[j]), Real(1) - Real(alphas[j])});
      }
      break;
    }
    default: {
      // Nodes: the entry point, the samples (the partial step's among them), the exit point.
      Real t_a = Real(iv.t0);
      auto a = sample(t_a);
      auto node = [&](Real t_b) {
        const auto b = sample(t_b);
        const Real h = t_b - t_a;
        if (h > 0) out.add(detail::segment(config_.rule, a, b, h));
        t_a = t_b;
        a = b;
      };
      if (partial_first) node(Real(plan.t_partial));
      for (long m = 0; m < fine.count && !out.done(); ++m) node(t_of(m));
      if (partial_last && !out.done()) node(Real(plan.t_partial));
      if (!out.done()) node(Real(iv.t1));
      return result();
    }
  }
  if (partial_last && per_sample_rule) add_partial();
  return result();
}

}  // namespace vrv
