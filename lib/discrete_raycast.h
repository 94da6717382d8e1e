#pragma once
// Discrete raycasts configured the way renderers and papers do them: a sample placement,
// a segment rule, oversampling with an opacity correction, early termination, skipping,
// pre- or post-classification, front-to-back or back-to-front, in double or float.
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <type_traits>
#include <vector>

#include "lib/field.h"
#include "lib/grid_field.h"
#include "lib/opacity_correction.h"
#include "lib/sampling.h"
#include "lib/scene.h"
#include "lib/segment_rule.h"
#include "lib/transfer_function.h"

namespace vrv {

enum class Compositing { front_to_back, back_to_front };
enum class Classification { post, pre };  // pre: classify at grid nodes, then interpolate
enum class Precision { double_precision, single_precision };

struct DiscreteConfig {
  SegmentRule rule = SegmentRule::riemann;
  SamplingConfig sampling;
  int oversample = 1;                   // N: samples per unit step (renderer's convention)
  bool centred_oversamples = false;     // N samples at the centres of the unit step's N parts,
                                        // not from the unit sample on (see detail::oversampled)
  Correction correction = Correction::none;
  std::optional<double> termination;    // stop once the accumulated opacity reaches it
  std::optional<double> skip_below;     // skip samples whose opacity is below it
  Compositing compositing = Compositing::front_to_back;
  Classification classification = Classification::post;
  Precision precision = Precision::double_precision;
};

struct DiscreteResult {
  double value = 0;
  long samples = 0;  // field samples taken
};

// Throws std::invalid_argument (naming the option) for a combination that means nothing.
void validate(const DiscreteConfig& config, bool grid_field);

namespace detail {

// g, tau and, for the alpha rule, the renderer's colour and opacity per unit step.
template <class Real>
struct Classified {
  Real g = 0, tau = 0, alpha_unit = 0, color = 0;
};

// Classification of one field value (post) or of interpolated node classes (pre).  The
// renderer's colour and unit opacity are computed only for the rules that use them.
class Classifier {
 public:
  Classifier(const TransferFunction& tf, double unit_step, bool with_color = true)
      : tf_(tf), unit_step_(unit_step), with_color_(with_color) {}
  template <class Real>
  Classified<Real> from_value(double v) const {
    if (tf_.convention() == Convention::opacity_color)
      return from_opacity_color<Real>(tf_.first()(v), tf_.second()(v));
    // Consecutive samples mostly stay on one branch: look it up only when v leaves it.
    if (!(v >= lo_ && v < hi_)) segment_ = tf_.segment(v, lo_, hi_);
    return from_emission_extinction<Real>(segment_.g(v), segment_.tau(v));
  }
  template <class Real>
  Classified<Real> from_emission_extinction(double g, double tau) const {
    Classified<Real> c{Real(g), Real(tau), 0, 0};
    if (with_color_) {
      c.alpha_unit = Real(-std::expm1(-tau * unit_step_));
      c.color = tau > 0 ? Real(g / tau) : Real(0);  // colour is g / tau; undefined (0) where tau = 0
    }
    return c;
  }
  template <class Real>
  Classified<Real> from_opacity_color(double a, double color) const {
    const double tau = -std::log1p(-std::min(a, 1.0)) / tf_.unit_length();
    return Classified<Real>{Real(color * tau), Real(tau), Real(a), Real(color)};
  }

 private:
  const TransferFunction& tf_;
  double unit_step_;
  bool with_color_;
  mutable TransferSegment segment_;  // the branch for values in [lo_, hi_)
  mutable double lo_ = 1, hi_ = 0;   // empty until the first lookup
};

}  // namespace detail

// Casts rays through one field with one configuration; builds what the configuration needs
// once (pre-classified grids) and nothing else.
template <ScalarField F>
class DiscreteRaycaster {
 public:
  DiscreteRaycaster(const F& field, const Box& box, const TransferFunction& tf, double background,
                    DiscreteConfig config);
  DiscreteResult cast(const Ray& ray) const;

 private:
  template <class Real>
  DiscreteResult cast_in(const Ray& ray, Interval iv) const;
  template <class Real>
  detail::Classified<Real> classify(const Ray& ray, Real t, const detail::Classifier& classes) const;

  const F& field_;
  Box box_;
  const TransferFunction& tf_;
  double background_;
  DiscreteConfig config_;
  std::optional<GridField> pre_first_, pre_second_;  // classified node values
};

DiscreteResult discrete_raycast(const Scene& scene, const Ray& ray, const DiscreteConfig& config);

}  // namespace vrv

#include "lib/discrete_raycast_impl.h"
