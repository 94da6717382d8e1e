#include "lib/ray_accumulator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "analytic/piece_integrals.h"
#include "lib/util/error_free.h"

namespace vrv {

namespace {

bool same_curve(const PiecewiseLinear& a, const PiecewiseLinear& b) {
  const auto& p = a.points();
  const auto& q = b.points();
  return std::equal(p.begin(), p.end(), q.begin(), q.end(),
                    [](const ControlPoint& x, const ControlPoint& y) { return x.v == y.v && x.y == y.y; });
}

// The curve tau is made of: the extinction, or the opacity (with the unit length).
const PiecewiseLinear& extinction_curve(const TransferFunction& tf) {
  return tf.convention() == Convention::emission_extinction ? tf.second() : tf.first();
}

}  // namespace

void require_shared_extinction(std::span<const ReferenceChannel> channels) {
  if (channels.empty()) return;
  const TransferFunction& first = *channels.front().transfer;
  for (const ReferenceChannel& c : channels.subspan(1)) {
    const TransferFunction& tf = *c.transfer;
    if (tf.convention() != first.convention() || tf.unit_length() != first.unit_length() ||
        !same_curve(extinction_curve(tf), extinction_curve(first)))
      throw std::invalid_argument(
          "integrate_channels_reference: the channels' transfer functions must share one extinction "
          "(the same opacity or extinction curve and unit length)");
  }
}

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
constexpr int kMaxNodes = 129;

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

// The accuracy check of a weighted (shaded) emission.  S is not the panel's polynomial: a highlight,
// or a normal turning fast where the gradient nearly vanishes, puts a small, slowly decaying part
// on top of the smooth one, and the last two coefficients can then be small by chance (a 9-point
// rule on a shaded Marschner-Lobb piece: tail 1.7e-10 after 3.6e-8, estimate 1.2e-13, error
// 1.5e-11).  The tail is also judged as the largest of the last quarter of the coefficients against
// the quarter before it, and the larger error kept.
ChebyshevAccuracy weighted_accuracy(std::span<const double> c, double noise) {
  const ChebyshevAccuracy standard = chebyshev_accuracy(c, noise);
  const int n = static_cast<int>(c.size()), w = n / 4;
  if (w < 4) return standard;
  double scale = 0, tail = 0, before = std::numeric_limits<double>::min();
  for (double x : c) scale = std::max(scale, std::abs(x));
  for (int k = n - w; k < n; ++k) tail = std::max(tail, std::abs(c[k]));
  for (int k = n - 2 * w; k < n - w; ++k) before = std::max(before, std::abs(c[k]));
  if (tail <= std::max(4 * eps * scale * std::sqrt(static_cast<double>(n)), noise)) return standard;
  const double r = std::pow(tail / before, 1.0 / w);
  if (!(r < 0.8)) return {std::max(standard.error, 2 * tail / 0.2), false, false, standard.noise_error};
  return {standard.error + 2 * tail * r / (1 - r), standard.resolved, false, standard.noise_error};
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
std::optional<SignedSlopes> signed_slopes(const TransferSegment& seg, double lo, double hi) {
  if (seg.convention != Convention::emission_extinction) return std::nullopt;
  for (const Line& line : {seg.first, seg.second})
    if (line.slope != 0 && !(line(lo) >= 0 && line(hi) >= 0)) return std::nullopt;
  return SignedSlopes{seg.first.slope, seg.second.slope};
}

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
  double xs[kMaxNodes], values[kMaxNodes], coefficients[kMaxNodes];
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

// The optical-depth half of the spectral rule on one piece [c, d]: the proxy's values at the
// rule's n nodes, tau there, the piece's depth and its error, and Phi(t) - Phi(c) at the nodes.
template <int N>
struct RayAccumulator<N>::SpectralDepth {
  std::array<double, kMaxNodes> values;  // the proxy at the nodes (from +1 to -1)
  std::array<double, kMaxNodes> tau;
  std::array<double, kMaxNodes> phi;  // (Phi(t_j) - Phi(c)) / half, non-increasing in j (with_phi only)
  double v_max = 1, tau_max = 0;
  double position_noise = 0;  // node_position_noise of the piece
  double dphi = 0, depth_error = 0;
  bool converged = false, at_rounding = false;
};

template <int N>
RayAccumulator<N>::RayAccumulator(std::span<const ReferenceChannel, N> channels, const ReferenceOptions& options,
                                  Interval iv, double position_error, const EmissionWeight* weight)
    : weight_(weight),
      shade_max_(weight ? weight->max() : 1.0),
      shade_min_(weight ? weight->min() : 1.0),
      tol_(options.tol),
      stop_when_opaque_(options.stop_when_opaque),
      iv_(iv),
      position_error_(position_error) {
  for (int k = 0; k < N; ++k) {
    Channel& ch = ch_[k];
    ch.tf = channels[k].transfer;
    ch.background = channels[k].background;
    ch.kappa = ch.tf->emission_per_extinction();
    affine_ = affine_ && ch.tf->affine();
    levels_.insert(levels_.end(), ch.tf->breakpoints().begin(), ch.tf->breakpoints().end());
  }
  if constexpr (N > 1) {
    std::sort(levels_.begin(), levels_.end());
    levels_.erase(std::unique(levels_.begin(), levels_.end()), levels_.end());
  }
  double largest_level = 0;
  for (double v : levels_) largest_level = std::max(largest_level, std::abs(v));
  value_floor_ = std::min(1.0, largest_level);
  for (double v : levels_) {
    unsigned jumps = 0;
    for (int k = 0; k < N; ++k) {
      const auto jump = ch_[k].tf->jump_at(v);
      max_extinction_ = std::max(max_extinction_, ch_[k].tf->extinction(v) + jump.extinction);
      if (jump.emission != 0 || jump.extinction != 0) jumps |= 1u << k;
    }
    if (jumps) jumps_by_channel_.emplace_back(v, jumps);
  }
  live_jump_levels();
  for (const Channel& ch : ch_) max_extinction_ = std::max(max_extinction_, ch.tf->max_extinction());
  for (Channel& ch : ch_) check_termination(ch, iv.t0);
}

template <int N>
void RayAccumulator<N>::live_jump_levels() {
  unsigned live = 0;
  for (int k = 0; k < N; ++k)
    if (!ch_[k].stopped) live |= 1u << k;
  jump_levels_.clear();
  for (const auto& [level, channels] : jumps_by_channel_)
    if (channels & live) jump_levels_.push_back(level);
}

template <int N>
typename RayAccumulator<N>::Mask RayAccumulator<N>::integrating() const {
  Mask m;
  for (int k = 0; k < N; ++k) m[k] = !ch_[k].stopped;
  return m;
}

template <int N>
typename RayAccumulator<N>::Mask RayAccumulator<N>::emitting() const {
  Mask m;
  for (int k = 0; k < N; ++k) m[k] = !ch_[k].stopped && !ch_[k].emission_done;
  return m;
}

template <int N>
bool RayAccumulator<N>::stopped() const {
  for (const Channel& ch : ch_)
    if (!ch.stopped) return false;
  return true;
}

template <int N>
double RayAccumulator<N>::sensitivity_after(const Channel& ch, double t) const {
  return ch.emission_done ? ch.background : ch.max_emission(shade_max_) * (iv_.t1 - t) + ch.background;
}

template <int N>
double RayAccumulator<N>::field_tolerance() const {
  // A field error df changes g by <= dg/dv df and tau by <= dtau/dv df; the latter reaches
  // everything behind through the transmittance.  The tightest channel's.
  double tol = std::numeric_limits<double>::infinity();
  for (const Channel& ch : ch_) {
    if (ch.stopped) continue;
    const double per_unit = (ch.emission_done ? 0.0 : ch.tf->max_emission_slope() * shade_max_) +
                            ch.tf->max_extinction_slope() * sensitivity_after(ch, iv_.t0);
    const double weight = iv_.length() * per_unit * transmittance_;
    tol = std::min(tol, weight > 0 ? kFieldShare * tol_ / weight : std::numeric_limits<double>::infinity());
  }
  return tol;
}

template <int N>
void RayAccumulator<N>::book_depth_error(Channel& ch, double dphi) {
  ch.depth_error += dphi;
  ch.depth_error_weighted += dphi * ch.value;
}

template <int N>
void RayAccumulator<N>::book_depth_error(double dphi) {
  for (Channel& ch : ch_)
    if (!ch.stopped) book_depth_error(ch, dphi);
}

template <int N>
void RayAccumulator<N>::advance_depth(double dphi) {
  // The running sum's rounding reaches only what comes after (booked before this piece's own
  // emission is added: 4 ulps of a depth of 2e300 charged to a value of 1e-300 gave an estimate
  // of 1.95e-15).  It is booked exactly (TwoSum): a bound of 4 ulps of Phi per piece, summed
  // over the ~2600 pieces of a 200-point transfer function, was 4.6e-12 of the 1.1e-12 estimate
  // for an error of 2e-15.  The piece's own depth keeps 4 ulps for how it was computed.
  book_depth_error(std::abs(sum_rounding(phi_, dphi)) + 4 * eps * dphi);
  phi_ += dphi;
  transmittance_ = std::exp(-phi_);
}

template <int N>
void RayAccumulator<N>::consume(const RayPanel& panel) {
  if (stopped()) return;
  const double transmittance = transmittance_;  // at the panel's start
  const double field_error = panel.error + position_error_;
  const Mask started = integrating();
  panel_cuts(panel);
  // A proxy error moves the crossings of jumps within their bands (those of kinks only to
  // second order): charged when the ray reaches the band, attenuated by e^-Phi there (emission
  // 1e300 behind optical depth 700 gave estimates of 1e285), its depth error reaching only what
  // comes after it (a wall of extinction 1e6 behind a jump was charged for everything before).
  find_jump_bands(panel);
  for (Channel& ch : ch_) ch.next_band = 0;
  double c = panel.a;
  for (std::size_t k = 0; k <= cuts_.size() && !stopped(); ++k) {
    const double t = k < cuts_.size() ? cuts_[k] : panel.b;
    if (!bands_.empty())
      for (Channel& ch : ch_)
        if (!ch.stopped) charge_bands(ch, c, transmittance);
    if (!(t > c)) continue;
    const double v = panel(0.5 * (c + t));
    const Mask live = integrating();
    const double phi0 = phi_;
    std::array<double, N> value0{};
    for (int i = 0; i < N; ++i) {
      if (!live[i]) continue;
      Channel& ch = ch_[i];
      // ... and changes g and tau through the slopes of the branch each piece is on.
      find_branch(ch, v);
      const auto& slopes = ch.branch_slopes;
      // With a weight the emission's slope is dg x S, S varying along the piece: charged apart.
      const auto& joint = ch.joint_slopes;
      ch.piece_joint = -1;
      if (joint && !ch.emission_done && !weight_ && field_error > 0) {
        value0[i] = ch.value;
        ch.joint.push_back({field_error * (t - c), joint->emission, joint->extinction, 0, transmittance_, ch.value, 0});
        ch.piece_depth_error = 0;
        ch.piece_joint = static_cast<int>(ch.joint.size()) - 1;
      } else {
        ch.error += charge(field_error, t - c, transmittance_, ch.emission_done ? 0.0 : slopes.emission * shade_max_);
        ch.piece_depth_error = charge(field_error, t - c, slopes.extinction);
        book_depth_error(ch, ch.piece_depth_error);
      }
    }
    integrate_piece(panel, c, t);
    for (int i = 0; i < N; ++i) {
      Channel& ch = ch_[i];
      if (!live[i] || ch.piece_joint < 0) continue;
      auto& joint = ch.joint[static_cast<std::size_t>(ch.piece_joint)];
      joint.t_lo = transmittance_, joint.before_hi = ch.value;
      ch.piece_joint = -1;
      split_closed_form_joint(ch, panel, c, t, phi0, value0[i]);
    }
    c = t;
  }
  for (int i = 0; i < N; ++i)
    if (started[i]) charge_bands(ch_[i], panel.b, transmittance);
}

template <int N>
void RayAccumulator<N>::find_branch(Channel& ch, double v) {
  if (v > ch.branch_lo && v < ch.branch_hi) return;
  double lo = 0, hi = 0;
  ch.seg = ch.tf->segment(v, lo, hi);
  ch.branch_slopes = ch.tf->slope_bounds(v, v);
  ch.joint_slopes = signed_slopes(ch.seg, lo, hi);
  // At a breakpoint the slopes are both sides' (slope_bounds): kept for this piece only.
  if (v > lo) ch.branch_lo = lo, ch.branch_hi = hi;
  else ch.branch_lo = std::numeric_limits<double>::infinity(), ch.branch_hi = -std::numeric_limits<double>::infinity();
}

template <int N>
void RayAccumulator<N>::panel_cuts(const RayPanel& panel) {
  crossings_.clear();
  if (may_cross(panel, levels_)) find_crossings(panel, levels_, crossings_);
  cuts_.clear();
  for (const Crossing& x : crossings_) cuts_.push_back(x.t);
  const Mask emit = emitting();
  if (!weight_ || std::none_of(emit.begin(), emit.end(), [](bool e) { return e; })) return;
  switches_.clear();
  weight_->append_switches(panel.a, panel.b, switches_);
  for (const WeightSwitch& w : switches_) {
    if (w.cut) cuts_.push_back(w.t);
    // The integrand takes one side's branch up to the found switch: a jump placed dt off the
    // true one is wrong by at most the weight's spread over dt (attenuated at least as here).
    if (w.jump)
      for (int i = 0; i < N; ++i)
        if (emit[i]) ch_[i].error += charge(w.dt, shade_max_ - shade_min_, ch_[i].tf->max_emission(), transmittance_);
  }
  std::sort(cuts_.begin(), cuts_.end());
}

template <int N>
void RayAccumulator<N>::split_closed_form_joint(Channel& ch, const RayPanel& panel, double c, double d, double phi0,
                                                double value0) {
  // Over one joint, T and R are bounded by their values at its ends; where a closed-form piece
  // absorbs much, that box is loose (a ray that is one piece of depth 7.7 was charged |dg| x its
  // field error x its length, 2.8e-6, where the cancellation dg T - dtau R leaves 1.4e-8).  Its
  // partial integrals are closed forms too: the joint is split where the depth grows by 1/16.
  const bool closed_form = panel.size() == 1 || (panel.size() == 2 && affine_);
  const double dphi = phi_ - phi0;
  if (!closed_form || !(dphi > 0.0625) || ch.joint.empty()) return;
  const int parts = static_cast<int>(std::min(64.0, std::ceil(16 * dphi)));
  const auto whole = ch.joint.back();
  ch.joint.pop_back();
  const TransferSegment& seg = ch.seg;
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
    ch.joint.push_back({whole.size * (s - s_prev) / (d - c), whole.dg, whole.dtau, t_s * (1 - slack),
                        std::min(1.0, t_prev * (1 + slack)), before_prev - slack * std::abs(before_prev),
                        before_s + slack * std::abs(before_s)});
    s_prev = s, t_prev = t_s, before_prev = before_s;
  }
}

template <int N>
bool RayAccumulator<N>::jumps_located(const RayPanel& panel) {
  if (jump_levels_.empty()) return true;  // the bands need the crossings; nothing else here does
  crossings_.clear();
  if (may_cross(panel, levels_)) find_crossings(panel, levels_, crossings_);
  return find_jump_bands(panel);
}

template <int N>
bool RayAccumulator<N>::find_jump_bands(const RayPanel& panel) {
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

template <int N>
void RayAccumulator<N>::charge_bands(Channel& ch, double c, double panel_transmittance) {
  std::size_t& k = ch.next_band;
  // Phi and the value are those where the ray is, or where the channel stopped (the rest of the
  // panel was not integrated for it).
  const double phi = ch.stopped ? ch.phi_at_stop : phi_;
  for (; k < bands_.size() && bands_[k].u <= c; ++k) {
    const JumpBand& band = bands_[k];
    const auto jump = ch.tf->jump_at(band.level);
    if (N > 1 && jump.emission == 0 && jump.extinction == 0) continue;  // another channel's jump
    const double at = std::min(c, ch.stopped_at);
    // Phi at the band's start is at least Phi here less max tau over the way back, and never
    // less than at the panel's start.
    const double transmittance = std::min(panel_transmittance, std::exp(-(phi - max_extinction_ * (at - band.u))));
    // The depth error scales what comes after the band: from here on (booked), and the at most
    // max g (at - u) already added since its start.
    // After termination its bound covers the emission from where it began; a band that starts
    // before (the ray's end or an opaque stop closes the piece holding it) moves emission too.
    if (ch.emission_done && band.u >= ch.emission_done_at) {
      book_depth_error(ch, jump.extinction * band.dt);
      continue;
    }
    // The crossing x lies in [u, u + 2 dt]: e^-Phi there is at least this, and the emission
    // added before x differs from what is added now by at most max g e^-Phi per unit length.
    const double beyond = std::max(0.0, band.u + 2 * band.dt - at), behind = std::max(0.0, at - band.u);
    const double t_lo = std::exp(-(phi + max_extinction_ * beyond));
    const double reach = ch.max_emission(shade_max_) * transmittance;
    const auto signed_jump = ch.tf->signed_jump_at(band.level);
    ch.joint.push_back({band.dt, signed_jump.emission, signed_jump.extinction, t_lo, transmittance,
                        ch.value - reach * behind, ch.value + reach * beyond, shade_min_, shade_max_});
  }
}

template <int N>
void RayAccumulator<N>::integrate_piece(const RayPanel& panel, double c, double d) {
  const Mask live = integrating();
  const Mask emit = emitting();
  const bool any_emits = std::any_of(emit.begin(), emit.end(), [](bool e) { return e; });
  const int first_live = static_cast<int>(std::find(live.begin(), live.end(), true) - live.begin());
  const TransferSegment& tau_seg = ch_[first_live].seg;  // tau is every channel's
  // A closed form per emitting channel (each of the same depth), or one for the depth alone.
  const auto add = [&](std::array<PieceIntegral, N>& piece, const auto& closed_form) {
    int from = -1;
    for (int i = 0; i < N; ++i)
      if (emit[i]) {
        piece[i] = closed_form(&ch_[i].seg);
        if (from < 0) from = i;
      }
    if (from < 0) from = first_live, piece[from] = closed_form(nullptr);
    for (int i = 0; i < N; ++i) {
      if (!live[i]) continue;
      Channel& ch = ch_[i];
      const double attenuated = transmittance_ * piece[i].emission;
      // The closed forms are accurate to a few dozen ulps (their documented amplification cap).
      ch.error += 64 * eps * std::abs(attenuated);
      ch.value += attenuated;
    }
    advance_depth(piece[from].optical_depth);
  };
  bool all_kappa = true;
  for (int i = 0; i < N; ++i) all_kappa = all_kappa && (!emit[i] || ch_[i].kappa);
  if (weight_ && any_emits) {
    // A weighted emission has no closed form: every piece is integrated spectrally, S at the nodes.
    integrate_spectral(panel, c, d, emit, 0);
  } else if (panel.size() == 1) {
    const double v = panel.coefficients[0];
    std::array<PieceIntegral, N> piece{};
    add(piece, [&](const TransferSegment* seg) {
      return constant_piece(d - c, seg ? seg->g(v) : 0.0, tau_seg.tau(v));
    });
  } else if (panel.size() == 2 && affine_) {
    const double vc = panel(c), vd = panel(d);
    std::array<PieceIntegral, N> piece{};
    add(piece, [&](const TransferSegment* seg) {
      return linear_piece(d - c, seg ? seg->g(vc) : 0.0, seg ? seg->g(vd) : 0.0, tau_seg.tau(vc), tau_seg.tau(vd));
    });
  } else if (all_kappa) {
    const double phi0 = phi_;
    integrate_spectral(panel, c, d, Mask{}, 0);
    for (int i = 0; i < N; ++i)
      if (emit[i]) ch_[i].value += *ch_[i].kappa * std::exp(-phi0) * -std::expm1(-(phi_ - phi0));
  } else if (!integrate_opaque_piece(panel, c, d)) {
    // The channels with g = kappa tau keep their exact route beside the others' rule.
    Mask by_rule = emit;
    for (int i = 0; i < N; ++i) by_rule[i] = emit[i] && !ch_[i].kappa;
    const double phi0 = phi_;
    integrate_spectral(panel, c, d, by_rule, 0);
    for (int i = 0; i < N; ++i)
      if (emit[i] && !by_rule[i]) ch_[i].value += *ch_[i].kappa * std::exp(-phi0) * -std::expm1(-(phi_ - phi0));
  }
  for (Channel& ch : ch_) check_termination(ch, d);
}

template <int N>
bool RayAccumulator<N>::integrate_opaque_piece(const RayPanel& panel, double c, double d) {
  // Where a piece is thousands of optical depths thick, e^-Phi is a boundary layer of width 1/tau that no
  // polynomial resolves (tau ~ 1e21 gave a NaN, then estimates of 1e6).  There
  //   int g e^-Phi ds = int (g / tau) e^-Phi dPhi,
  // and g / tau (a ratio of two affine functions of v, monotone where tau > 0) lies between its
  // values at the ends of the value range: over the layer [c, e] that holds all but e^-64 of
  // the light, the integral is that bracket times e^-Phi0 (1 - e^-dPhi), and only Phi is needed.
  // Taken when every emitting channel's bracket meets the piece's share of the tolerance; else
  // the spectral route.
  const Mask emit = emitting();
  if (!affine_ || weight_ || panel.size() < 2) return false;
  int first_emitting = -1;
  for (int i = N - 1; i >= 0; --i)
    if (emit[i]) first_emitting = i;
  if (first_emitting < 0) return false;
  const TransferSegment& tau_seg = ch_[first_emitting].seg;
  // The layer: 64 optical depths at the entry's tau (a few ulps of t if thinner than that).
  const double tau_c = tau_seg.tau(panel(c));
  // Only where the layer is a small part of the piece (the spectral route handles depths of
  // hundreds per piece well, and then more tightly).  Checked first: the value ranges cost a
  // re-expansion of the proxy each (a sixth of an ordinary ray's time when made first), and
  // most pieces of a grid ray end here.
  if (!(tau_c * (d - c) > 4096)) return false;
  const double margin = panel.error + position_error_;
  const double e = std::min(d, c + std::max(64 / tau_c, 8 * eps * std::max(std::abs(c), std::abs(d))));
  if (!(e > c)) return false;
  const ValueRange on_piece = piece_range(panel, c, d);
  const ValueRange on_layer = e < d ? piece_range(panel, c, e) : on_piece;
  // The values of the piece (and of the layer) within a branch [lo, hi): the field's within the
  // proxy's range widened by its error.
  const auto within = [&](const ValueRange& r, double lo, double hi) {
    return ValueRange{std::max(r.min - margin, lo), std::min(r.max + margin, hi)};
  };
  // Each emitting channel's own branch bounds its own ratio; tau is bounded over all of them
  // (each lies in the extinction's branch: a channel's breakpoints include the extinction's).
  const double v_mid = panel(0.5 * (c + d));
  std::array<ValueRange, N> whole{}, layer{};
  double widest_lo = std::numeric_limits<double>::infinity(), widest_hi = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < N; ++i) {
    if (!emit[i]) continue;
    double lo = 0, hi = 0;
    ch_[i].tf->segment(v_mid, lo, hi);
    whole[i] = within(on_piece, lo, hi);
    if (!(whole[i].min <= whole[i].max)) return false;
    layer[i] = e < d ? within(on_layer, lo, hi) : whole[i];
    if (!(layer[i].min <= layer[i].max)) return false;
    widest_lo = std::min(widest_lo, lo), widest_hi = std::max(widest_hi, hi);
  }
  const ValueRange all_layer = N == 1 ? layer[0] : within(on_layer, widest_lo, widest_hi);
  const double tau_lo = tau_seg.tau(all_layer.min), tau_hi = tau_seg.tau(all_layer.max);
  if (!(std::min(tau_lo, tau_hi) * (e - c) > 32)) return false;
  const double transmittance = transmittance_;  // at the piece's start: the layer below moves transmittance_
  const double local_tol = kQuadratureShare * tol_ * (d - c) / iv_.length();
  std::array<double, N> r_min{}, r_max{};
  for (int i = 0; i < N; ++i) {
    if (!emit[i]) continue;
    const TransferSegment& seg = ch_[i].seg;
    const double r_lo = seg.g(layer[i].min) / tau_seg.tau(layer[i].min);
    const double r_hi = seg.g(layer[i].max) / tau_seg.tau(layer[i].max);
    r_min[i] = std::min(r_lo, r_hi), r_max[i] = std::max(r_lo, r_hi);
    if (!(0.5 * (r_max[i] - r_min[i]) * transmittance <= local_tol)) return false;
  }
  const double phi0 = phi_;
  std::array<double, N> booked0{};
  for (int i = 0; i < N; ++i) booked0[i] = ch_[i].depth_error;
  integrate_spectral(panel, c, e, Mask{}, 0);
  const double absorbed = -std::expm1(-(phi_ - phi0));
  // 1 - e^-dPhi is 1 up to e^-(tau_min (e - c)), whatever the errors in Phi inside the layer.
  const double unabsorbed = std::exp(-std::min(tau_lo, tau_hi) * (e - c));
  for (int i = 0; i < N; ++i) {
    if (!emit[i]) continue;
    Channel& ch = ch_[i];
    const double emission = 0.5 * (r_min[i] + r_max[i]) * transmittance * absorbed;
    ch.value += emission;
    ch.error += 0.5 * (r_max[i] - r_min[i]) * transmittance * absorbed + r_max[i] * transmittance * unabsorbed +
                8 * eps * emission;
    // Depth errors of the piece (its field error, booked by consume, and the layer's quadrature)
    // do not reach the layer's own emission, which the bracket covers (v's range is widened by
    // the field error): charge them only to what comes after, as if booked after this emission.
    ch.depth_error_weighted += (ch.piece_depth_error + ch.depth_error - booked0[i]) * emission;
    // Likewise for the piece's joint charge.
    if (ch.piece_joint >= 0) ch.joint[static_cast<std::size_t>(ch.piece_joint)].before_lo = ch.value;
  }
  if (e < d) {
    // Behind the layer: at most max g e^-Phi per unit length; only Phi is carried on.
    for (int i = 0; i < N; ++i)
      if (emit[i]) {
        const TransferSegment& seg = ch_[i].seg;
        ch_[i].error += std::max(seg.g(whole[i].min), seg.g(whole[i].max)) * transmittance_ * (d - e);
      }
    integrate_spectral(panel, e, d, Mask{}, 0);
  }
  return true;
}

template <int N>
void RayAccumulator<N>::spectral_depth(const RayPanel& panel, double c, double d, bool with_phi,
                                       const ChebyshevRule& rule, SpectralDepth& depth) const {
  // The extinction's branch is every channel's; its slope the largest of theirs (the same lines).
  double extinction_slope = 0;
  const TransferSegment* seg = nullptr;
  for (const Channel& ch : ch_)
    if (!ch.stopped) {
      if (!seg) seg = &ch.seg;
      extinction_slope = std::max(extinction_slope, ch.branch_slopes.extinction);
    }
  const int n = rule.size();
  const auto count = static_cast<std::size_t>(n);
  double* values = depth.values.data();
  double* tau = depth.tau.data();
  const double half = 0.5 * (d - c), mid = 0.5 * (c + d);
  // The whole panel at its own nodes: the sampled values themselves, no interpolation.
  if (c == panel.a && d == panel.b && n == panel.size()) {
    std::copy_n(panel.values.begin(), n, values);
  } else {
    double xs[kMaxNodes];
    for (int j = 0; j < n; ++j) xs[j] = panel.x_of(mid + half * rule.node(j));
    chebyshev_evaluate_many(panel.coefficients, {xs, count}, {values, count});
  }
  // Below a unit floor, never below the field's own rounding (its noise, which the panel's error
  // does not carry).
  double v_max = value_floor_ < 1 ? std::max(value_floor_, panel.noise / (8 * eps)) : 1.0, tau_max = 0;
  for (int j = 0; j < n; ++j) {
    v_max = std::max(v_max, std::abs(values[j]));
    tau[j] = seg->tau(values[j]);
    tau_max = std::max(tau_max, tau[j]);
  }
  // Rounding in v (size v_max) reaches tau and g through the branch's slopes: that, not the
  // size of tau, is the noise floor when a steep branch is evaluated near its zero.  Only this
  // branch's (seg's lines extend past its ends): the value range of a piece that ends at a
  // crossing also touches the next branch, whose slope of 1e10 made an estimate of 5.6e-5 for
  // an actual error of 1.4e-15.
  double tau_c[kMaxNodes];
  rule.coefficients({tau, count}, {tau_c, count});
  const double tau_rounding = 8 * eps * (extinction_slope * v_max + tau_max);
  ChebyshevAccuracy tau_acc = chebyshev_accuracy({tau_c, count}, tau_rounding);
  // Only where a piece is short against its position (below): v moves by the nodes' rounding.
  const double position_noise = node_position_noise(c, d, {values, count}, rule);
  if (!tau_acc.resolved && position_noise > 0)
    tau_acc = chebyshev_accuracy({tau_c, count}, tau_rounding + extinction_slope * position_noise);
  depth.v_max = v_max, depth.tau_max = tau_max, depth.position_noise = position_noise;
  depth.dphi = half * chebyshev_integral({tau_c, count});
  // The accuracy check bounds the values' noise in the max norm (Lebesgue constant x the
  // largest node's noise); the integral sees sum_j w_j noise_j, each node's own.
  const double tau_floor = 2 * eps * max_abs({tau_c, count});
  const auto tau_noise = [&](int j) { return std::max(8 * eps * (extinction_slope * v_max + tau[j]), tau_floor); };
  depth.depth_error = 2 * half * without_noise(tau_acc) + half * weighted_sum(rule, tau_noise);
  depth.converged = tau_acc.resolved;
  depth.at_rounding = tau_acc.at_rounding;
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
}

template <int N>
typename RayAccumulator<N>::SpectralTry RayAccumulator<N>::spectral_try(const RayPanel& panel, double c, double d,
                                                                        const Mask& emit, int n) const {
  const ChebyshevRule& rule = ChebyshevRule::get(n);
  const auto count = static_cast<std::size_t>(n);
  const bool any_emits = std::any_of(emit.begin(), emit.end(), [](bool e) { return e; });
  SpectralDepth depth;
  spectral_depth(panel, c, d, any_emits, rule, depth);
  SpectralTry out;
  out.dphi = depth.dphi;
  out.depth_error = depth.depth_error;
  out.depth_converged = depth.converged;
  out.depth_at_rounding = depth.at_rounding;
  if (!any_emits) return out;
  const double half = 0.5 * (d - c), mid = 0.5 * (c + d);
  // The weight at the nodes, and its rounding (only where there is one: grey rays pay nothing).
  const bool weighted = weight_ != nullptr;
  double shade[kMaxNodes], shade_noise[kMaxNodes];
  if (weighted) {
    double ts[kMaxNodes];
    for (int j = 0; j < n; ++j) ts[j] = mid + half * rule.node(j);
    // The ends exactly (mid + half may round past d): the weight knows a node at an end by it.
    ts[0] = d, ts[n - 1] = c;
    weight_->values(c, d, {ts, count}, {shade, count}, {shade_noise, count});
  }
  const double* phi = depth.phi.data();
  // e^-Phi at the nodes, and what the rounding of Phi there (the running depth, and the
  // cumulative product's sum of |Q_jk| tau_k) scales h_j by.
  double at[kMaxNodes], depth_rounding[kMaxNodes];
  for (int j = 0; j < n; ++j) {
    at[j] = std::exp(-(phi_ + half * phi[j]));
    depth_rounding[j] = 1 + (phi_ + half * (phi[j] + depth.tau_max * rule.cumulative_row_abs(j)));
  }
  for (int i = 0; i < N; ++i) {
    if (!emit[i]) continue;
    const Channel& ch = ch_[i];
    const TransferSegment& seg = ch.seg;
    const TransferFunction::Slopes& slopes = ch.branch_slopes;
    double g[kMaxNodes], h[kMaxNodes], h_c[kMaxNodes];
    for (int j = 0; j < n; ++j) {
      g[j] = seg.g_given_tau(depth.values[j], depth.tau[j]);
      h[j] = g[j] * at[j];
    }
    if (weighted)
      for (int j = 0; j < n; ++j) h[j] = g[j] * shade[j] * at[j];
    rule.coefficients({h, count}, {h_c, count});
    // Each node's own noise: the rounding of g and of v through the slope, attenuated there,
    // and of Phi there, which scales h_j.  The largest decides when the tail is noise (splitting
    // stops helping); one bound for the whole piece, max g x e^-Phi at its start x (1 + its
    // end's depth), was 1e3 x too high where the piece absorbs much and accepted unresolved
    // pieces as noise.
    double noise[kMaxNodes], h_noise = 0;
    for (int j = 0; j < n; ++j) {
      noise[j] = 8 * eps * (slopes.emission * depth.v_max + g[j]) * at[j] * depth_rounding[j];
      if (weighted) noise[j] = noise[j] * shade_max_ + g[j] * shade_noise[j] * at[j];
      h_noise = std::max(h_noise, noise[j]);
    }
    const auto accuracy = [&](double noise_level) {
      return weighted ? weighted_accuracy({h_c, count}, noise_level) : chebyshev_accuracy({h_c, count}, noise_level);
    };
    ChebyshevAccuracy h_acc = accuracy(h_noise);
    if (!h_acc.resolved && depth.position_noise > 0)
      h_acc = accuracy(h_noise + slopes.emission * shade_max_ * depth.position_noise * transmittance_);
    const double h_floor = 2 * eps * max_abs({h_c, count});
    const auto node_noise = [&](int j) { return std::max(noise[j], h_floor); };
    out.error[i] = 2 * half * without_noise(h_acc) + half * weighted_sum(rule, node_noise);
    out.emission[i] = half * chebyshev_integral({h_c, count});
    out.converged[i] = h_acc.resolved;
    out.at_rounding[i] = h_acc.at_rounding;
  }
  return out;
}

template <int N>
void RayAccumulator<N>::integrate_spectral(const RayPanel& panel, double c, double d, const Mask& emit, int level) {
  const bool depth_only = std::none_of(emit.begin(), emit.end(), [](bool e) { return e; });
  // tau(f(t)) is a polynomial of the proxy's degree when tau is affine in v.
  const bool exact = depth_only && affine_;
  // A weighted emission is judged on the full rule (a grid cell's ladder from 17 points): S's
  // content does not shrink with the piece's share of the panel, and few coefficients are fooled
  // by it (weighted_accuracy needs 16).
  const bool weighted = weight_ && !depth_only;
  const int most = exact ? panel.size() : weighted ? kSpectralPoints : spectral_points(panel, c, d);
  // A known-degree panel (a grid cell's cubic) is smooth on its short piece: the nested rules
  // 9, 17, 33 are tried in turn before the piece is split (33 points at once cost a grid ray 4x
  // the work its pieces need).  Analytic panels keep one rule per piece.
  const bool ladder = !exact && panel.size() <= kKnownDegreeNodes;
  int n = ladder ? std::min(most, weighted ? 2 * kFirstLadderPoints - 1 : kFirstLadderPoints) : most;
  const double local_tol = kQuadratureShare * tol_ * (d - c) / iv_.length();
  // Every channel still integrating meets its share: its emission's error where it emits here,
  // and the depth's error through what comes after.
  const auto accepted = [&](const SpectralTry& s) {
    if (!s.depth_converged) return false;
    for (int i = 0; i < N; ++i) {
      const Channel& ch = ch_[i];
      if (ch.stopped) continue;
      const double judged = (emit[i] ? s.error[i] : 0.0) + s.depth_error * transmittance_ * sensitivity_after(ch, c);
      const bool converged = !emit[i] || s.converged[i];
      const bool at_rounding = s.depth_at_rounding && (!emit[i] || s.at_rounding[i]);
      if (!(converged && (judged <= local_tol || at_rounding))) return false;
    }
    return true;
  };
  SpectralTry s = spectral_try(panel, c, d, emit, n);
  while (ladder && !accepted(s) && n < most) {
    n = 2 * n - 1;
    s = spectral_try(panel, c, d, emit, n);
  }
  ++spectral_pieces_;
  const double mid = 0.5 * (c + d);
  const bool splittable = level < kMaxLevel && mid > c && mid < d && spectral_pieces_ < kMaxSpectralPieces * N;
  const bool good = accepted(s);
  if (splittable && !good) {
    integrate_spectral(panel, c, mid, emit, level + 1);
    integrate_spectral(panel, mid, d, emit, level + 1);
    return;
  }
  const bool capped = !good && (level >= kMaxLevel || spectral_pieces_ >= kMaxSpectralPieces * N);
  // The depth's own error reaches this piece's emission too; the rounding of the running sum
  // Phi (booked apart: splitting cannot reduce it) only what comes after (h_noise covers the
  // piece's own).
  for (int i = 0; i < N; ++i) {
    Channel& ch = ch_[i];
    if (ch.stopped) continue;
    if (capped) ch.capped = true;
    book_depth_error(ch, s.depth_error);
    ch.value += s.emission[i];
  }
  advance_depth(s.dphi);
  for (int i = 0; i < N; ++i)
    if (!ch_[i].stopped) ch_[i].error += s.error[i];
}

template <int N>
double RayAccumulator<N>::joint_error(const Channel& ch, double value, double other_error) const {
  double sum = 0;
  for (const auto& j : ch.joint) {
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

template <int N>
void RayAccumulator<N>::check_termination(Channel& ch, double t) {
  if (ch.stopped) return;
  // Everything still to come emits at most max g per unit length, attenuated by e^-Phi.
  const double rest = ch.emission_done ? 0.0 : transmittance_ * ch.max_emission(shade_max_) * (iv_.t1 - t);
  // Opaque: neither the emission to come nor the background (whose share lies in
  // [0, e^-Phi I0], reported as e^-Phi I0) can matter any more.
  const double behind = rest + transmittance_ * ch.background;
  if (stop_when_opaque_ && ch.termination_booked + behind <= kTerminationShare * tol_) {
    ch.emission_done = ch.stopped = ch.stopped_early = true;
    ch.emission_done_at = std::min(ch.emission_done_at, t);
    ch.stopped_at = t;
    ch.phi_at_stop = phi_, ch.transmittance_at_stop = transmittance_;
    ch.error += behind;
    ch.termination_booked += behind;
    if constexpr (N > 1) live_jump_levels();
    return;
  }
  if (!ch.emission_done && rest <= kTerminationShare * tol_) {
    ch.emission_done = true;
    ch.emission_done_at = t;
    ch.error += rest;
    ch.termination_booked += rest;
  }
}

template <int N>
void RayAccumulator<N>::note_cap() {
  for (Channel& ch : ch_)
    if (!ch.stopped) ch.capped = true;
}

template <int N>
void RayAccumulator<N>::give_up(double t) {
  for (Channel& ch : ch_) {
    if (ch.stopped) continue;
    // The rest emits at most max g per unit length, and at most sup g / tau however long it is
    // (a box of +-1e300 gave estimates of 2e300 where I <= 2), and lets through at most e^-Phi I0.
    const double rest =
        std::min(ch.tf->max_emission() * (iv_.t1 - t), ch.tf->max_emission_per_extinction()) * shade_max_;
    ch.error += transmittance_ * ((ch.emission_done ? 0.0 : rest) + ch.background);
    ch.stopped = ch.capped = true;
    ch.stopped_at = t;
    ch.phi_at_stop = phi_, ch.transmittance_at_stop = transmittance_;
  }
  live_jump_levels();
}

template <int N>
ReferenceResult RayAccumulator<N>::finish(int channel) const {
  const Channel& ch = ch_[static_cast<std::size_t>(channel)];
  const double phi = ch.stopped ? ch.phi_at_stop : phi_;
  const double transmittance = ch.stopped ? ch.transmittance_at_stop : transmittance_;
  ReferenceResult r;
  r.hit = true;
  r.t_entry = iv_.t0;
  r.t_exit = iv_.t1;
  r.optical_depth = phi;
  r.stopped_early = ch.stopped_early;
  r.value = ch.value + ch.background * transmittance;
  // First order in dPhi; 10 % covers the second-order terms.
  const double after = std::max(0.0, r.value * ch.depth_error - ch.depth_error_weighted);
  // The sum's and the background term's own rounding: relative to what each adds (a background
  // of 1e10 behind a depth of 62 was charged 16 eps x 1e10 = 3.6e-5 for an error of 1e-16); the
  // depth's error reaches the background through `after`.
  const double separate =
      ch.error + 1.1 * after + 16 * eps * (std::abs(ch.value) + std::abs(ch.background) * transmittance);
  r.error_estimate = separate + joint_error(ch, r.value, separate);
  r.capped = ch.capped;
  r.tolerance_met = !ch.capped && r.error_estimate <= tol_ && std::isfinite(r.value) && std::isfinite(r.error_estimate);
  return r;
}

template class RayAccumulator<1>;
template class RayAccumulator<2>;
template class RayAccumulator<3>;
template class RayAccumulator<4>;

}  // namespace detail
}  // namespace vrv
