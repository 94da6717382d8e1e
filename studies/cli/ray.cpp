// vrv ray: the reference value along one ray, or along every ray of a JSON-lines file.
#include <fstream>
#include <iostream>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "studies/cli/cli_support.h"
#include "studies/cli/discrete_options.h"
#include "studies/cli/commands.h"

namespace vrv::cli {
namespace {

struct RayOptions {
  std::string scene;
  std::string origin;
  std::string direction;
  std::string rays;
  double tol = 1e-12;
  bool json = false;
  DiscreteOptions discrete;
};

void print_discrete(const DiscreteResult& r, bool json) {
  if (json) {
    nlohmann::ordered_json j;
    j["value"] = r.value;
    j["samples"] = r.samples;
    std::cout << j.dump() << '\n';
    return;
  }
  fmt::print("value          {:.17g}\nsamples        {}\n", r.value, r.samples);
}

void print_result(const ReferenceResult& r, bool json) {
  if (json) {
    std::cout << to_json(r).dump() << '\n';
    return;
  }
  fmt::print("value          {:.17g}\nerror_estimate {:.3g}\nevaluations    {}\n", r.value,
             r.error_estimate, r.evaluations);
  if (r.hit)
    fmt::print("t_entry        {:.17g}\nt_exit         {:.17g}\noptical_depth  {:.17g}\n",
               r.t_entry, r.t_exit, r.optical_depth);
  else
    fmt::print("(the ray misses the volume: value is the background)\n");
}

Vec3 json_vec3(const nlohmann::json& line, const char* key, const std::string& where) {
  if (!line.contains(key)) throw std::invalid_argument(fmt::format("{}: {}: missing", where, key));
  const auto& a = line[key];
  if (!a.is_array() || a.size() != 3)
    throw std::invalid_argument(fmt::format("{}: {}: expected an array of three numbers", where, key));
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!a[i].is_number())
      throw std::invalid_argument(fmt::format("{}: {}[{}]: not a number", where, key, i));
    v[i] = a[i].get<double>();
  }
  return v;
}

// One ray: the discrete raycast when a method is configured, else the reference.
void answer(const Scene& scene, const Ray& ray, const RayOptions& opt,
            const std::optional<DiscreteConfig>& discrete, bool json) {
  if (discrete)
    print_discrete(discrete_raycast(scene, ray, *discrete), json);
  else
    print_result(integrate_reference(scene, ray, {opt.tol}), json);
}

void run_rays_file(const Scene& scene, const RayOptions& opt, const std::optional<DiscreteConfig>& discrete) {
  std::ifstream in(opt.rays);
  if (!in) throw std::invalid_argument(fmt::format("{}: cannot be read", opt.rays));
  std::string text;
  for (int number = 1; std::getline(in, text); ++number) {
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = fmt::format("{}:{}", opt.rays, number);
    const auto line = nlohmann::json::parse(text, nullptr, false);
    if (line.is_discarded() || !line.is_object())
      throw std::invalid_argument(fmt::format("{}: not a JSON object", where));
    Ray ray;
    try {
      ray = make_ray(json_vec3(line, "origin", where), json_vec3(line, "direction", where));
    } catch (const std::invalid_argument& e) {
      const std::string m = e.what();
      throw std::invalid_argument(m.starts_with(where) ? m : fmt::format("{}: {}", where, m));
    }
    answer(scene, ray, opt, discrete, true);
  }
}

void run_ray(const RayOptions& opt) {
  check_tolerance(opt.tol);
  const Scene scene = load_scene_or_default(opt.scene);
  const auto discrete = discrete_config(opt.discrete, scene);
  if (!opt.rays.empty()) {
    if (!opt.origin.empty() || !opt.direction.empty())
      throw std::invalid_argument("--rays: give either --rays or --origin/--direction, not both");
    run_rays_file(scene, opt, discrete);
    return;
  }
  if (opt.origin.empty() || opt.direction.empty())
    throw std::invalid_argument("--origin and --direction are required (or --rays FILE)");
  Ray ray;
  try {
    ray = make_ray(parse_vec3(opt.origin, "--origin"), parse_vec3(opt.direction, "--direction"));
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    throw std::invalid_argument(m.starts_with("--") ? m : "--direction: " + m);
  }
  answer(scene, ray, opt, discrete, opt.json);
}

}  // namespace

void add_ray_command(CLI::App& app) {
  auto opt = std::make_shared<RayOptions>();
  CLI::App* cmd = app.add_subcommand(
      "ray", "Reference value of the emission-absorption integral along a ray (or rays)");
  cmd->add_option("--scene", opt->scene, "Scene file (TOML); the embedded default when omitted");
  cmd->add_option("--origin", opt->origin, "Ray origin x,y,z (world units)");
  cmd->add_option("--direction", opt->direction, "Ray direction x,y,z (any length but zero)");
  cmd->add_option("--rays", opt->rays,
                  "JSON-lines file, one {\"origin\": [x,y,z], \"direction\": [x,y,z]} per line");
  cmd->add_option("--tol", opt->tol, "Absolute tolerance on I")->capture_default_str();
  cmd->add_flag("--json", opt->json, "One JSON line per ray, values to full double precision");
  add_discrete_options(*cmd, opt->discrete);
  cmd->callback([opt] { run_ray(*opt); });
}

}  // namespace vrv::cli
