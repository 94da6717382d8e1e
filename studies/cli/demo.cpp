// vrv demo: the main job on the embedded default scene; a row of reference rays with their
// error estimates and cost, so a fresh checkout shows what vrv computes in one command.
#include <memory>

#include <fmt/format.h>

#include "studies/cli/cli_support.h"
#include "studies/cli/commands.h"

namespace vrv::cli {
namespace {

struct DemoOptions {
  std::string scene;
  int rays = 9;
  double tol = 1e-12;
};

void run_demo(const DemoOptions& opt) {
  check_tolerance(opt.tol);
  if (opt.rays < 1) throw std::invalid_argument("--rays: must be at least 1");
  const Scene scene = load_scene_or_default(opt.scene);
  const Vec3 centre = 0.5 * (scene.box.min + scene.box.max);
  const Vec3 extent = scene.box.extent();
  fmt::print("{:>3}  {:>10}  {:>22}  {:>10}  {:>6}\n", "ray", "y", "I (reference)", "error est.",
             "evals");
  double worst = 0;
  long evaluations = 0;
  for (int i = 0; i < opt.rays; ++i) {
    // Rays along +x across the middle of the box, from just below to just above it in y.
    const double y = centre.y() + extent.y() * ((i + 0.5) / opt.rays - 0.5);
    const Vec3 origin(scene.box.min.x() - extent.x(), y, centre.z() + 0.1 * extent.z());
    const ReferenceResult r =
        integrate_reference(scene, make_ray(origin, Vec3(1, 0, 0)), {opt.tol});
    fmt::print("{:>3}  {:>10.6f}  {:>22.17g}  {:>10.2e}  {:>6}\n", i, y, r.value,
               r.error_estimate, r.evaluations);
    worst = std::max(worst, r.error_estimate);
    evaluations += r.evaluations;
  }
  fmt::print("{} rays, tol {:.0e}: largest error estimate {:.2e}, mean field evaluations {:.1f}\n",
             opt.rays, opt.tol, worst, static_cast<double>(evaluations) / opt.rays);
}

}  // namespace

void add_demo_command(CLI::App& app) {
  auto opt = std::make_shared<DemoOptions>();
  CLI::App* cmd = app.add_subcommand(
      "demo", "Reference values along a row of rays through a scene (default: Marschner-Lobb)");
  cmd->add_option("--scene", opt->scene, "Scene file (TOML); the embedded default when omitted");
  cmd->add_option("--rays", opt->rays, "Number of rays")->capture_default_str();
  cmd->add_option("--tol", opt->tol, "Absolute tolerance on I")->capture_default_str();
  cmd->callback([opt] { run_demo(*opt); });
}

}  // namespace vrv::cli
