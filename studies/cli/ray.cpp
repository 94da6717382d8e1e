// vrv ray: the reference value (or a discrete raycast) along one ray, or along every ray of a
// JSON-lines file or standard input, cast in parallel and printed in input order.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "lib/discrete_channels.h"
#include "lib/discrete_error_bound.h"
#include "lib/discrete_error_estimate.h"
#include "lib/rays_file.h"
#include "lib/reference_channels.h"
#include "lib/util/parallel.h"
#include "lib/util/progress.h"
#include "studies/cli/cli_support.h"
#include "studies/cli/memory_limit.h"
#include "studies/cli/commands.h"
#include "studies/cli/discrete_flags.h"
#include "studies/cli/projection_options.h"
#include "lib/scene_mode.h"
#include "lib/projection/projection_reference.h"

namespace vrv::cli {
namespace {

struct RayOptions {
  std::string scene;
  std::optional<double> max_memory_gib;  // --max-memory: the scene's volume
  std::string origin;
  std::string direction;
  std::string rays;
  double tol = ReferenceOptions{}.tol;
  bool json = false;
  int threads = 0;
  bool quiet = false;
  std::string mode;  // --mode: a projection instead of emission-absorption
  bool bound = false;  // --bound: the discrete raycast's a-priori error bound beside its value
  std::optional<ProjectionSetup> projection;
  DiscreteOptions discrete;
  CLI::Option* tol_option = nullptr;
  CLI::Option* threads_option = nullptr;
};

// One ray's answer, whichever integrator gave it.
struct Answer {
  nlohmann::ordered_json json;
  bool finite = true;
  bool tolerance_met = true;
};

Answer reference_answer(const ReferenceResult& r) {
  return {to_json(r), std::isfinite(r.value) && std::isfinite(r.error_estimate), r.tolerance_met};
}

Answer discrete_answer(const DiscreteResult& r) {
  nlohmann::ordered_json j;
  j["value"] = finite_or_null(r.value);
  j["samples"] = r.samples;
  return {j, std::isfinite(r.value), true};
}

// An RGB scene's ray: the grey answer's keys, with value, error_estimate and optical_depth (each
// channel's own: a channel stops early where its remaining emission cannot matter) one per channel.
Answer color_reference_answer(const ChannelsReferenceResult& r) {
  nlohmann::ordered_json j = to_json(r.channel[0]);
  Answer a{{}, true, r.tolerance_met()};
  for (const char* key : {"value", "error_estimate", "optical_depth"}) j[key] = nlohmann::ordered_json::array();
  for (const ReferenceResult& c : r.channels()) {
    j["value"].push_back(finite_or_null(c.value));
    j["error_estimate"].push_back(finite_or_null(c.error_estimate));
    j["optical_depth"].push_back(finite_or_null(c.optical_depth));
    a.finite = a.finite && std::isfinite(c.value) && std::isfinite(c.error_estimate);
  }
  j["evaluations"] = r.evaluations;
  j["tolerance_met"] = a.tolerance_met;
  a.json = std::move(j);
  return a;
}

// Each channel cast alone with its own transfer function and background, as vrv render does.
Answer color_discrete_answer(const Scene& scene, const Ray& ray, const DiscreteConfig& config) {
  const ChannelsDiscreteResult r = discrete_channel_values(scene, std::span<const Ray>(&ray, 1), config).front();
  nlohmann::ordered_json j;
  j["value"] = nlohmann::ordered_json::array();
  for (double v : r.value) j["value"].push_back(finite_or_null(v));
  j["samples"] = r.samples;
  return {j, std::all_of(r.value.begin(), r.value.end(), [](double v) { return std::isfinite(v); }), true};
}

Answer projection_answer(const Scene& scene, const Ray& ray, const RayOptions& opt, const ProjectionSetup& p) {
  if (p.discrete) {
    const DiscreteProjectionResult r = discrete_projection(scene, ray, *p.discrete);
    return {to_json(r, p.mode), std::isfinite(r.value), true};
  }
  const ProjectionResult r = projection_reference(scene, ray, p.mode, {opt.tol});
  return {to_json(r, p.mode), std::isfinite(r.value) && std::isfinite(r.error_estimate), r.tolerance_met};
}

Answer answer(const Scene& scene, const Ray& ray, const RayOptions& opt,
              const std::optional<DiscreteConfig>& discrete) {
  if (opt.projection) return projection_answer(scene, ray, opt, *opt.projection);
  if (scene.color)
    return discrete ? color_discrete_answer(scene, ray, *discrete)
                    : color_reference_answer(integrate_color_reference(scene, ray, {opt.tol}));
  if (discrete) {
    Answer a = discrete_answer(discrete_raycast(scene, ray, *discrete));
    if (opt.bound) {
      const DiscreteErrorEstimate e = estimate_discrete_error(scene, ray, *discrete);
      a.json["error_bound"] = finite_or_null(discrete_error_bound(scene, ray, *discrete).bound);
      a.json["error_estimate"] = finite_or_null(e.error);
      a.json["asymptotic"] = e.asymptotic;
    }
    return a;
  }
  return reference_answer(integrate_reference(scene, ray, {opt.tol}));
}

// --bound asks for a grey discrete raycast the bound covers (lib/discrete_error_bound.h): refused
// before anything runs otherwise, with the reason.
void check_bound_request(const Scene& scene, const RayOptions& opt, const std::optional<DiscreteConfig>& discrete) {
  if (!opt.bound) return;
  if (opt.projection || !discrete)
    throw std::invalid_argument("--bound: applies to a discrete raycast (--method), not to the reference or --mode");
  if (const std::string why = why_no_error_bound(scene, *discrete); !why.empty())
    throw std::invalid_argument(fmt::format("--bound: no a-priori bound is derived for {} (docs/error-bounds.md)", why));
}

double work_factor(const RayOptions& opt) { return opt.bound ? kPredictedRaycastWorkFactor : 1; }

void print_text(const Answer& a, const std::optional<DiscreteConfig>& discrete) {
  const auto& j = a.json;
  if (j.contains("mode")) {  // a projection: every key as it is in the JSON
    for (const auto& [key, value] : j.items()) {
      if (value.is_number_float()) fmt::print("{:<14} {:.17g}\n", key, value.get<double>());
      else fmt::print("{:<14} {}\n", key, value.is_string() ? value.get<std::string>() : value.dump());
    }
    return;
  }
  // A number, or an RGB scene's three (the answer is finite: nothing is null).
  const auto numbers = [](const nlohmann::ordered_json& v, const char* format) {
    if (!v.is_array()) return fmt::format(fmt::runtime(format), v.get<double>());
    std::string s;
    for (const auto& x : v) s += fmt::format(fmt::runtime(s.empty() ? "{}" : " {}"), fmt::format(fmt::runtime(format), x.get<double>()));
    return s;
  };
  fmt::print("value          {}\n", numbers(j["value"], "{:.17g}"));
  if (discrete) {
    fmt::print("samples        {}\n", j["samples"].get<long>());
    if (j.contains("error_bound"))
      fmt::print("error_bound    {:.3g}\nerror_estimate {:.3g}{}\n", j["error_bound"].get<double>(),
                 j["error_estimate"].get<double>(), j["asymptotic"].get<bool>() ? "" : " (not asymptotic)");
    return;
  }
  fmt::print("error_estimate {}\nevaluations    {}\n", numbers(j["error_estimate"], "{:.3g}"),
             j["evaluations"].get<long>());
  if (!j["t_entry"].is_null())
    fmt::print("t_entry        {:.17g}\nt_exit         {:.17g}\noptical_depth  {}\n",
               j["t_entry"].get<double>(), j["t_exit"].get<double>(), numbers(j["optical_depth"], "{:.17g}"));
  else
    fmt::print("(the ray misses the volume: value is the background)\n");
  fmt::print("tolerance_met  {}\n", a.tolerance_met);
}

// "lines 3, 7, 12 and 5 more" from 1-based input line numbers.
std::string line_list(const std::vector<long>& lines) {
  constexpr std::size_t kShown = 5;
  std::string s;
  for (std::size_t i = 0; i < lines.size() && i < kShown; ++i)
    s += fmt::format("{}{}", i ? ", " : "", lines[i]);
  if (lines.size() > kShown) s += fmt::format(" and {} more", lines.size() - kShown);
  return fmt::format("line{} {}", lines.size() == 1 ? "" : "s", s);
}

std::vector<RayLine> read_rays_input(const std::string& path) {
  if (path == "-") return read_rays(std::cin, "<stdin>");
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw std::invalid_argument(fmt::format("--rays: {}: is a directory, not a rays file", path));
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(fmt::format("--rays: {}: cannot be read", path));
  return read_rays(in, path);
}

// The refusal of a rays file above --max-work: its remedy is the file's, not an image's.
[[noreturn]] void refuse_rays_file(const RayOptions& opt, bool discrete, double rays, double work,
                                   const char* how) {
  throw std::invalid_argument(fmt::format(
      "--rays {}: about {:.3g} rays{}, {:.3g} {}, above the work limit of {:.3g}; split the file or "
      "allow it with --max-work {}",
      opt.rays == "-" ? "<stdin>" : opt.rays, rays, how, work,
      discrete ? "samples" : "field evaluations of the reference", opt.discrete.max_work,
      work_limit_allowing(work)));
}

// A rays file counted before it is read, each ray at the box diagonal's work (an upper estimate):
// one far above --max-work is refused after reading only the lines the limit allows (at least
// 100,000, which are then estimated exactly), the rest estimated from the file's size.  Standard input and devices are checked once read (they cannot
// be read twice).
void refuse_long_rays_file(const Scene& scene, const RayOptions& opt, const std::optional<DiscreteConfig>& discrete) {
  const double per_ray = diagonal_work(discrete, opt.tol, scene) * work_factor(opt);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(opt.rays, ec) || !(per_ray > 0)) return;  // /dev/zero never ends
  std::ifstream in(opt.rays, std::ios::binary);
  if (!in) return;  // read_rays_input names the file
  // Up to 100,000 rays are read (under a second) and estimated ray by ray, exactly.
  const double allowed = std::max(std::floor(opt.discrete.max_work / per_ray), 1e5);
  const RayLineCount count = count_ray_lines(in, static_cast<long>(std::min(allowed, 1e18)));
  if (count.lines <= allowed) return;
  const auto size = std::filesystem::file_size(opt.rays, ec);
  const double rays = ec ? count.lines : std::max<double>(count.lines, std::round(static_cast<double>(size) * count.lines / count.bytes));
  refuse_rays_file(opt, discrete.has_value(), rays, rays * per_ray,
                   " (counted before reading them, each at the box diagonal's work)");
}

// Every ray, validated first, cast in parallel (each into its own slot) and printed in input
// order, so the output is the same for any thread count.
void run_rays(const Scene& scene, const RayOptions& opt, const std::optional<DiscreteConfig>& discrete) {
  refuse_long_rays_file(scene, opt, discrete);
  const std::vector<RayLine> rays = read_rays_input(opt.rays);
  const long n = static_cast<long>(rays.size());
  const double work =
      estimate_work(discrete, opt.tol, scene, n, [&](long i) { return rays[i].ray; }) * work_factor(opt);
  if (work > opt.discrete.max_work) refuse_rays_file(opt, discrete.has_value(), n, work, "");
  std::vector<Answer> answers(rays.size());
  {
    const ThreadLimit threads(opt.threads);
    Progress progress("rays", n, !opt.quiet);
    parallel_for_index(n, [&](long i) {
      answers[i] = answer(scene, rays[i].ray, opt, discrete);
      progress.advance();
    });
  }
  std::vector<long> missed, not_finite;
  std::string out;
  for (long i = 0; i < n; ++i) {
    nlohmann::ordered_json line;
    if (!rays[i].id.is_null()) line["id"] = rays[i].id;
    line.update(answers[i].json);
    out += line.dump() + '\n';
    if (!answers[i].finite) not_finite.push_back(rays[i].line);
    else if (!answers[i].tolerance_met) missed.push_back(rays[i].line);
  }
  std::cout << out << std::flush;
  const std::string name = opt.rays == "-" ? "<stdin>" : opt.rays;
  if (!not_finite.empty())
    throw CommandFailed(kExitNotFinite,
                        fmt::format("vrv ray: {}: {} of {} rays gave a non-finite value (null in the "
                                    "output): {}", name, not_finite.size(), n, line_list(not_finite)));
  if (!missed.empty())
    throw CommandFailed(kExitToleranceMissed,
                        fmt::format("vrv ray: {}: {} of {} rays missed --tol {:g} (\"tolerance_met\": "
                                    "false): {}", name, missed.size(), n, opt.tol, line_list(missed)));
}

Ray ray_from_options(const RayOptions& opt) {
  if (opt.origin.empty() || opt.direction.empty())
    throw std::invalid_argument("--origin and --direction are required (or --rays FILE)");
  try {
    return make_ray(parse_vec3(opt.origin, "--origin"), parse_vec3(opt.direction, "--direction"));
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    throw std::invalid_argument(m.starts_with("--") ? m : "--direction: " + m);
  }
}

void run_one(const Scene& scene, const RayOptions& opt, const std::optional<DiscreteConfig>& discrete) {
  if (opt.threads_option->count() > 0)
    throw std::invalid_argument("--threads: applies to --rays only (one ray runs on one thread)");
  const Ray ray = ray_from_options(opt);
  const double work = estimate_work(discrete, opt.tol, scene, 1, [&](long) { return ray; }) * work_factor(opt);
  if (work > opt.discrete.max_work) refuse_work(opt.discrete, discrete.has_value(), work, 1);
  if (work > 1e8 && !opt.quiet && isatty(STDERR_FILENO))  // one ray has no progress steps
    std::cerr << fmt::format("vrv ray: about {:.3g} field evaluations...\n", work);
  const Answer a = answer(scene, ray, opt, discrete);
  if (!a.finite)
    throw CommandFailed(kExitNotFinite,
                        fmt::format("vrv: error: the {} gave a non-finite value ({}); nothing printed",
                                    discrete ? "discrete raycast" : "reference",
                                    discrete ? "check --precision and the transfer function's range"
                                             : "value or error estimate is NaN or infinite"));
  if (opt.json) std::cout << a.json.dump() << '\n';
  else print_text(a, discrete);
  std::cout << std::flush;
  if (!a.tolerance_met) {
    // Under tol, the estimate missed nothing: a work limit stopped the refinement (it still bounds
    // the error); saying "estimate > tol" there read as a contradiction.
    double estimate = 0;  // an RGB ray's largest
    for (const auto& e : a.json["error_estimate"].is_array() ? a.json["error_estimate"]
                                                             : nlohmann::ordered_json::array({a.json["error_estimate"]}))
      estimate = std::max(estimate, e.get<double>());
    const std::string why =
        estimate > opt.tol ? fmt::format("error estimate {:.3g} > --tol {:g}", estimate, opt.tol)
                           : fmt::format("a work limit ended the refinement (the error estimate {:.3g} still "
                                         "bounds the error, but the work to certify --tol {:g} was not done)",
                                         estimate, opt.tol);
    throw CommandFailed(kExitToleranceMissed,
                        fmt::format("vrv ray: tolerance missed: {} (\"tolerance_met\": false)", why));
  }
}

void run_ray(RayOptions& opt) {
  check_tolerance(opt.tol);
  check_threads(opt.threads);
  if (!opt.discrete.method.empty() && opt.tol_option->count() > 0)
    throw std::invalid_argument("--tol: applies to the reference only, not to --method");
  if (!opt.rays.empty() && (!opt.origin.empty() || !opt.direction.empty()))
    throw std::invalid_argument("--rays: give either --rays or --origin/--direction, not both");
  const Scene scene = load_scene_or_default(opt.scene, memory_limit_bytes(opt.max_memory_gib));
  opt.projection = projection_setup(chosen_mode(opt.mode, scene_text_or_default(opt.scene)), opt.discrete, scene);
  if (opt.projection) require_grey(scene, opt.scene, "vrv ray --mode");
  // A projection's work is estimated as the emission-absorption cast's of the same sampling.
  const auto discrete = opt.projection ? opt.projection->work : discrete_config(opt.discrete, scene);
  check_bound_request(scene, opt, discrete);
  if (!opt.rays.empty()) run_rays(scene, opt, discrete);
  else run_one(scene, opt, discrete);
}

}  // namespace

void add_ray_command(CLI::App& app) {
  auto opt = std::make_shared<RayOptions>();
  CLI::App* cmd = app.add_subcommand(
      "ray", "Reference value of the emission-absorption integral along a ray (or rays)");
  cmd->footer(
      "--rays FILE|-: one JSON object per line, {\"origin\": [x,y,z], \"direction\": [x,y,z], "
      "\"id\": any}; the whole input is checked before any ray is cast; one JSON line per ray, in "
      "input order, with the id first.\n"
      "Exit: 0; 2 bad input (nothing printed); 3 a reference value missed --tol (printed with "
      "\"tolerance_met\": false, named on stderr); 4 a value is NaN or infinite (single ray: "
      "nothing printed; --rays: null, lines named on stderr).");
  cmd->add_option("--scene", opt->scene, "Scene file (TOML); the embedded default when omitted");
  add_volume_memory_option(*cmd, opt->max_memory_gib);
  cmd->add_option("--origin", opt->origin, "Ray origin x,y,z (world units)");
  cmd->add_option("--direction", opt->direction, "Ray direction x,y,z (any length but zero)");
  cmd->add_option("--rays", opt->rays, "JSON-lines file of rays, or - for standard input");
  opt->tol_option =
      add_shared_option(*cmd, Option::tol, opt->tol, "(the reference; not with --method)");
  cmd->add_flag("--json", opt->json, "One JSON line per ray, values to full double precision");
  opt->threads_option = cmd->add_option(
      "--threads", opt->threads, "Threads for --rays (default: all cores); results do not depend on it");
  cmd->add_flag("--quiet", opt->quiet, "No progress bar on stderr");
  add_discrete_options(*cmd, opt->discrete);
  cmd->add_flag("--bound", opt->bound,
                "With --method: also the raycast's a-priori error bound, |value - I| <= error_bound, and "
                "its estimated error value - I with whether the steps resolve the field (asymptotic) "
                "(docs/error-bounds.md; about 40 field evaluations per sample)");
  add_mode_option(*cmd, opt->mode);
  cmd->callback([opt] { run_ray(*opt); });
}

}  // namespace vrv::cli
