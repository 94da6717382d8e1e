#pragma once
// The reference's state along one ray, front to back, for N channels in lockstep: the optical
// depth Phi (log transmittance) they share, and each channel's value and error estimate.
//
// The channels of a ray (grey; an RGB scene's red, green and blue; alpha) share one extinction, so
// one walk serves them all: one set of cuts (the union of their transfer functions' breakpoints),
// one optical depth per piece, one route per piece, a piece split when any channel still emitting
// misses its share of the tolerance.  Each channel keeps what is its own: its emission and value,
// its error estimate and the charges behind it (depth errors weighted by its value, joint charges,
// jumps' bands), when its emission is done and when it stops.  N is fixed at compile time, so a
// grey ray (N = 1) pays nothing for colour and computes exactly what the one-channel
// integrator did.  Method and estimate: docs/reference-integrator.md.
#include <array>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "lib/chebyshev.h"
#include "lib/geometry.h"
#include "lib/ray_panel.h"
#include "lib/shading_weight.h"
#include "lib/transfer_function.h"

namespace vrv {

struct ReferenceOptions {
  double tol = 1e-12;  // absolute tolerance on I
  // Stop a ray once e^-Phi (max g x the length still to come + background) is below the
  // termination share of tol: nothing behind can matter (the bound joins the estimate), and
  // optical_depth is then the depth up to there.  False: Phi is carried to the exit.
  bool stop_when_opaque = true;
};

struct ReferenceResult {
  double value = 0;           // I
  double error_estimate = 0;  // bound on |I - value| (absolute)
  long evaluations = 0;       // field evaluations
  bool hit = false;           // the ray meets the box
  double t_entry = 0;         // clipped parameter range (world length along the unit direction)
  double t_exit = 0;
  double optical_depth = 0;   // int tau over [t_entry, t_exit], or up to where an opaque ray stopped
  // Stopped where nothing behind could matter any more (stop_when_opaque; the ray became
  // opaque, or emits nothing and has no background): optical_depth is then a lower bound.
  bool stopped_early = false;
  // The estimate is within the tolerance and no work cap was reached (a capped ray still
  // reports an honest, large estimate).  False also for a non-finite value or estimate.
  bool tolerance_met = true;
  // A work cap (evaluations, spectral pieces, halvings) ended the ray or accepted a piece unresolved.
  bool capped = false;
};

// One channel of a reference: its transfer function (not owned) and background.
struct ReferenceChannel {
  const TransferFunction* transfer = nullptr;
  double background = 0;
};

// Throws std::invalid_argument unless every channel's transfer function has the first one's
// extinction (convention, curve and unit length): the channels of one walk share their depth.
void require_shared_extinction(std::span<const ReferenceChannel> channels);

namespace detail {

// Signed dg/dv and dtau/dv on a branch of the transfer function.
struct SignedSlopes {
  double emission = 0, extinction = 0;
};

template <int N>
class RayAccumulator {
 public:
  static_assert(N >= 1 && N <= 4);
  // channels: N of them sharing one extinction (require_shared_extinction; not checked here, a
  // ray at a time).  position_error: a field error every panel carries on top of its own (the
  // rounding of a far ray's entry point, field_change_within(RayFrame::position_error)).
  // weight: a factor on every channel's emission (shading, lib/shading_weight.h), or none; it
  // must outlive the accumulator, as must the transfer functions.
  RayAccumulator(std::span<const ReferenceChannel, N> channels, const ReferenceOptions& options, Interval iv,
                 double position_error = 0, const EmissionWeight* weight = nullptr);

  // Field error allowed on a panel starting now, so that its effect on every channel still
  // integrating stays in budget.
  double field_tolerance() const;
  // Integrates the channels over the panel (cut at their transfer functions' crossings) and adds
  // the panel's own proxy error to each estimate.
  void consume(const RayPanel& panel);
  // False where the proxy comes within its error of a jump of a transfer function without
  // crossing it there: the field may cross where the proxy does not, so the panel should be
  // refined (if it cannot be, consume() charges the jump over the whole stretch).
  bool jumps_located(const RayPanel& panel);
  ReferenceResult finish(int channel = 0) const;
  // Nothing after this point can matter to any channel (opaque), or the work cap ended the ray.
  bool stopped() const;
  // The work cap is reached at t: the rest of the ray is bounded, not integrated.
  void give_up(double t);
  // A piece or panel was accepted unresolved at a work limit.
  void note_cap();
  // The field error every panel carries (a far ray's rounded entry point).
  double position_error() const { return position_error_; }

 private:
  // What a channel owns.
  struct Channel {
    const TransferFunction* tf = nullptr;
    double background = 0;
    std::optional<double> kappa;  // g = kappa tau everywhere
    double value = 0;
    double error = 0;
    double depth_error = 0;           // sum of dPhi_i booked to it
    double depth_error_weighted = 0;  // sum of dPhi_i * (value before i)
    bool emission_done = false;
    double emission_done_at = std::numeric_limits<double>::infinity();  // where it became done
    bool stopped = false;
    bool stopped_early = false;
    bool capped = false;
    double stopped_at = std::numeric_limits<double>::infinity();  // where its state froze
    double phi_at_stop = 0, transmittance_at_stop = 1;             // the shared depth then
    double termination_booked = 0;  // error booked by early termination so far
    // The current piece's branch and the field-error part of dPhi booked for it.
    TransferSegment seg;
    TransferFunction::Slopes branch_slopes;  // |dg/dv|, |dtau/dv| on it
    // The open range of values (lo, hi) the branch holds for, where seg, branch_slopes and
    // joint_slopes stay as they are (the next piece is mostly on the same branch); empty at first.
    double branch_lo = std::numeric_limits<double>::infinity();
    double branch_hi = -std::numeric_limits<double>::infinity();
    std::optional<SignedSlopes> joint_slopes;  // where jointly charged
    double piece_depth_error = 0;
    int piece_joint = -1;  // the piece's joint charge (an index into joint), while it is integrated
    std::size_t next_band = 0;
    // A field error at a point changes g there and tau for everything after it: per unit of error
    // I moves by dg T - dtau R (T the transmittance there, R the light still to come, background
    // included).  The two terms cancel where g and tau rise together (a thick medium of constant
    // g / tau does not care where it starts; charged apart, they made estimates 10^3 x the
    // error), so pieces of affine branches and jumps' bands are charged jointly, in finish(), once
    // R is known: over the ranges T and R can take there.
    struct JointCharge {
      double size = 0;                      // field error x length (a piece), the band's width (a jump)
      double dg = 0, dtau = 0;              // signed slopes (a piece), signed jumps (a band)
      double t_lo = 0, t_hi = 0;            // transmittance where it applies
      double before_lo = 0, before_hi = 0;  // the emission accumulated before that point
      double s_lo = 1, s_hi = 1;            // the range of the emission's weight there
    };
    std::vector<JointCharge> joint;

    // max g, max |dg/dv| over all values, times the weight's largest value.
    double max_emission(double shade_max) const { return tf->max_emission() * shade_max; }
  };
  // One Clenshaw-Curtis rule of n points on [c, d]: the piece's depth and its error (shared), and
  // each emitting channel's emission and error.
  struct SpectralTry {
    double dphi = 0;
    double depth_error = 0;
    bool depth_converged = false, depth_at_rounding = false;
    std::array<double, N> error{}, emission{};
    std::array<bool, N> converged{}, at_rounding{};
  };
  // A set of channels, by index.
  using Mask = std::array<bool, N>;

  void integrate_piece(const RayPanel& panel, double c, double d);
  // Replaces a closed-form piece's joint charge (the channel's last) by one per part of it.
  void split_closed_form_joint(Channel& ch, const RayPanel& panel, double c, double d, double phi0, double value0);
  // A piece that absorbs (nearly) everything, from Phi alone; false when it does not apply.
  bool integrate_opaque_piece(const RayPanel& panel, double c, double d);
  // Adaptive Clenshaw-Curtis on [c, d] for the channels in `emit` (depth alone for the others).
  void integrate_spectral(const RayPanel& panel, double c, double d, const Mask& emit, int level);
  SpectralTry spectral_try(const RayPanel& panel, double c, double d, const Mask& emit, int n) const;
  // spectral_try's depth half into `out`.
  struct SpectralDepth;
  void spectral_depth(const RayPanel& panel, double c, double d, bool with_phi, const ChebyshevRule& rule,
                      SpectralDepth& out) const;
  // Where a field error of the panel's size could put a jump's crossings (JumpBand), from
  // crossings_ (found first); returns whether each band holds exactly one located crossing.
  bool find_jump_bands(const RayPanel& panel);
  // The emission error of the bands from ch.next_band on that start at or before c (reached by
  // the integration), each attenuated at least as much as from its start.
  void charge_bands(Channel& ch, double c, double panel_transmittance);
  void check_termination(Channel& ch, double t);
  // ch.seg, ch.branch_slopes and ch.joint_slopes for the branch that holds v.
  static void find_branch(Channel& ch, double v);
  // The cuts of a panel: the crossings of every channel's transfer function and, with a weight,
  // its switches (a misplaced jump of the weight charged over its uncertainty), sorted, into cuts_.
  void panel_cuts(const RayPanel& panel);
  double sensitivity_after(const Channel& ch, double t) const;  // a priori bound on |dI / dPhi| at t
  // An uncertainty dPhi in the optical depth here scales everything behind by e^-dPhi, so it
  // costs dPhi times the part of I that comes after this point: known once the ray is done.
  static void book_depth_error(Channel& ch, double dphi);
  void book_depth_error(double dphi);  // to every channel still integrating
  // Phi += dphi, booking the sum's rounding.
  void advance_depth(double dphi);
  double joint_error(const Channel& ch, double value, double other_error) const;
  // Channels still integrating, or still emitting.
  Mask integrating() const;
  Mask emitting() const;

  std::array<Channel, N> ch_;
  const EmissionWeight* weight_;
  double shade_max_ = 1, shade_min_ = 1;  // the weight's range (1 without one)
  bool affine_ = true;                    // every channel's g and tau affine on each branch
  std::vector<double> levels_;            // every channel's breakpoints, sorted, once each
  std::vector<WeightSwitch> switches_;    // scratch: a panel's switches
  std::vector<double> cuts_;              // scratch: a panel's cuts
  double tol_;
  bool stop_when_opaque_;
  Interval iv_;
  double position_error_;
  double phi_ = 0;
  double transmittance_ = 1;  // e^-Phi, kept with Phi (advance_depth): every piece asks for it several times
  long spectral_pieces_ = 0;  // the work cap: kMaxSpectralPieces a channel
  double max_extinction_ = 0;  // max tau over all values
  // The least size of v whose rounding the spectral rule charges through the slopes: 1, or the
  // transfer functions' largest level where that is below 1 (and then at least the field's
  // noise).  v's rounding is a few ulps of the values it was computed at; a field of 1e-181 with
  // its levels in the same units was charged ulps of 1 times slopes of 1e180 (an estimate of 1e165).
  double value_floor_ = 1;
  // A stretch [u, u + ...] of the current panel where a jump at `level` may be crossed: dt is
  // how far the field's crossing can lie from the one integrated (the stretch's length where
  // none was located).
  struct JumpBand {
    double u = 0;
    double dt = 0;
    double level = 0;
  };
  // The breakpoints where a channel still integrating jumps (the others' need no locating), and
  // for every breakpoint where some channel jumps, which channels do (bit k: channel k).
  std::vector<double> jump_levels_;
  std::vector<std::pair<double, unsigned>> jumps_by_channel_;
  // jump_levels_ anew, after a channel stopped.
  void live_jump_levels();
  std::vector<JumpBand> bands_;
  std::vector<double> breaks_;  // scratch: the panel's monotone parts
  std::vector<Crossing> crossings_;
};

extern template class RayAccumulator<1>;
extern template class RayAccumulator<2>;
extern template class RayAccumulator<3>;
extern template class RayAccumulator<4>;

}  // namespace detail
}  // namespace vrv
