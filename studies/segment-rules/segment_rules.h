#pragma once
// The segment-rules study (Moreland, PhD thesis 2004, "Linear interpolation of opacity: initial
// approximation"): on a unit segment with front and back opacities alpha_f, alpha_b,
//   zeta = exp(-int_0^1 tau)                  the segment's transparency,
//   Psi  = int_0^1 exp(-int_0^s tau) ds       the emission weight (I = c_f (1 - Psi) + c_b (Psi - zeta)
//                                             for colour linear in s and emission g = c tau),
// exact for two models of what varies linearly inside the segment, against the average-opacity
// approximation; and the image error and observed order of vrv's segment rules.
// See docs/study-segment-rules.md.
#include <string>
#include <vector>

#include "lib/camera.h"
#include "lib/io/image_io.h"
#include "lib/order_estimate.h"
#include "lib/sampling.h"
#include "lib/scene.h"
#include "lib/segment_rule.h"
#include "lib/study_file.h"
#include "studies/engine/reference_audit.h"
#include "studies/engine/study_work.h"

namespace vrv {

class Checkpoints;  // studies/engine/checkpoint.h

struct ZetaPsi {
  double zeta = 1;
  double psi = 1;
};

// Moreland's "linearly interpolated opacity" (Fig. 1.6a, 1.7a): alpha(s) linear from alpha_f at
// s = 0 to alpha_b at s = 1, tau = -ln(1 - alpha) (opacity of a unit length).  zeta in closed form,
// Psi by tanh-sinh quadrature of the closed-form transmittance.  alpha in [0, 1].
ZetaPsi linear_alpha_segment(double alpha_f, double alpha_b);
// The mean of ln u over u in [a, b] (a, b >= 0, either order), cancellation-free; -inf if both 0.
double mean_log(double a, double b);

// tau linear from -ln(1 - alpha_f) to -ln(1 - alpha_b): what vrv's exact_linear rule integrates
// (analytic/piece_integrals.h).  alpha in [0, 1).
ZetaPsi linear_tau_segment(double alpha_f, double alpha_b);

// The average-opacity approximation (Fig. 1.6b, 1.7b), read off vrv's own moreland_segment
// (lib/segment_rule.h): zeta = 1 - (alpha_f + alpha_b)/2, Psi = (1 - zeta)/tau_avg.
ZetaPsi average_opacity_segment(double alpha_f, double alpha_b);

// Independent values for the checks: the defining integrals by adaptive Gauss-Kronrod (nested
// for Psi), no closed form involved.
ZetaPsi linear_alpha_by_quadrature(double alpha_f, double alpha_b);
ZetaPsi linear_tau_by_quadrature(double alpha_f, double alpha_b);

// The opacity grid: n points i/(n-1), the last (alpha = 1) replaced by `top` < 1 so that every
// model is finite there.
std::vector<double> opacity_grid(long n, double top);

// ---- Images: every rule at every step against the reference integrator, per pixel. ----

struct RenderSpec {
  std::string name, description;
  std::string scene_toml;
  Scene scene;              // has a camera
  std::vector<double> steps, quick_steps;
  double map_step = 0;      // the step of the error maps (one of steps and of quick_steps)
  int quick_width = 0, quick_height = 0;
  bool check_orders = true;  // false: orders reported, not gated (steps outside the asymptotic range)
};

struct RuleSpec {
  SegmentRule rule = SegmentRule::riemann;
  double expected_order = 1;
};

struct ImageErrorRow {
  std::string render;
  SegmentRule rule;
  double step = 0;
  double mean_error = 0, max_error = 0, samples_per_ray = 0;
};

struct RenderResult {
  std::vector<ImageErrorRow> rows;            // rule-major, steps in order
  std::vector<OrderEstimate> fits;                 // per rule: observed order and its spread
  std::vector<Image> error_maps;              // per rule: discrete - reference at map_step
  Image reference;
  long hit_pixels = 0;
  int width = 0, height = 0;
};

// Reading a study file's images (also the volume study's, studies/volume/): [[images.rule]] as
// rule and expected_order, and one [[render]] table (name, steps, quick_steps, map_step,
// quick_width, quick_height, check_orders, scene with a camera).  Throws StudyFileError.
std::vector<RuleSpec> read_rules(const StudyReader& r, const toml::table& images);
// The [images] table: a step strategy, reference_tol > 0, order_tolerance and the rules.
struct ImageSettings {
  std::vector<RuleSpec> rules;
  Strategy strategy = Strategy::inviwo;
  double reference_tol = 0;
  OrderTolerance order_tolerance;
};
ImageSettings read_images(const StudyReader& r, const toml::table& doc);
RenderSpec read_render(const StudyReader& r, const toml::table& t, const std::string& at);

// Renders the reference image (integrate_reference at reference_tol per pixel) and every
// (rule, step); means are over the pixels whose ray meets the box.  Deterministic for any
// thread count.  With checkpoints, each image row is stored under checkpoint_key (--resume).  The
// reference's truths are counted in `audit`.
RenderResult run_render(const RenderSpec& spec, const std::vector<RuleSpec>& rules, Strategy strategy,
                        double reference_tol, ReferenceAudit& audit, bool quick, bool progress, Checkpoints* checkpoints = nullptr,
                        const std::string& checkpoint_key = "render");

// Adds the field evaluations of run_render(spec, ...) to `work` (the reference and every rule
// at every step, on each pixel), estimated without casting a ray.
void add_render_work(const RenderSpec& spec, const std::vector<RuleSpec>& rules, Strategy strategy,
                     double reference_tol, bool quick, StudyWork& work);

}  // namespace vrv
