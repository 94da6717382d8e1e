#include "lib/reference_integrator.h"

#include <stdexcept>

#include <fmt/format.h>

#include "lib/option_error.h"
#include "lib/util/error_free.h"

namespace vrv {

void check_tolerance(double tol) {
  if (!(tol > 0) || !std::isfinite(tol))
    throw OptionError(Option::tol, fmt::format("must be a positive finite number, got {}", tol));
}

void validate(const ReferenceOptions& options) { check_tolerance(options.tol); }

namespace detail {
namespace {

constexpr double eps = std::numeric_limits<double>::epsilon();
// The tolerance is shared out: field proxies, quadrature, and the emission cut off by
// early termination once the transmittance makes the rest negligible.
constexpr double kFieldShare = 0.25;
constexpr double kQuadratureShare = 0.5;
constexpr double kTerminationShare = 0.25;
constexpr int kMaxLevel = 50;
constexpr int kSpectralPoints = 33;
// Panels of at most this many nodes are known-degree (exact) proxies: ramps, trilinear cells.
constexpr int kKnownDegreeNodes = 8;
constexpr int kFirstLadderPoints = 9;
// Work cap per ray: past it pieces are accepted as they are and their (large) error
// estimates reported, so a pathological input costs bounded time instead of hanging.
constexpr long kMaxSpectralPieces = 20000;

// A piece that is a small part of a resolved panel needs a lower degree than the panel (its
// polynomial content shrinks with the length ratio); the accuracy check still splits any piece
// that this underserves.
int spectral_points(const RayPanel& panel, double c, double d) {
  const double share = (d - c) / (panel.b - panel.a);
  return share > 0.25 ? kSpectralPoints : share > 0.06 ? 17 : 9;
}

// A field error charged over a stretch: the product of non-negative factors, with an exact 0
// (a branch of slope 0, no emission) winning over an overflow of the others (a stretch 1e300
// long in a box of +-1e300 overflowed, and inf * 0 made the estimate NaN).
double charge(double a, double b, double c, double d = 1) {
  return a == 0 || b == 0 || c == 0 || d == 0 ? 0.0 : a * b * c * d;
}

double max_abs(std::span<const double> c) {
  double m = 0;
  for (double x : c) m = std::max(m, std::abs(x));
  return m;
}

// The accuracy check's error less its max-norm share of the values' noise.
double without_noise(const ChebyshevAccuracy& acc) { return std::max(0.0, acc.error - acc.noise_error); }

// sum_j w_j noise(j): what noise at the nodes does to the rule's integral over [-1, 1].
template <class Noise>
double weighted_sum(const ChebyshevRule& rule, const Noise& noise) {
  double sum = 0;
  for (int j = 0; j < rule.size(); ++j) sum += rule.weight(j) * noise(j);
  return sum;
}

// dg/dv and dtau/dv, signed, on an affine branch whose lines stay >= 0 over its values [lo, hi]
// (a line clamped at 0 has slope 0 on one side); none otherwise.  A field error that takes a
// value past lo or hi moves a crossing: the bands' and kinks' business, not the slopes'.
struct SignedSlopes {
  double emission = 0, extinction = 0;
};
std::optional<SignedSlopes> signed_slopes(const TransferSegment& seg, double lo, double hi) {
  if (seg.convention != Convention::emission_extinction) return std::nullopt;
  for (const Line& line : {seg.first, seg.second})
    if (line.slope != 0 && !(line(lo) >= 0 && line(hi) >= 0)) return std::nullopt;
  return SignedSlopes{seg.first.slope, seg.second.slope};
}

}  // namespace

RayAccumulator::RayAccumulator(const TransferFunction& tf, double background,
                               const ReferenceOptions& options, Interval iv, double position_error,
                               const EmissionWeight* weight)
    : tf_(tf),
      weight_(weight),
      shade_max_(weight ? weight->max() : 1.0),
      shade_min_(weight ? weight->min() : 1.0),
      background_(background),
      tol_(options.tol),
      stop_when_opaque_(options.stop_when_opaque),
      iv_(iv),
      position_error_(position_error) {
  double largest_level = 0;
  for (double v : tf.breakpoints()) largest_level = std::max(largest_level, std::abs(v));
  value_floor_ = std::min(1.0, largest_level);
  for (double v : tf.breakpoints()) {
    const auto jump = tf.jump_at(v);
    max_extinction_ = std::max(max_extinction_, tf.extinction(v) + jump.extinction);
    if (jump.emission != 0 || jump.extinction != 0) jump_levels_.push_back(v);
  }
  max_extinction_ = std::max(max_extinction_, tf.max_extinction());  // exact where a line rounds
  check_termination(iv.t0);
}

double RayAccumulator::sensitivity_after(double t) const {
  return emission_done_ ? background_ : max_emission() * (iv_.t1 - t) + background_;
}

double RayAccumulator::field_tolerance() const {
  // A field error df changes g by <= dg/dv df and tau by <= dtau/dv df; the latter reaches
  // everything behind through the transmittance.
  const double per_unit = (emission_done_ ? 0.0 : tf_.max_emission_slope() * shade_max_) +
                          tf_.max_extinction_slope() * sensitivity_after(iv_.t0);
  const double weight = iv_.length() * per_unit * transmittance_;
  return weight > 0 ? kFieldShare * tol_ / weight : std::numeric_limits<double>::infinity();
}

void RayAccumulator::book_depth_error(double dphi) {
  depth_error_ += dphi;
  depth_error_weighted_ += dphi * value_;
}

void RayAccumulator::advance_depth(double dphi) {
  // The running sum's rounding reaches only what comes after (booked before this piece's own
  // emission is added: 4 ulps of a depth of 2e300 charged to a value of 1e-300 gave an estimate
  // of 1.95e-15).  It is booked exactly (TwoSum): a bound of 4 ulps of Phi per piece, summed
  // over the ~2600 pieces of a 200-point transfer function, was 4.6e-12 of the 1.1e-12 estimate
  // for an error of 2e-15.  The piece's own depth keeps 4 ulps for how it was computed.
  book_depth_error(std::abs(sum_rounding(phi_, dphi)) + 4 * eps * dphi);
  phi_ += dphi;
  transmittance_ = std::exp(-phi_);
}

void RayAccumulator::consume(const RayPanel& panel) {
  if (stopped_) return;
  const double transmittance = transmittance_;  // at the panel's start
  const double field_error = panel.error + position_error_;
  panel_cuts(panel);
  // A proxy error moves the crossings of jumps within their bands (those of kinks only to
  // second order): charged when the ray reaches the band, attenuated by e^-Phi there (emission
  // 1e300 behind optical depth 700 gave estimates of 1e285), its depth error reaching only what
  // comes after it (a wall of extinction 1e6 behind a jump was charged for everything before).
  find_jump_bands(panel);
  std::size_t next_band = 0;
  double c = panel.a;
  for (std::size_t k = 0; k <= cuts_.size() && !stopped_; ++k) {
    const double t = k < cuts_.size() ? cuts_[k] : panel.b;
    next_band = charge_bands(next_band, c, transmittance);
    if (!(t > c)) continue;
    const double v = panel(0.5 * (c + t));
    // ... and changes g and tau through the slopes of the branch each piece is on.
    const auto slopes = tf_.slope_bounds(v, v);
    double lo = 0, hi = 0;
    const TransferSegment seg = tf_.segment(v, lo, hi);
    branch_slopes_ = slopes;
    // With a weight the emission's slope is dg x S, S varying along the piece: charged apart.
    const auto joint = emission_done_ || weight_ || !(field_error > 0) ? std::nullopt : signed_slopes(seg, lo, hi);
    if (joint) {
      const double phi0 = phi_, value0 = value_;
      joint_.push_back({field_error * (t - c), joint->emission, joint->extinction, 0, transmittance_, value_, 0});
      piece_depth_error_ = 0;
      piece_joint_ = &joint_.back();
      integrate_piece(panel, c, t, seg);
      piece_joint_->t_lo = transmittance_, piece_joint_->before_hi = value_;
      piece_joint_ = nullptr;
      split_closed_form_joint(panel, c, t, seg, phi0, value0);
    } else {
      error_ += charge(field_error, t - c, transmittance_, emission_done_ ? 0.0 : slopes.emission * shade_max_);
      piece_depth_error_ = charge(field_error, t - c, slopes.extinction);
      book_depth_error(piece_depth_error_);
      integrate_piece(panel, c, t, seg);
    }
    c = t;
  }
  charge_bands(next_band, panel.b, transmittance);
}

void RayAccumulator::panel_cuts(const RayPanel& panel) {
  crossings_.clear();
  if (may_cross(panel, tf_.breakpoints())) find_crossings(panel, tf_.breakpoints(), crossings_);
  cuts_.clear();
  for (const Crossing& x : crossings_) cuts_.push_back(x.t);
  if (!weight_ || emission_done_) return;
  switches_.clear();
  weight_->append_switches(panel.a, panel.b, switches_);
  for (const WeightSwitch& w : switches_) {
    if (w.cut) cuts_.push_back(w.t);
    // The integrand takes one side's branch up to the found switch: a jump placed dt off the
    // true one is wrong by at most the weight's spread over dt (attenuated at least as here).
    if (w.jump) error_ += charge(w.dt, shade_max_ - shade_min_, tf_.max_emission(), transmittance_);
  }
  std::sort(cuts_.begin(), cuts_.end());
}

void RayAccumulator::split_closed_form_joint(const RayPanel& panel, double c, double d,
                                             const TransferSegment& seg, double phi0, double value0) {
  // Over one joint, T and R are bounded by their values at its ends; where a closed-form piece
  // absorbs much, that box is loose (a ray that is one piece of depth 7.7 was charged |dg| x its
  // field error x its length, 2.8e-6, where the cancellation dg T - dtau R leaves 1.4e-8).  Its
  // partial integrals are closed forms too: the joint is split where the depth grows by 1/16.
  const bool closed_form = panel.size() == 1 || (panel.size() == 2 && tf_.affine());
  const double dphi = phi_ - phi0;
  if (!closed_form || !(dphi > 0.0625) || joint_.empty()) return;
  const int parts = static_cast<int>(std::min(64.0, std::ceil(16 * dphi)));
  const JointCharge whole = joint_.back();
  joint_.pop_back();
  const double t0 = std::exp(-phi0), vc = panel(c);
  const auto partial = [&](double s) {
    if (panel.size() == 1) return constant_piece(s - c, seg.g(vc), seg.tau(vc));
    const double vs = panel(s);
    return linear_piece(s - c, seg.g(vc), seg.g(vs), seg.tau(vc), seg.tau(vs));
  };
  // The partial integrals are closed forms to a few dozen ulps (as in add()): widened by that.
  constexpr double slack = 64 * eps;
  double s_prev = c, t_prev = whole.t_hi, before_prev = whole.before_lo;
  for (int i = 1; i <= parts; ++i) {
    const double s = i == parts ? d : c + (d - c) * i / parts;
    double t_s = whole.t_lo, before_s = whole.before_hi;
    if (i < parts) {
      const PieceIntegral p = partial(s);
      t_s = std::exp(-(phi0 + p.optical_depth)), before_s = value0 + t0 * p.emission;
    }
    joint_.push_back({whole.size * (s - s_prev) / (d - c), whole.dg, whole.dtau, t_s * (1 - slack),
                      std::min(1.0, t_prev * (1 + slack)), before_prev - slack * std::abs(before_prev),
                      before_s + slack * std::abs(before_s)});
    s_prev = s, t_prev = t_s, before_prev = before_s;
  }
}

bool RayAccumulator::jumps_located(const RayPanel& panel) {
  if (jump_levels_.empty()) return true;  // the bands need the crossings; nothing else here does
  crossings_.clear();
  if (may_cross(panel, tf_.breakpoints())) find_crossings(panel, tf_.breakpoints(), crossings_);
  return find_jump_bands(panel);
}

bool RayAccumulator::find_jump_bands(const RayPanel& panel) {
  bands_.clear();
  if (jump_levels_.empty()) return true;
  // The field is within this of the proxy; comparing it with a level rounds by ulps of the level.
  const auto margin = [&](double level) {
    return panel.error + position_error_ + panel.noise + 4 * eps * std::abs(level);
  };
  const double widest = margin(std::max(std::abs(jump_levels_.front()), std::abs(jump_levels_.back())));
  if (!may_cross(panel, jump_levels_, widest)) return true;
  breaks_.clear();
  monotone_breaks(panel, breaks_);
  bool located = true;
  for (std::size_t i = 0; i + 1 < breaks_.size(); ++i) {
    for (double level : jump_levels_) {
      const auto band = part_level_band(panel, i, level, margin(level));
      if (!band) continue;
      // A crossing the proxy has moves to anywhere in the band; where it has none (p passes
      // within its error of the level), the field may still cross anywhere in it.
      int found = 0;
      double dt = 0;
      for (const Crossing& x : crossings_)
        if (x.level == level && x.t >= band->u && x.t <= band->w)
          ++found, dt = std::max(x.t - band->u, band->w - x.t);
      if (found != 1) located = false, dt = band->w - band->u;
      dt += 4 * eps * std::max(std::abs(band->u), std::abs(band->w));
      bands_.push_back({band->u, dt, level});
    }
  }
  std::sort(bands_.begin(), bands_.end(), [](const JumpBand& x, const JumpBand& y) { return x.u < y.u; });
  return located;
}

std::size_t RayAccumulator::charge_bands(std::size_t first, double c, double panel_transmittance) {
  std::size_t k = first;
  for (; k < bands_.size() && bands_[k].u <= c; ++k) {
    const JumpBand& band = bands_[k];
    const auto jump = tf_.jump_at(band.level);
    // Phi and the value are those where the ray is, or where it stopped (the rest of the
    // panel was never integrated).
    const double at = std::min(c, stopped_at_);
    // Phi at the band's start is at least Phi here less max tau over the way back, and never
    // less than at the panel's start.
    const double transmittance =
        std::min(panel_transmittance, std::exp(-(phi_ - max_extinction_ * (at - band.u))));
    // The depth error scales what comes after the band: from here on (booked), and the at most
    // max g (at - u) already added since its start.
    // After termination its bound covers the emission from where it began; a band that starts
    // before (the ray's end or an opaque stop closes the piece holding it) moves emission too.
    if (emission_done_ && band.u >= emission_done_at_) {
      book_depth_error(jump.extinction * band.dt);
      continue;
    }
    // The crossing x lies in [u, u + 2 dt]: e^-Phi there is at least this, and the emission
    // added before x differs from what is added now by at most max g e^-Phi per unit length.
    const double beyond = std::max(0.0, band.u + 2 * band.dt - at), behind = std::max(0.0, at - band.u);
    const double t_lo = std::exp(-(phi_ + max_extinction_ * beyond));
    const double reach = max_emission() * transmittance;
    const auto signed_jump = tf_.signed_jump_at(band.level);
    joint_.push_back({band.dt, signed_jump.emission, signed_jump.extinction, t_lo, transmittance,
                      value_ - reach * behind, value_ + reach * beyond, shade_min_, shade_max_});
  }
  return k;
}

void RayAccumulator::add(const PieceIntegral& piece) {
  const double attenuated = transmittance_ * piece.emission;
  // The closed forms are accurate to a few dozen ulps (their documented amplification cap).
  error_ += 64 * eps * std::abs(attenuated);
  value_ += attenuated;
  advance_depth(piece.optical_depth);
}

void RayAccumulator::integrate_piece(const RayPanel& panel, double c, double d,
                                     const TransferSegment& seg) {
  const double emission_on = emission_done_ ? 0.0 : 1.0;
  if (weight_ && !emission_done_) {
    // A weighted emission has no closed form: every piece is integrated spectrally, S at the nodes.
    integrate_spectral(panel, c, d, seg, false, 0);
  } else if (panel.size() == 1) {
    const double v = panel.coefficients[0];
    add(constant_piece(d - c, emission_on * seg.g(v), seg.tau(v)));
  } else if (panel.size() == 2 && tf_.affine()) {
    const double vc = panel(c), vd = panel(d);
    add(linear_piece(d - c, emission_on * seg.g(vc), emission_on * seg.g(vd), seg.tau(vc),
                     seg.tau(vd)));
  } else if (const auto kappa = tf_.emission_per_extinction(); emission_done_ || kappa) {
    const double phi0 = phi_;
    integrate_spectral(panel, c, d, seg, true, 0);
    if (!emission_done_) value_ += *kappa * std::exp(-phi0) * -std::expm1(-(phi_ - phi0));
  } else if (integrate_opaque_piece(panel, c, d, seg)) {
  } else {
    integrate_spectral(panel, c, d, seg, false, 0);
  }
  check_termination(d);
}

namespace {

// How far v at the nodes of [c, d] can be off a smooth function of the node because the nodes'
// positions carry their own rounding, a few ulps of t (moving v by |dv/dt| times that), where that
// rounding exceeds 1e-9 of the piece's length; 0 elsewhere, so that nothing changes where it cannot
// matter.  A piece 1e-9 long at t = 367 (a grid cell's cubic passing a transfer-function knot on a
// real scan) had its nodes 6e-5 of its length off and v rough at 1e-13; never looking resolved, it
// was halved until the spectral-piece cap and the ray reported its tolerance missed.  Only used
// to decide that splitting stops helping: tails below it are still charged as they are.
// |dv/dt| from the nodes, doubled (neighbouring nodes of a resolved piece see within that of it).
double node_position_noise(double c, double d, std::span<const double> values, const ChebyshevRule& rule) {
  const double position = 4 * eps * std::max(std::abs(c), std::abs(d));
  if (!(position > 1e-9 * (d - c))) return 0;
  const double half = 0.5 * (d - c);
  double dv_dt = 0;
  for (std::size_t j = 0; j + 1 < values.size(); ++j)
    dv_dt = std::max(dv_dt, std::abs(values[j + 1] - values[j]) /
                                (half * std::abs(rule.node(static_cast<int>(j) + 1) - rule.node(static_cast<int>(j)))));
  return 2 * dv_dt * position;
}

// The range of the proxy on [c, d]: re-expanded there (exactly, it is a polynomial of the
// same degree), every value lies in c0 +- sum |ck|, widened by the rounding.
ValueRange piece_range(const RayPanel& panel, double c, double d) {
  const int n = panel.size();
  const auto count = static_cast<std::size_t>(n);
  const ChebyshevRule& rule = ChebyshevRule::get(n);
  double xs[129], values[129], coefficients[129];
  for (int j = 0; j < n; ++j) xs[j] = panel.x_of(0.5 * (c + d) + 0.5 * (d - c) * rule.node(j));
  chebyshev_evaluate_many(panel.coefficients, {xs, count}, {values, count});
  rule.coefficients({values, count}, {coefficients, count});
  double spread = 0, size = 0;
  for (int k = 1; k < n; ++k) spread += std::abs(coefficients[k]);
  for (int j = 0; j < n; ++j) size = std::max(size, std::abs(values[j]));
  const double slack = 16 * n * eps * (size + spread);
  return {coefficients[0] - spread - slack, coefficients[0] + spread + slack};
}

}  // namespace

bool RayAccumulator::integrate_opaque_piece(const RayPanel& panel, double c, double d,
                                            const TransferSegment& seg) {
  // Where a piece is thousands of optical depths thick, e^-Phi is a boundary layer of width 1/tau that no
  // polynomial resolves (tau ~ 1e21 gave a NaN, then estimates of 1e6).  There
  //   int g e^-Phi ds = int (g / tau) e^-Phi dPhi,
  // and g / tau (a ratio of two affine functions of v, monotone where tau > 0) lies between its
  // values at the ends of the value range: over the layer [c, e] that holds all but e^-64 of
  // the light, the integral is that bracket times e^-Phi0 (1 - e^-dPhi), and only Phi is needed.
  // Taken when the bracket meets the piece's share of the tolerance; else the spectral route.
  if (!tf_.affine() || emission_done_ || panel.size() < 2 || weight_) return false;
  // The layer: 64 optical depths at the entry's tau (a few ulps of t if thinner than that).
  const double tau_c = seg.tau(panel(c));
  // Only where the layer is a small part of the piece (the spectral route handles depths of
  // hundreds per piece well, and then more tightly).  Checked first: the value ranges cost a
  // re-expansion of the proxy each (a sixth of an ordinary ray's time when made first), and
  // most pieces of a grid ray end here.
  if (!(tau_c * (d - c) > 4096)) return false;
  double lo = 0, hi = 0;
  tf_.segment(panel(0.5 * (c + d)), lo, hi);
  const double margin = panel.error + position_error_;
  const auto values_on = [&](double from, double to) {
    const ValueRange r = piece_range(panel, from, to);
    return ValueRange{std::max(r.min - margin, lo), std::min(r.max + margin, hi)};
  };
  const double e = std::min(d, c + std::max(64 / tau_c, 8 * eps * std::max(std::abs(c), std::abs(d))));
  if (!(e > c)) return false;
  const ValueRange whole = values_on(c, d);
  if (!(whole.min <= whole.max)) return false;
  const ValueRange layer = e < d ? values_on(c, e) : whole;
  if (!(layer.min <= layer.max)) return false;
  const double tau_lo = seg.tau(layer.min), tau_hi = seg.tau(layer.max);
  const double r_lo = seg.g(layer.min) / tau_lo, r_hi = seg.g(layer.max) / tau_hi;
  if (!(std::min(tau_lo, tau_hi) * (e - c) > 32)) return false;
  const double r_min = std::min(r_lo, r_hi), r_max = std::max(r_lo, r_hi);
  const double transmittance = transmittance_;  // at the piece's start: the layer below moves transmittance_
  const double local_tol = kQuadratureShare * tol_ * (d - c) / iv_.length();
  if (!(0.5 * (r_max - r_min) * transmittance <= local_tol)) return false;
  const double phi0 = phi_, booked0 = depth_error_;
  integrate_spectral(panel, c, e, seg, true, 0);
  const double absorbed = -std::expm1(-(phi_ - phi0));
  const double emission = 0.5 * (r_min + r_max) * transmittance * absorbed;
  value_ += emission;
  // 1 - e^-dPhi is 1 up to e^-(tau_min (e - c)), whatever the errors in Phi inside the layer.
  const double unabsorbed = std::exp(-std::min(tau_lo, tau_hi) * (e - c));
  error_ += 0.5 * (r_max - r_min) * transmittance * absorbed + r_max * transmittance * unabsorbed +
            8 * eps * emission;
  // Depth errors of the piece (its field error, booked by consume, and the layer's quadrature)
  // do not reach the layer's own emission, which the bracket covers (v's range is widened by
  // the field error): charge them only to what comes after, as if booked after this emission.
  depth_error_weighted_ += (piece_depth_error_ + depth_error_ - booked0) * emission;
  if (piece_joint_) piece_joint_->before_lo = value_;  // likewise for the piece's joint charge
  if (e < d) {
    // Behind the layer: at most max g e^-Phi per unit length; only Phi is carried on.
    error_ += std::max(seg.g(whole.min), seg.g(whole.max)) * transmittance_ * (d - e);
    integrate_spectral(panel, e, d, seg, true, 0);
  }
  return true;
}

SpectralDepth& RayAccumulator::spectral_depth(const RayPanel& panel, double c, double d,
                                              const TransferSegment& seg, bool with_phi,
                                              const ChebyshevRule& rule, SpectralDepth& out) const {
  const TransferFunction::Slopes& slopes = branch_slopes_;
  SpectralDepth* slot = &out;
  if (depth_share_) {
    const SpectralDepthKey key{c, d, rule.size(), seg.convention, seg.extinction_line(), seg.unit_length,
                               slopes.extinction, value_floor_};
    if (SpectralDepth* shared = depth_share_->find(key, with_phi)) return *shared;
    if (SpectralDepth* kept = depth_share_->slot(key)) slot = kept;
  }
  SpectralDepth& depth = *slot;
  const int n = rule.size();
  const auto count = static_cast<std::size_t>(n);
  double* values = depth.values.data();
  double* tau = depth.tau.data();
  const double half = 0.5 * (d - c), mid = 0.5 * (c + d);
  // The whole panel at its own nodes: the sampled values themselves, no interpolation.
  if (c == panel.a && d == panel.b && n == panel.size()) {
    std::copy_n(panel.values.begin(), n, values);
  } else {
    double xs[129];
    for (int j = 0; j < n; ++j) xs[j] = panel.x_of(mid + half * rule.node(j));
    chebyshev_evaluate_many(panel.coefficients, {xs, count}, {values, count});
  }
  // Below a unit floor, never below the field's own rounding (its noise, which the panel's error
  // does not carry).
  double v_max = value_floor_ < 1 ? std::max(value_floor_, panel.noise / (8 * eps)) : 1.0, tau_max = 0;
  for (int j = 0; j < n; ++j) {
    v_max = std::max(v_max, std::abs(values[j]));
    tau[j] = seg.tau(values[j]);
    tau_max = std::max(tau_max, tau[j]);
  }
  // Rounding in v (size v_max) reaches tau and g through the branch's slopes: that, not the
  // size of tau, is the noise floor when a steep branch is evaluated near its zero.  Only this
  // branch's (seg's lines extend past its ends): the value range of a piece that ends at a
  // crossing also touches the next branch, whose slope of 1e10 made an estimate of 5.6e-5 for
  // an actual error of 1.4e-15.
  double tau_c[129];
  rule.coefficients({tau, count}, {tau_c, count});
  const double tau_rounding = 8 * eps * (slopes.extinction * v_max + tau_max);
  ChebyshevAccuracy tau_acc = chebyshev_accuracy({tau_c, count}, tau_rounding);
  // Only where a piece is short against its position (below): v moves by the nodes' rounding.
  const double position_noise = node_position_noise(c, d, {values, count}, rule);
  if (!tau_acc.resolved && position_noise > 0)
    tau_acc = chebyshev_accuracy({tau_c, count}, tau_rounding + slopes.extinction * position_noise);
  depth.v_max = v_max, depth.tau_max = tau_max, depth.position_noise = position_noise;
  depth.dphi = half * chebyshev_integral({tau_c, count});
  // The accuracy check bounds the values' noise in the max norm (Lebesgue constant x the
  // largest node's noise); the integral sees sum_j w_j noise_j, each node's own.
  const double tau_floor = 2 * eps * max_abs({tau_c, count});
  const auto tau_noise = [&](int j) { return std::max(8 * eps * (slopes.extinction * v_max + tau[j]), tau_floor); };
  depth.depth_error = 2 * half * without_noise(tau_acc) + half * weighted_sum(rule, tau_noise);
  depth.converged = tau_acc.resolved;
  depth.at_rounding = tau_acc.at_rounding;
  depth.has_phi = with_phi;
  depth.has_attenuation = false;
  if (with_phi) {
    double* phi = depth.phi.data();
    rule.cumulative_integral({tau, count}, {phi, count});
    // tau >= 0, so Phi rises from 0 at x = -1 (the last node): rounding in the spectral
    // integral (~eps sum |tau|, thousands when tau ~ 1e21) must not make it negative, or
    // e^-Phi overflows.  The running maximum is the stable form; its change is within that
    // rounding, which h_noise below charges through (1 + phi_ + dphi).
    phi[n - 1] = std::max(phi[n - 1], 0.0);
    for (int j = n - 1; j-- > 0;) phi[j] = std::max(phi[j], phi[j + 1]);
  }
  return depth;
}

RayAccumulator::SpectralTry RayAccumulator::spectral_try(const RayPanel& panel, double c, double d,
                                                         const TransferSegment& seg, bool depth_only,
                                                         int n) const {
  const ChebyshevRule& rule = ChebyshevRule::get(n);
  const auto count = static_cast<std::size_t>(n);
  SpectralDepth own;
  SpectralDepth& depth = spectral_depth(panel, c, d, seg, !depth_only, rule, own);
  SpectralTry out;
  out.dphi = depth.dphi;
  out.depth_error = depth.depth_error;
  out.converged = depth.converged;
  out.at_rounding = depth.at_rounding;
  if (depth_only) return out;
  const double half = 0.5 * (d - c), mid = 0.5 * (c + d);
  // The weight at the nodes, and its rounding (only where there is one: grey rays pay nothing).
  const bool weighted = weight_ != nullptr;
  double shade[129], shade_noise[129];
  if (weighted) {
    double ts[129];
    for (int j = 0; j < n; ++j) ts[j] = mid + half * rule.node(j);
    // The ends exactly (mid + half may round past d): the weight knows a node at an end by it.
    ts[0] = d, ts[n - 1] = c;
    weight_->values(c, d, {ts, count}, {shade, count}, {shade_noise, count});
  }
  const TransferFunction::Slopes& slopes = branch_slopes_;
  const double* phi = depth.phi.data();
  const double* at = depth.attenuation.data();  // e^-Phi at the nodes
  if (!depth.has_attenuation || depth.at_depth != phi_) {
    for (int j = 0; j < n; ++j) depth.attenuation[j] = std::exp(-(phi_ + half * phi[j]));
    depth.has_attenuation = true, depth.at_depth = phi_;
  }
  double g[129], h[129], h_c[129];
  for (int j = 0; j < n; ++j) {
    g[j] = seg.g_given_tau(depth.values[j], depth.tau[j]);
    h[j] = g[j] * at[j];
  }
  if (weighted)
    for (int j = 0; j < n; ++j) h[j] = g[j] * shade[j] * at[j];
  rule.coefficients({h, count}, {h_c, count});
  // Each node's own noise: the rounding of g and of v through the slope, attenuated there,
  // and of Phi there (the running depth, and the cumulative product's sum of |Q_jk| tau_k),
  // which scales h_j.  The largest decides when the tail is noise (splitting stops helping);
  // one bound for the whole piece, max g x e^-Phi at its start x (1 + its end's depth), was
  // 1e3 x too high where the piece absorbs much and accepted unresolved pieces as noise.
  double noise[129], h_noise = 0;
  for (int j = 0; j < n; ++j) {
    const double depth_rounding = phi_ + half * (phi[j] + depth.tau_max * rule.cumulative_row_abs(j));
    noise[j] = 8 * eps * (slopes.emission * depth.v_max + g[j]) * at[j] * (1 + depth_rounding);
    if (weighted) noise[j] = noise[j] * shade_max_ + g[j] * shade_noise[j] * at[j];
    h_noise = std::max(h_noise, noise[j]);
  }
  ChebyshevAccuracy h_acc = chebyshev_accuracy({h_c, count}, h_noise);
  if (!h_acc.resolved && depth.position_noise > 0)
    h_acc = chebyshev_accuracy({h_c, count},
                               h_noise + slopes.emission * shade_max_ * depth.position_noise * transmittance_);
  const double h_floor = 2 * eps * max_abs({h_c, count});
  const auto node_noise = [&](int j) { return std::max(noise[j], h_floor); };
  out.error = 2 * half * without_noise(h_acc) + half * weighted_sum(rule, node_noise);
  out.emission = half * chebyshev_integral({h_c, count});
  out.converged = out.converged && h_acc.resolved;
  out.at_rounding = out.at_rounding && h_acc.at_rounding;
  return out;
}

void RayAccumulator::integrate_spectral(const RayPanel& panel, double c, double d,
                                        const TransferSegment& seg, bool depth_only, int level) {
  // tau(f(t)) is a polynomial of the proxy's degree when tau is affine in v.
  const bool exact = depth_only && tf_.affine();
  const int most = exact ? panel.size() : spectral_points(panel, c, d);
  // A known-degree panel (a grid cell's cubic) is smooth on its short piece: the nested rules
  // 9, 17, 33 are tried in turn before the piece is split (33 points at once cost a grid ray 4x
  // the work its pieces need).  Analytic panels keep one rule per piece.
  const bool ladder = !exact && panel.size() <= kKnownDegreeNodes;
  int n = ladder ? std::min(most, kFirstLadderPoints) : most;
  const double local_tol = kQuadratureShare * tol_ * (d - c) / iv_.length();
  const auto accepted = [&](const SpectralTry& s) {
    const double judged = s.error + s.depth_error * transmittance_ * sensitivity_after(c);
    return s.converged && (judged <= local_tol || s.at_rounding);
  };
  SpectralTry s = spectral_try(panel, c, d, seg, depth_only, n);
  while (ladder && !accepted(s) && n < most) {
    n = 2 * n - 1;
    s = spectral_try(panel, c, d, seg, depth_only, n);
  }
  ++spectral_pieces_;
  const double mid = 0.5 * (c + d);
  const bool splittable =
      level < kMaxLevel && mid > c && mid < d && spectral_pieces_ < kMaxSpectralPieces;
  const bool good = accepted(s);
  if (splittable && !good) {
    integrate_spectral(panel, c, mid, seg, depth_only, level + 1);
    integrate_spectral(panel, mid, d, seg, depth_only, level + 1);
    return;
  }
  if (!good && (level >= kMaxLevel || spectral_pieces_ >= kMaxSpectralPieces)) capped_ = true;
  // The depth's own error reaches this piece's emission too; the rounding of the running sum
  // Phi (booked apart: splitting cannot reduce it) only what comes after (h_noise covers the
  // piece's own).
  book_depth_error(s.depth_error);
  value_ += s.emission;
  advance_depth(s.dphi);
  error_ += s.error;
}

double RayAccumulator::joint_error(double value, double other_error) const {
  double sum = 0;
  for (const JointCharge& j : joint_) {
    // R = value - before, widened by what value and before may be off (other_error; the
    // joint charges themselves are of second order there); R >= 0.
    const double r_lo = std::max(0.0, value - j.before_hi - other_error);
    const double r_hi = std::max(0.0, value - j.before_lo + other_error);
    double worst = 0;  // |dg S T - dtau R| is largest at a corner of the box of S, T and R
    for (double s : {j.s_lo, j.s_hi})
      for (double t : {j.t_lo, j.t_hi})
        for (double r : {r_lo, r_hi}) worst = std::max(worst, std::abs(j.dg * s * t - j.dtau * r));
    // Second order: e^-x against 1 - x (x = |dtau| size), and the product of both changes, from
    // the first-order sizes x and |dg| size (size^2 alone overflowed for field values near 1e180,
    // where the size is the field's rounding, and the estimate was infinite).
    // A zero factor wins over an infinite one (charge), as in every other charge.
    const double x = j.size * std::abs(j.dtau), y = j.size * std::abs(j.dg);
    const double second = 0.5 * (charge(x, x, r_hi) + charge(x, y, j.s_hi * j.t_hi));
    sum += charge(j.size, worst, 1) + (second > 0 ? second : 0.0);
  }
  return sum;
}

void RayAccumulator::check_termination(double t) {
  if (stopped_) return;
  // Everything still to come emits at most max g per unit length, attenuated by e^-Phi.
  const double rest = emission_done_ ? 0.0 : transmittance_ * max_emission() * (iv_.t1 - t);
  // Opaque: neither the emission to come nor the background (whose share lies in
  // [0, e^-Phi I0], reported as e^-Phi I0) can matter any more.
  const double behind = rest + transmittance_ * background_;
  if (stop_when_opaque_ && termination_booked_ + behind <= kTerminationShare * tol_) {
    emission_done_ = stopped_ = stopped_early_ = true;
    emission_done_at_ = std::min(emission_done_at_, t);
    stopped_at_ = t;
    error_ += behind;
    termination_booked_ += behind;
    return;
  }
  if (!emission_done_ && rest <= kTerminationShare * tol_) {
    emission_done_ = true;
    emission_done_at_ = t;
    error_ += rest;
    termination_booked_ += rest;
  }
}

void RayAccumulator::give_up(double t) {
  if (stopped_) return;
  // The rest emits at most max g per unit length, and at most sup g / tau however long it is
  // (a box of +-1e300 gave estimates of 2e300 where I <= 2), and lets through at most e^-Phi I0.
  const double rest = std::min(tf_.max_emission() * (iv_.t1 - t), tf_.max_emission_per_extinction()) * shade_max_;
  error_ += transmittance_ * ((emission_done_ ? 0.0 : rest) + background_);
  stopped_ = capped_ = true;
  stopped_at_ = t;
}

ReferenceResult RayAccumulator::finish() const {
  ReferenceResult r;
  r.hit = true;
  r.t_entry = iv_.t0;
  r.t_exit = iv_.t1;
  r.optical_depth = phi_;
  r.stopped_early = stopped_early_;
  r.value = value_ + background_ * transmittance_;
  // First order in dPhi; 10 % covers the second-order terms.
  const double after = std::max(0.0, r.value * depth_error_ - depth_error_weighted_);
  // The sum's and the background term's own rounding: relative to what each adds (a background
  // of 1e10 behind a depth of 62 was charged 16 eps x 1e10 = 3.6e-5 for an error of 1e-16); the
  // depth's error reaches the background through `after`.
  const double separate = error_ + 1.1 * after + 16 * eps * (std::abs(value_) + std::abs(background_) * transmittance_);
  r.error_estimate = separate + joint_error(r.value, separate);
  r.capped = capped_;
  r.tolerance_met = !capped_ && r.error_estimate <= tol_ && std::isfinite(r.value) &&
                    std::isfinite(r.error_estimate);
  return r;
}

}  // namespace detail

ReferenceResult integrate_reference(const Scene& scene, const Ray& ray,
                                    const ReferenceOptions& options) {
  return visit_field(scene, [&](const auto& field) {
    return integrate_reference(field, scene.box, scene.transfer, scene.background, ray, options,
                               scene.shading_or_null());
  });
}

}  // namespace vrv
