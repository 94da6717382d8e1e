// Fuzz target: parse a scene, then cast one reference ray and one discrete ray through it.  The
// input is a scene file; two optional comment lines (TOML ignores them) choose the ray and the
// discrete method, else a ray through the box centre and riemann at one sample per voxel:
//   #ray OX OY OZ DX DY DZ
//   #method RULE STRATEGY RATE_OR_STEP [N] [CORRECTION] [float]
// A valid scene and ray must give a finite reference value with a finite, non-negative error
// estimate (every channel's, for an RGB scene), and a finite double-precision discrete value: a NaN is never a silent result.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>

#include "lib/discrete_raycast.h"
#include "lib/reference_channels.h"
#include "lib/reference_integrator.h"
#include "lib/scene_file.h"
#include "tests/fuzz/fuzz_limits.h"

namespace {

constexpr double kMaxSamples = 1e6;  // per discrete ray: the harness's work budget

// The words after `tag` on the first line that starts with it, or "".
std::string directive(const std::string& text, const std::string& tag) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(tag + " ", 0) == 0) return line.substr(tag.size() + 1);
  return "";
}

vrv::Ray ray_for(const vrv::Scene& scene, const std::string& words) {
  std::istringstream in(words);
  vrv::Vec3 o, d;
  if (in >> o[0] >> o[1] >> o[2] >> d[0] >> d[1] >> d[2]) return vrv::make_ray(o, d);
  const vrv::Vec3 centre = 0.5 * (scene.box.min + scene.box.max);
  const vrv::Vec3 dir(1, 0.3, 0.2);
  return vrv::make_ray(centre - 2 * scene.box.extent().norm() * dir.normalized(), dir);
}

// False when the method line means nothing or asks for more than the harness's budget.
bool config_for(const vrv::Scene& scene, const std::string& words, vrv::DiscreteConfig& c) {
  c.sampling.dims = scene.dims;
  std::istringstream in(words);
  std::string rule, strategy, correction, precision;
  double value = 1;
  if (in >> rule >> strategy >> value) {
    const auto r = vrv::parse_segment_rule(rule);
    const auto s = vrv::parse_strategy(strategy);
    if (!r || !s || !std::isfinite(value) || !(value > 0)) return false;
    c.rule = *r;
    c.sampling.strategy = *s;
    const bool step = *s == vrv::Strategy::step || *s == vrv::Strategy::vtk || *s == vrv::Strategy::inviwo;
    (step ? c.sampling.step : c.sampling.rate) = value;
    int n = 1;
    if (in >> n) {
      if (n < 1 || n > 1024) return false;
      c.oversample = n;
    }
    if (in >> correction) {
      const auto k = vrv::parse_correction(correction);
      if (!k) return false;
      c.correction = *k;
    }
    if (in >> precision && precision == "float") c.precision = vrv::Precision::single_precision;
  } else {
    c.sampling.strategy = vrv::Strategy::entry_exit_corner;
    c.sampling.rate = 1;
  }
  const bool step = c.sampling.step > 0;
  const double dims = std::max({scene.dims[0], scene.dims[1], scene.dims[2]});
  const double samples =
      (step ? scene.box.extent().norm() / c.sampling.step : c.sampling.rate * std::sqrt(3.0) * dims) *
      c.oversample;
  if (!(samples <= kMaxSamples)) return false;
  try {
    vrv::validate(c, std::holds_alternative<vrv::GridField>(scene.field));
  } catch (const std::invalid_argument&) {
    return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (!vrv::fuzz::worth_running(text)) return -1;
  vrv::Scene scene;
  vrv::Ray ray;
  try {
    scene = vrv::parse_scene(text, "fuzz.toml");
    ray = ray_for(scene, directive(text, "#ray"));
  } catch (const vrv::SceneFileError&) {
    return 0;
  } catch (const std::invalid_argument&) {  // make_ray: a zero or non-finite direction
    return 0;
  }
  const vrv::ReferenceResult ref = vrv::integrate_reference(scene, ray, {1e-10});
  if (!std::isfinite(ref.value) || !std::isfinite(ref.error_estimate) || !(ref.error_estimate >= 0))
    std::abort();
  if (scene.color) {  // an RGB scene: every channel from the shared panels, finite likewise
    const vrv::ChannelsReferenceResult rgb = vrv::integrate_color_reference(scene, ray, {1e-10});
    for (const vrv::ReferenceResult& c : rgb.channels())
      if (!std::isfinite(c.value) || !std::isfinite(c.error_estimate) || !(c.error_estimate >= 0)) std::abort();
  }
  vrv::DiscreteConfig config;
  if (!config_for(scene, directive(text, "#method"), config)) return 0;
  const vrv::DiscreteResult d = vrv::discrete_raycast(scene, ray, config);
  // Float precision may overflow to inf for extinction beyond float's range: the commands refuse
  // that result (issue 12, CLI); here only double precision must stay finite.
  if (config.precision == vrv::Precision::double_precision && !std::isfinite(d.value)) std::abort();
  return 0;
}
