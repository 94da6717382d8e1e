#pragma once
// Discrete raycasts configured the way renderers and papers do them: a sample placement,
// a segment rule, oversampling with an opacity correction, early termination, skipping,
// pre- or post-classification, front-to-back or back-to-front, in double or float.
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "lib/util/force_inline.h"
#include "lib/field.h"
#include "lib/gradient_scheme.h"
#include "lib/grid_field.h"
#include "lib/opacity_correction.h"
#include "lib/sampling.h"
#include "lib/scene.h"
#include "lib/segment_rule.h"
#include "lib/shading.h"
#include "lib/transfer_function.h"
#include "lib/transfer_table.h"

namespace vrv {

enum class Compositing { front_to_back, back_to_front };
enum class Classification { post, pre };  // pre: classify at grid nodes, then interpolate
enum class Precision { double_precision, single_precision };

// What an opacity/colour transfer function's opacity a means to the alpha rule (sample step H,
// the strategy's unit step; the transfer function's unit_length L):
//   per_sample         alpha = a whatever H (unit_length unused): what vrv did before, and what a
//                      renderer without opacity correction does;
//   per_unit_distance  alpha = 1 - (1 - a)^(H / L), computed as -expm1(log1p(-a) H / L): opacity
//                      given per unit distance and corrected to the sample distance (VTK's scalar
//                      opacity unit distance, most renderers).  Converges to the reference.
// Emission/extinction transfer functions are per unit length already (alpha = 1 - exp(-tau H)).
enum class OpacityUnit { per_sample, per_unit_distance };
// How the alpha rule's colour enters: straight, a sample emits colour * alpha (its own, corrected
// opacity); premultiplied, the colour is stored multiplied by the transfer function's opacity a
// (per unit distance, before any correction; for emission/extinction the unit-step alpha) and
// emitted as stored, colour * a, after the corrections that scale colours (schulze) — a renderer
// that premultiplies and corrects only the opacity.  Pre-classification then interpolates the
// product colour * a.  Equal to straight when alpha = a (per_sample, no oversampling correction).
enum class ColorConvention { straight, premultiplied };

std::optional<OpacityUnit> parse_opacity_unit(std::string_view name);  // "sample", "distance"
std::string opacity_unit_list();  // its names in order, "a, b, c": the choices an error offers
std::string_view opacity_unit_name(OpacityUnit u);
std::optional<ColorConvention> parse_color_convention(std::string_view name);  // "straight", "premultiplied"
std::string color_convention_list();  // its names in order, "a, b, c": the choices an error offers
std::string_view color_convention_name(ColorConvention c);
std::optional<Compositing> parse_compositing(std::string_view name);  // "front_to_back", "back_to_front"
std::string compositing_list();  // its names in order, "a, b, c": the choices an error offers
std::string_view compositing_name(Compositing c);
std::optional<Classification> parse_classification(std::string_view name);  // "post", "pre"
std::string classification_list();  // likewise
std::string_view classification_name(Classification c);
std::optional<Precision> parse_precision(std::string_view name);  // "double", "float"
std::string precision_list();  // likewise
std::string_view precision_name(Precision p);

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
  // Renderer conventions (defaults: the continuous transfer function, vrv's earlier behaviour).
  OpacityUnit opacity_unit = OpacityUnit::per_sample;  // alpha rule, opacity/colour TFs only
  ColorConvention color = ColorConvention::straight;   // alpha rule only
  int table_size = 0;  // 0: the transfer function itself; N >= 2: read from N-entry tables (all rules)
  TableLookup table_lookup = TableLookup::centred;     // how the tables are read (table_size > 0)
  // Shaded scenes (lib/shading.h): how the gradient is taken (lib/gradient_scheme.h), and the
  // central differences' offset (default: one node spacing, or one voxel of the scene's dims).
  GradientScheme gradient = GradientScheme::central;
  std::optional<double> gradient_offset;
  // Where S is taken (lib/gradient_scheme.h): nodes needs a grid, pre-classification and the node
  // differences (the gradient a node has).
  ShadeAt shade_at = ShadeAt::samples;
};

struct DiscreteResult {
  double value = 0;
  long samples = 0;          // field samples taken
  double transmittance = 1;  // the product of the samples' transparencies (alpha is 1 - it)
};

// Throws std::invalid_argument (naming the option) for a combination that means nothing.
void validate(const DiscreteConfig& config, bool grid_field);
// The same, and the options that need a transfer-function convention (opacity_unit needs an
// opacity/colour transfer function).
void validate(const DiscreteConfig& config, bool grid_field, const TransferFunction& tf);

namespace detail {

// g, tau and, for the alpha rule, the renderer's colour and opacity per unit step.
// alpha_stored: the transfer function's own opacity (premultiplied colour carries it).
template <class Real>
struct Classified {
  Real g = 0, tau = 0, alpha_unit = 0, color = 0, alpha_stored = 0;
};

// How samples read the transfer function: the opacity convention and, when renderers' tables
// stand in for the curves, the tables of the first and second curve.
struct TransferLookup {
  OpacityUnit opacity_unit = OpacityUnit::per_sample;
  const TransferTable* first = nullptr;
  const TransferTable* second = nullptr;
};

// Classification of one field value (post) or of interpolated node classes (pre).  The
// renderer's colour and unit opacity are computed only for the rules that use them.
class Classifier {
 public:
  Classifier(const TransferFunction& tf, double unit_step, bool with_color = true, TransferLookup lookup = {})
      : tf_(tf), unit_step_(unit_step), with_color_(with_color), lookup_(lookup) {}
  template <class Real>
  VRV_FORCE_INLINE Classified<Real> from_value(double v) const {
    if (lookup_.first) {
      const double a = (*lookup_.first)(v), b = (*lookup_.second)(v);
      return tf_.convention() == Convention::opacity_color ? from_opacity_color<Real>(a, b)
                                                           : from_emission_extinction<Real>(a, b);
    }
    if (tf_.convention() == Convention::opacity_color)
      return from_opacity_color<Real>(tf_.first()(v), tf_.second()(v));
    // Consecutive samples mostly stay on one branch: look it up only when v leaves it.
    if (!(v >= lo_ && v < hi_)) {
      // Through locals: the members' addresses never escape, so the loop keeps them in registers.
      double lo, hi;
      segment_ = tf_.segment(v, lo, hi);
      lo_ = lo, hi_ = hi;
    }
    return from_emission_extinction<Real>(segment_.g(v), segment_.tau(v));
  }
  template <class Real>
  VRV_FORCE_INLINE Classified<Real> from_emission_extinction(double g, double tau) const {
    Classified<Real> c{Real(g), Real(tau), 0, 0, 0};
    if (with_color_) {
      c.alpha_unit = c.alpha_stored = Real(-std::expm1(-tau * unit_step_));
      c.color = tau > 0 ? Real(g / tau) : Real(0);  // colour is g / tau; undefined (0) where tau = 0
    }
    return c;
  }
  template <class Real>
  Classified<Real> from_opacity_color(double a, double color) const {
    const double log_t = std::log1p(-std::min(a, 1.0));  // ln(1 - a) over the unit length L
    const double tau = -log_t / tf_.unit_length();
    const double alpha = lookup_.opacity_unit == OpacityUnit::per_unit_distance
                             ? -std::expm1(log_t * (unit_step_ / tf_.unit_length()))
                             : a;
    return Classified<Real>{Real(color * tau), Real(tau), Real(alpha), Real(color), Real(a)};
  }

 private:
  const TransferFunction& tf_;
  double unit_step_;
  bool with_color_;
  TransferLookup lookup_;
  mutable TransferSegment segment_;  // the branch for values in [lo_, hi_)
  mutable double lo_ = 1, hi_ = 0;   // empty until the first lookup
};

// S of the nodes a ray's samples read (config.shade_at = nodes), kept per ray: neighbouring samples
// share a cell's 8 corners, so each node's normal and powers are made once, not once a sample.
// Direct-mapped by a multiplicative hash of the node's index (its low bits alone would map the
// corners of a 64-wide grid's rows onto one slot).
class NodeShadeCache {
 public:
  template <class Shade>
  double operator()(std::size_t node, Shade&& shade) {
    Slot& slot = slots_[(node * 0x9E3779B97F4A7C15ull) >> (64 - kBits)];
    if (slot.node != node) slot = {node, shade(node)};
    return slot.s;
  }

 private:
  static constexpr int kBits = 6;
  struct Slot {
    std::size_t node = static_cast<std::size_t>(-1);
    double s = 0;
  };
  std::array<Slot, std::size_t{1} << kBits> slots_{};
};

}  // namespace detail

// Casts rays through one field with one configuration; builds what the configuration needs
// once (pre-classified grids) and nothing else.
template <ScalarField F>
class DiscreteRaycaster {
 public:
  // shading: the scene's (lib/shading.h), or none; with it every sample's emission (g and the
  // colour) is multiplied by S from the gradient taken as config.gradient says, at the sample or
  // at the nodes (config.shade_at).  `dims`: the scene's nominal voxel grid (the default central offset of analytic fields).
  DiscreteRaycaster(const F& field, const Box& box, const TransferFunction& tf, double background,
                    DiscreteConfig config, const Shading* shading = nullptr, std::array<int, 3> dims = {64, 64, 64});
  DiscreteResult cast(const Ray& ray) const;

 private:
  template <class Real>
  DiscreteResult cast_in(const Ray& ray, Interval iv) const;
  template <class Real>
  detail::Classified<Real> classify(const Ray& ray, Real t, const detail::Classifier& classes) const;
  // config.shade_at = nodes: the classes interpolated from the nodes' shaded classes (S of each
  // node's gradient for this ray's `factor`).
  template <class Real>
  detail::Classified<Real> classify_shaded_nodes(const Ray& ray, Real t, const detail::Classifier& classes,
                                                 const ShadingFactor& factor, detail::NodeShadeCache& cache) const;

  const F& field_;
  Box box_;
  const TransferFunction& tf_;
  double background_;
  DiscreteConfig config_;
  std::optional<GridField> pre_first_, pre_second_;  // classified node values
  std::optional<TransferTable> table_first_, table_second_;  // config.table_size > 0
  const Shading* shading_;
  Vec3 central_offsets_ = Vec3::Ones();        // config.gradient = central
  const NodeGradients* node_gradients_ = nullptr;  // config.gradient = nodes: the field's own
  // The gradient at p by config.gradient.
  Vec3 gradient_at(const Vec3& p) const;
  // c's emission times S at p (shaded scenes).
  template <class Real>
  void shade(detail::Classified<Real>& c, const Vec3& p, const ShadingFactor& factor) const;
};

DiscreteResult discrete_raycast(const Scene& scene, const Ray& ray, const DiscreteConfig& config);

// The raycaster of a grey scene whose field is `field` (visit_field's argument): the scene's box,
// transfer function, background, shading and voxel grid.  The scene and field must outlive it.
template <ScalarField F>
DiscreteRaycaster<F> scene_raycaster(const F& field, const Scene& scene, const DiscreteConfig& config) {
  return DiscreteRaycaster<F>(field, scene.box, scene.transfer, scene.background, config, scene.shading_or_null(),
                              scene.dims);
}

}  // namespace vrv

#include "lib/discrete_raycast_impl.h"
