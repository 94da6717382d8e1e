// `import vrv`: the C++ API (lib/vrv.h) for Python, numpy arrays in and out.
//
// Rays are arrays of shape (..., 3); results keep the leading shape.  The work runs with the GIL
// released, in parallel over rays (TBB), and every number is the one `vrv ray --json` prints.
// Bad input raises with the command line's one-line message: ValueError for bad values (an option
// named by the keyword the caller wrote, tol= as "tol: ...", where the command line says "--tol:
// ..."), FileNotFoundError / IsADirectoryError / PermissionError for scene files that cannot be read.
// Work above max_work is refused up front with the command line's --max-work message, and
// Ctrl-C stops a running call within a pixel or so (KeyboardInterrupt, nothing returned or written).
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "lib/discrete_error_estimate.h"
#include "lib/discrete_options.h"
#include "lib/discrete_plan.h"
#include "lib/image_loop.h"  // pixel_ray
#include "lib/io/npy.h"
#include "lib/io/output_paths.h"
#include "lib/verify/verify_output.h"
#include "lib/verify/projection_models.h"
#include "lib/verify/verify_report_html.h"
#include "lib/util/parallel.h"
#include "lib/verify_work.h"
#include "lib/vrv.h"
#include "lib/option_error.h"
#include "lib/projection/projection_reference.h"
#include "lib/scene_mode.h"
#include "studies/cli/projection_options.h"
#include "lib/io/image_module.h"
#include "studies/cli/published_folder.h"
#include "studies/cli/verify_run.h"  // kVerifyOutMarker
#include "studies/engine/memory_budget.h"
#include "studies/engine/plot_script.h"

namespace py = pybind11;

namespace vrv::python {
namespace {

using Points = py::array_t<double, py::array::c_style | py::array::forcecast>;

// Runs `work` (no Python inside) on a worker thread in a TBB task group while this thread, without
// the GIL, runs Python's signal handlers every 50 ms: an exception from one (KeyboardInterrupt on
// Ctrl-C) cancels the group, whose loops stop within an item or so (WorkCancelled,
// lib/util/parallel.h), and is raised once the worker has stopped; the work's result is dropped.
template <class Work>
auto interruptible(Work&& work) -> decltype(work()) {
  using Result = decltype(work());
  tbb::task_group group;
  std::optional<Result> result;
  auto done = std::async(std::launch::async, [&] { group.run_and_wait([&] { result.emplace(work()); }); });
  std::optional<py::error_already_set> interrupt;
  {
    py::gil_scoped_release release;
    while (done.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
      py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) {
        interrupt.emplace();  // takes the handler's exception
        group.cancel();
        break;
      }
    }
    done.wait();
  }
  if (interrupt) throw std::move(*interrupt);
  done.get();  // the work's own exception, if any
  if (!result) throw WorkCancelled();  // cancelled by TBB itself; not expected
  return std::move(*result);
}

// An array (or a nested list) of real numbers as doubles.  numpy would cast a complex array to its
// real part (a warning, not an error) and booleans to 0 and 1: ValueError naming the argument.
// Anything else numpy converts is taken (object arrays of numbers, integers past int64); what it
// cannot convert is a TypeError naming the argument.
Points real_array(const py::handle& h, const std::string& name) {
  if (const py::array a = py::array::ensure(h)) {
    const char kind = a.dtype().kind();
    if (kind == 'c' || kind == 'b')
      throw std::invalid_argument(fmt::format("{}: dtype {} is not real numbers (give floats or integers)", name,
                                              py::str(a.dtype()).cast<std::string>()));
  }
  try {
    return py::cast<Points>(h);
  } catch (const std::exception&) {  // pybind11's cast_error, or numpy's own ("could not convert string")
    throw py::type_error(fmt::format("{}: expected an array of numbers, got {}", name,
                                     py::str(py::type::of(h).attr("__name__")).cast<std::string>()));
  }
}

// The leading shape of an (..., 3) array; ValueError naming the argument otherwise.
std::vector<py::ssize_t> leading_shape(const Points& a, const char* name) {
  if (a.ndim() < 1 || a.shape(a.ndim() - 1) != 3)
    throw std::invalid_argument(fmt::format("{}: expected an array of shape (..., 3)", name));
  return {a.shape(), a.shape() + a.ndim() - 1};
}

std::vector<Ray> make_rays(const Points& origins, const Points& directions) {
  const auto shape = leading_shape(origins, "origins");
  if (leading_shape(directions, "directions") != shape)
    throw std::invalid_argument("directions: shape differs from the origins' shape");
  const std::size_t n = origins.size() / 3;
  const double* o = origins.data();
  const double* d = directions.data();
  std::vector<Ray> rays(n);
  for (std::size_t i = 0; i < n; ++i) {
    try {
      rays[i] = make_ray(Vec3(o[3 * i], o[3 * i + 1], o[3 * i + 2]),
                         Vec3(d[3 * i], d[3 * i + 1], d[3 * i + 2]));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("rays[{}]: {}", i, e.what()));
    }
  }
  return rays;
}

template <class T>
py::array_t<T> filled(const std::vector<py::ssize_t>& shape, std::size_t n, auto&& get) {
  py::array_t<T> a(shape);
  T* p = a.mutable_data();
  for (std::size_t i = 0; i < n; ++i) p[i] = get(i);
  return a;
}

// The same with a trailing axis of the three channels (RGB scenes): get(i, c).
template <class T>
py::array_t<T> filled_rgb(std::vector<py::ssize_t> shape, std::size_t n, auto&& get) {
  shape.push_back(3);
  py::array_t<T> a(shape);
  T* p = a.mutable_data();
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) p[3 * i + c] = get(i, c);
  return a;
}

// One keyword into its field of DiscreteOptions (declared in lib/discrete_options.h), as the Python
// type the field holds; an option that needs a method is recorded as given with its value's text,
// which the work refusal quotes as the command line would (a false flag is not given).
template <class T>
void set_keyword(DiscreteOptions& opt, T DiscreteOptions::*member, const DiscreteOptionField& f, const py::handle& value) {
  using Value = typename std::conditional_t<std::is_same_v<T, std::optional<double>>, std::type_identity<double>,
                                            std::conditional_t<std::is_same_v<T, std::optional<std::string>>,
                                                               std::type_identity<std::string>, std::type_identity<T>>>::type;
  // pybind11's cast error ("Unable to cast Python instance to C++ type", a RuntimeError) names
  // neither the keyword nor the value.
  const auto expected = [] {
    if constexpr (std::is_same_v<Value, bool>) return "True or False";
    else if constexpr (std::is_same_v<Value, std::string>) return "a string";
    else if constexpr (std::is_integral_v<Value>) return "a whole number within a C int";
    else return "a number";
  };
  Value v;
  try {
    v = py::cast<Value>(value);
  } catch (const py::cast_error&) {
    throw py::type_error(fmt::format("{}: expected {}, got {}", option_name(f.option, Spelling::key), expected(),
                                     py::repr(value).cast<std::string>()));
  }
  opt.*member = v;
  if (!f.needs_method) return;
  if constexpr (std::is_same_v<Value, bool>) {
    if (v) opt.give(f.option, "true");
  } else if constexpr (std::is_same_v<Value, std::string>) {
    opt.give(f.option, v);
  } else {
    opt.give(f.option, fmt::format("{}", v));
  }
}

// The keywords as lib/discrete_options.h declares them (the command line's names with '_' for
// '-': method=... is --method), so the checks, the defaults (max_work 1e9) and every message are
// `vrv ray`'s and `vrv render`'s.
struct DiscreteKeywords {
  DiscreteOptions options;
  std::optional<DiscreteConfig> config;  // none: the reference
};

std::unique_ptr<DiscreteKeywords> discrete_keywords(const Scene& scene, const py::dict& kw,
                                                    bool projection = false) {
  auto k = std::make_unique<DiscreteKeywords>();
  for (const auto& item : kw) {
    const std::string name = py::str(item.first);
    const py::handle value = item.second;
    const auto fields = discrete_option_fields();
    const auto field = std::find_if(fields.begin(), fields.end(), [&](const DiscreteOptionField& f) {
      return option_name(f.option, Spelling::key) == name;
    });
    if (field == fields.end()) throw py::type_error(fmt::format("unexpected keyword argument '{}'", name));
    if (value.is_none()) continue;
    std::visit([&](auto member) { set_keyword(k->options, member, *field, value); }, field->member);
  }
  if (projection) return k;  // its method and options are read by projection_keywords
  k->config = discrete_config(k->options, scene);  // an OptionError names the keyword (PYBIND11_MODULE)
  return k;
}

// The discrete projection that mode= and method= describe (cli::projection_setup, the command
// line's rules), or none without method; errors name the keywords the caller wrote.
std::optional<DiscreteProjectionConfig> projection_keywords(const Scene& scene, const std::string& mode,
                                                            const DiscreteKeywords& keywords) {
  return cli::projection_setup(mode, keywords.options, scene)->discrete;
}

// Splits mode= from the other keywords (a scene's reference or raycast takes those).
std::optional<std::string> take_mode(const py::kwargs& given, py::dict& rest) {
  std::optional<std::string> mode;
  for (const auto& [key, value] : given) {
    if (py::str(key).cast<std::string>() == "mode") {
      if (!value.is_none()) mode = py::cast<std::string>(value);
    } else {
      rest[key] = value;
    }
  }
  return mode;
}

// mode=...: a projection (lib/projection/projection_mode.h), the command line's vocabulary;
// none or "emission_absorption": emission-absorption.  ValueError naming the keyword otherwise.
std::optional<ProjectionMode> mode_keyword(const std::optional<std::string>& mode) {
  if (!mode || *mode == kEmissionAbsorption) return std::nullopt;
  if (const auto m = parse_projection_mode(*mode)) return m;
  throw std::invalid_argument(
      fmt::format("mode: unknown value '{}' (one of {}, {})", *mode, projection_mode_list(), kEmissionAbsorption));
}

// The fields every reference result has (emission-absorption and projections), in this order, as
// `vrv ray` prints them: NaN entry and exit where the ray misses the box.
template <class Result>
void put_reference_fields(py::dict& out, const std::vector<py::ssize_t>& shape, const std::vector<Result>& r) {
  const std::size_t n = r.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  out["value"] = filled<double>(shape, n, [&](auto i) { return r[i].value; });
  out["error_estimate"] = filled<double>(shape, n, [&](auto i) { return r[i].error_estimate; });
  out["evaluations"] = filled<long>(shape, n, [&](auto i) { return r[i].evaluations; });
  out["hit"] = filled<bool>(shape, n, [&](auto i) { return r[i].hit; });
  out["t_entry"] = filled<double>(shape, n, [&](auto i) { return r[i].hit ? r[i].t_entry : nan; });
  out["t_exit"] = filled<double>(shape, n, [&](auto i) { return r[i].hit ? r[i].t_exit : nan; });
}

// Projection references along rays: value, error_estimate, evaluations, hit, t_entry, t_exit,
// position and ambiguous (MIP) and tolerance_met, as `vrv ray --mode` prints them.
py::dict projection_values(const Scene& scene, const Points& origins, const std::vector<Ray>& rays,
                           ProjectionMode mode, double tol) {
  require_grey(scene, "scene", "mode=");
  const ProjectionOptions options{tol};
  validate(options);
  const std::vector<ProjectionResult> r = interruptible([&] {
    std::vector<ProjectionResult> values(rays.size());
    parallel_for_index(static_cast<long>(rays.size()),
                       [&](long i) { values[i] = projection_reference(scene, rays[i], mode, options); });
    return values;
  });
  const auto shape = leading_shape(origins, "origins");
  const std::size_t n = r.size();
  py::dict out;
  out["mode"] = std::string(projection_mode_name(mode));
  put_reference_fields(out, shape, r);
  if (is_mip(mode)) {
    out["position"] = filled<double>(shape, n, [&](auto i) { return r[i].position; });
    out["ambiguous"] = filled<bool>(shape, n, [&](auto i) { return r[i].ambiguous; });
  }
  out["tolerance_met"] = filled<bool>(shape, n, [&](auto i) { return r[i].tolerance_met; });
  return out;
}

// An RGB scene's references: value, error_estimate, optical_depth and tolerance_met with a trailing
// axis of the channels; evaluations (shared by the channels), hit, t_entry and t_exit without.
py::dict color_reference(const std::vector<py::ssize_t>& shape, const std::vector<ChannelsReferenceResult>& r) {
  const std::size_t n = r.size();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const auto ray = [&](std::size_t i) -> const ReferenceResult& { return r[i].channel[0]; };
  py::dict out;
  out["value"] = filled_rgb<double>(shape, n, [&](auto i, int c) { return r[i].channel[c].value; });
  out["error_estimate"] = filled_rgb<double>(shape, n, [&](auto i, int c) { return r[i].channel[c].error_estimate; });
  out["evaluations"] = filled<long>(shape, n, [&](auto i) { return r[i].evaluations; });
  out["hit"] = filled<bool>(shape, n, [&](auto i) { return ray(i).hit; });
  out["t_entry"] = filled<double>(shape, n, [&](auto i) { return ray(i).hit ? ray(i).t_entry : nan; });
  out["t_exit"] = filled<double>(shape, n, [&](auto i) { return ray(i).hit ? ray(i).t_exit : nan; });
  out["optical_depth"] = filled_rgb<double>(shape, n, [&](auto i, int c) { return r[i].channel[c].optical_depth; });
  out["tolerance_met"] = filled_rgb<bool>(shape, n, [&](auto i, int c) { return r[i].channel[c].tolerance_met; });
  return out;
}

py::dict reference(const Scene& scene, const py::object& given_origins, const py::object& given_directions, double tol,
                   double max_work, const std::optional<std::string>& mode_name) {
  const Points origins = real_array(given_origins, "origins"), directions = real_array(given_directions, "directions");
  const std::optional<ProjectionMode> mode = mode_keyword(mode_name);
  const std::vector<Ray> rays = make_rays(origins, directions);
  if (mode) {
    // A projection's work is estimated as the emission-absorption reference's (as vrv ray --mode).
    const auto keywords = discrete_keywords(scene, py::dict(py::arg("max_work") = max_work));
    check_work(keywords->options, std::nullopt, tol, scene, static_cast<long>(rays.size()),
                    [&](long i) { return rays[i]; });
    return projection_values(scene, origins, rays, *mode, tol);
  }
  const ReferenceOptions options{tol};
  validate(options);
  const auto keywords = discrete_keywords(scene, py::dict(py::arg("max_work") = max_work));
  check_work(keywords->options, std::nullopt, tol, scene, static_cast<long>(rays.size()),
                  [&](long i) { return rays[i]; });
  if (scene.color) return color_reference(leading_shape(origins, "origins"), interruptible([&] {
                                            return color_reference_values(scene, rays, options);
                                          }));
  const std::vector<ReferenceResult> r = interruptible([&] {
    std::vector<ReferenceResult> values(rays.size());
    reference_values(scene, rays, options, values);
    return values;
  });
  const auto shape = leading_shape(origins, "origins");
  const std::size_t n = r.size();
  py::dict out;
  put_reference_fields(out, shape, r);
  out["optical_depth"] = filled<double>(shape, n, [&](auto i) { return r[i].optical_depth; });
  out["tolerance_met"] = filled<bool>(shape, n, [&](auto i) { return r[i].tolerance_met; });
  return out;
}

// discrete(mode=...): the discrete projection along rays: value, samples and (MIP) position.
py::dict discrete_projection(const Scene& scene, const Points& origins, const Points& directions, ProjectionMode mode,
                             const py::dict& kw) {
  const auto keywords = discrete_keywords(scene, kw, /*projection=*/true);
  const auto config = projection_keywords(scene, std::string(projection_mode_name(mode)), *keywords);
  if (!config) throw std::invalid_argument("method: required with mode (riemann, trapezoid, simpson; max for MIP)");
  const std::vector<Ray> rays = make_rays(origins, directions);
  DiscreteConfig work;
  work.sampling = config->sampling;
  check_work(keywords->options, work, 0, scene, static_cast<long>(rays.size()), [&](long i) { return rays[i]; });
  const std::vector<DiscreteProjectionResult> r =
      interruptible([&] { return discrete_projection_values(scene, rays, *config); });
  const auto shape = leading_shape(origins, "origins");
  py::dict out;
  out["value"] = filled<double>(shape, r.size(), [&](auto i) { return r[i].value; });
  out["samples"] = filled<long>(shape, r.size(), [&](auto i) { return r[i].samples; });
  if (is_mip(mode)) out["position"] = filled<double>(shape, r.size(), [&](auto i) { return r[i].position; });
  return out;
}

// bound=True (taken out of kw): the a-priori error bound beside the value, as `vrv ray --bound`.
bool take_bound(py::dict& kw) {
  if (!kw.contains("bound")) return false;
  const py::object value = kw["bound"];
  PyDict_DelItemString(kw.ptr(), "bound");
  if (!py::isinstance<py::bool_>(value)) throw std::invalid_argument("bound: must be True or False");
  return value.cast<bool>();
}

py::dict discrete(const Scene& scene, const py::object& given_origins, const py::object& given_directions,
                  const py::kwargs& given) {
  const Points origins = real_array(given_origins, "origins"), directions = real_array(given_directions, "directions");
  py::dict kw;
  const std::optional<ProjectionMode> mode = mode_keyword(take_mode(given, kw));
  const bool bound = take_bound(kw);
  if (mode && bound) throw std::invalid_argument("bound: applies to emission-absorption, not to mode=...");
  if (mode) return discrete_projection(scene, origins, directions, *mode, kw);
  const auto keywords = discrete_keywords(scene, kw);
  const auto& config = keywords->config;
  if (!config) throw std::invalid_argument(fmt::format("--method: required ({})", segment_rule_list()));
  if (bound)
    if (const std::string why = why_no_error_bound(scene, *config); !why.empty())
      throw std::invalid_argument(fmt::format("bound: no a-priori bound is derived for {} (docs/error-bounds.md)", why));
  const std::vector<Ray> rays = make_rays(origins, directions);
  const double work = estimate_work(config, 0, scene, static_cast<long>(rays.size()), [&](long i) { return rays[i]; }) *
                      (bound ? kPredictedRaycastWorkFactor : 1);
  if (work > keywords->options.max_work) refuse_work(keywords->options, true, work, static_cast<long>(rays.size()));
  const auto shape = leading_shape(origins, "origins");
  py::dict out;
  if (scene.color) {  // each channel cast alone: value (..., 3), samples summed over the channels
    const auto r = interruptible([&] { return discrete_channel_values(scene, rays, *config); });
    out["value"] = filled_rgb<double>(shape, rays.size(), [&](auto i, int c) { return r[i].value[c]; });
    out["samples"] = filled<long>(shape, rays.size(), [&](auto i) { return r[i].samples; });
    return out;
  }
  const std::vector<DiscreteResult> r = interruptible([&] { return discrete_values(scene, rays, *config); });
  out["value"] = filled<double>(shape, r.size(), [&](auto i) { return r[i].value; });
  out["samples"] = filled<long>(shape, r.size(), [&](auto i) { return r[i].samples; });
  if (bound) {
    struct Predicted {
      double bound = 0;
      DiscreteErrorEstimate estimate;
    };
    const std::vector<Predicted> p = interruptible([&] {
      std::vector<Predicted> v(rays.size());
      parallel_for_index(static_cast<long>(rays.size()), [&](long i) {
        const Ray& ray = rays[static_cast<std::size_t>(i)];
        v[static_cast<std::size_t>(i)] = {discrete_error_bound(scene, ray, *config).bound,
                                          estimate_discrete_error(scene, ray, *config)};
      });
      return v;
    });
    out["error_bound"] = filled<double>(shape, p.size(), [&](auto i) { return p[i].bound; });
    out["error_estimate"] = filled<double>(shape, p.size(), [&](auto i) { return p[i].estimate.error; });
    out["asymptotic"] = filled<bool>(shape, p.size(), [&](auto i) { return p[i].estimate.asymptotic; });
  }
  return out;
}

// render(mode=..., method=...): the discrete projection of the camera's pixels.
py::array_t<double> render_projection(const Scene& scene, ProjectionMode mode, const Camera& camera,
                                      const py::dict& kw) {
  const std::vector<Ray> rays = camera_rays(camera);
  const auto keywords = discrete_keywords(scene, kw, /*projection=*/true);
  const auto config = projection_keywords(scene, std::string(projection_mode_name(mode)), *keywords);
  DiscreteConfig work;
  work.sampling = config->sampling;
  check_work(keywords->options, work, 0, scene, static_cast<long>(rays.size()), [&](long i) { return rays[i]; });
  const std::vector<DiscreteProjectionResult> r =
      interruptible([&] { return discrete_projection_values(scene, rays, *config); });
  py::array_t<double> a({camera.height, camera.width});
  std::transform(r.begin(), r.end(), a.mutable_data(), [](const DiscreteProjectionResult& v) { return v.value; });
  return a;
}

// An RGB scene's image, or any scene's with alpha: (height, width, channels), A last: the reference
// (one set of panels for the channels), or each channel's discrete image.
py::array_t<double> render_channels(const Scene& scene, const Camera& camera, const std::optional<DiscreteConfig>& config,
                                    const ReferenceOptions& options, bool alpha) {
  const std::vector<Ray> rays = camera_rays(camera);
  const int n = scene.channel_count() + (alpha ? 1 : 0);
  py::array_t<double> a({camera.height, camera.width, n});
  double* p = a.mutable_data();
  if (!config) {
    const auto r = interruptible([&] { return channel_reference_values(scene, rays, options, alpha); });
    for (std::size_t i = 0; i < r.size(); ++i)
      for (int c = 0; c < n; ++c) p[n * i + c] = r[i].channel[c].value;
    return a;
  }
  const ImageF64 image = interruptible([&] { return discrete_channel_image(scene, camera, *config, alpha); });
  std::copy(image.pixels.begin(), image.pixels.end(), p);
  return a;
}

// (height, width) values of the scene's camera: the reference without `method`, else the
// discrete raycast the keywords describe; with mode=, the projection's reference or discrete version.
py::array_t<double> render(const Scene& scene, std::optional<double> given_tol, std::optional<int> width,
                           std::optional<int> height, bool alpha, const py::kwargs& given) {
  py::dict kw;
  const std::optional<ProjectionMode> mode = mode_keyword(take_mode(given, kw));
  if (mode && alpha) throw std::invalid_argument("alpha=: a projection's image has one channel");
  const bool discrete = kw.contains("method") && !kw["method"].is_none();
  // As the command line: a tolerance with a method would be accepted and ignored.
  if (discrete && given_tol) throw std::invalid_argument("tol: applies to the reference only, not to method");
  const double tol = given_tol.value_or(ReferenceOptions{}.tol);
  if (mode && discrete) return render_projection(scene, *mode, scene_camera(scene, width, height), kw);
  const auto keywords = discrete_keywords(scene, kw);
  const auto& config = keywords->config;
  const Camera camera = scene_camera(scene, width, height);
  const ReferenceOptions options{tol};
  if (!config) validate(options);
  check_work(keywords->options, config, tol, scene, static_cast<long>(camera.width) * camera.height,
                  [&](long i) { return pixel_ray(camera, i); });
  if (mode) {
    const ReferenceImage ref = interruptible([&] { return projection_reference_image(scene, camera, *mode, tol, false); });
    py::array_t<double> a({camera.height, camera.width});
    std::copy(ref.pixels.begin(), ref.pixels.end(), a.mutable_data());
    return a;
  }
  if (scene.color || alpha) return render_channels(scene, camera, config, options, alpha);
  const ValueImage image = interruptible([&] {
    return config ? render_discrete_image(scene, camera, *config) : render_reference_image(scene, camera, options);
  });
  py::array_t<double> a({image.height, image.width});
  std::copy(image.pixels.begin(), image.pixels.end(), a.mutable_data());
  return a;
}

// Camera rays as (origins, directions), each of shape (height, width, 3).
py::tuple rays(const Scene& scene, std::optional<int> width, std::optional<int> height) {
  const Camera camera = scene_camera(scene, width, height);
  const std::vector<Ray> r = camera_rays(camera);
  py::array_t<double> o({camera.height, camera.width, 3}), d({camera.height, camera.width, 3});
  double* po = o.mutable_data();
  double* pd = d.mutable_data();
  for (std::size_t i = 0; i < r.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      po[3 * i + k] = r[i].origin[k];
      pd[3 * i + k] = r[i].direction[k];
    }
  return py::make_tuple(o, d);
}

// A scene or bounds file that cannot be read raises the OSError Python uses for that reason,
// with the loader's message; any other problem in it is a ValueError.
template <class Error, class Load>
auto load_file(const std::filesystem::path& path, Load load) {
  try {
    return load(path);
  } catch (const Error& e) {
    std::error_code ec;
    PyObject* type = PyExc_ValueError;
    if (!std::filesystem::exists(path, ec)) type = PyExc_FileNotFoundError;
    else if (std::filesystem::is_directory(path, ec)) type = PyExc_IsADirectoryError;
    else if (std::string(e.what()).find("cannot open") != std::string::npos) type = PyExc_PermissionError;
    PyErr_SetString(type, e.what());
    throw py::error_already_set();
  }
}

// A volume file is refused from its header above max_memory GiB (default 3/4 of physical memory,
// as the command line's --max-memory): without a limit a VTI file without end was read until
// MemoryError.
Scene from_file(const std::filesystem::path& path, std::optional<double> max_memory) {
  if (max_memory && !(*max_memory > 0 && std::isfinite(*max_memory)))
    throw std::invalid_argument(fmt::format("max_memory: must be a positive number of GiB, got {}", *max_memory));
  const double limit = max_memory ? *max_memory * double(1 << 30) : default_memory_limit();
  return load_file<SceneFileError>(path, [&](const auto& p) { return load_scene(p, limit); });
}

py::dict box(const Scene& scene) {
  py::dict d;
  d["min"] = py::make_tuple(scene.box.min[0], scene.box.min[1], scene.box.min[2]);
  d["max"] = py::make_tuple(scene.box.max[0], scene.box.max[1], scene.box.max[2]);
  return d;
}

// A (height, width) or (height, width, channels) array as `vrv verify` reads the same array from
// a .npy file (lib/io/image_channels.h): grey, grey+alpha, RGB or RGBA; float32 keeps its type
// (and its quantum), anything else is taken as float64.  ValueError "images[i]: <reason>".
ChannelImage array_image(const py::handle& h, std::size_t index) {
  NpyArray a;
  const auto as_npy = [&](auto array, const char* dtype) {
    a.dtype = dtype;
    a.shape.assign(array.shape(), array.shape() + array.ndim());
    a.values.assign(array.data(), array.data() + array.size());
  };
  const std::string name = fmt::format("images[{}]", index);
  if (py::isinstance<py::array_t<float>>(h))
    as_npy(py::cast<py::array_t<float, py::array::c_style | py::array::forcecast>>(h), "<f4");
  else
    as_npy(real_array(h, name), "<f8");
  try {
    return channel_image(a, name);
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument(e.what());
  }
}

// The first image's (width, height) when its shape is an image's, read before any array is
// copied so that too much work is refused first; (0, 0) otherwise (array_image says why).
std::pair<int, int> image_size(const py::sequence& images) {
  if (images.size() == 0) return {0, 0};
  const py::array a = py::array::ensure(images[0]);
  constexpr py::ssize_t kMaxSide = 1 << 16;  // array_image's (lib/io/image_channels.h)
  if (!a || (a.ndim() != 2 && a.ndim() != 3) || a.shape(0) < 1 || a.shape(1) < 1 || a.shape(0) > kMaxSide ||
      a.shape(1) > kMaxSide)
    return {0, 0};
  return {static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0))};
}

// The bounds of a bounds file: its [defaults], or the case named `case_name`.
BoundSet bounds_of(const std::filesystem::path& file, const std::optional<std::string>& case_name) {
  const BoundsFile bounds = load_file<BoundsFileError>(file, [](const auto& p) { return load_bounds(p); });
  return chosen_bounds(bounds, case_name);
}

// studies/engine/plot_study.py, looked for as `vrv verify` looks (studies/engine/plot_script.h):
// under ./studies, <module dir>/../studies, $VRV_STUDY_PATH, the source tree the module was built
// from, then the installed copy relative to the module.
PlotScript plot_script() {
  namespace fs = std::filesystem;
  std::vector<fs::path> dirs{fs::path("studies")};
  const fs::path module(py::module_::import("vrv").attr("__file__").cast<std::string>());
  dirs.push_back(fs::absolute(module).parent_path().parent_path() / "studies");
  if (const char* env = std::getenv("VRV_STUDY_PATH"); env && *env) dirs.emplace_back(env);
  dirs.push_back(fs::path(VRV_SOURCE_DIR) / "studies");
  return find_plot_script(dirs);
}

// The log-log plot of `out`/plots.json, drawn as `vrv verify --out` draws it: the plot script run
// by $VRV_PYTHON, else Debian's /usr/bin/python3 (python3-matplotlib), else python3.  A plot that
// cannot be drawn is, as there, one line (a RuntimeWarning here) and not an error: the tables stand.
// `shown`: the folder as the user named it (the plot is drawn in its staging folder).
void draw_plot(const std::filesystem::path& out, const std::filesystem::path& shown) {
  const std::string python = plot_python();
  const PlotScript script = plot_script();
  int status = 127;  // could not be started, as draw_study_plots counts it
  try {
    if (!script.path.empty())
      status = py::module_::import("subprocess").attr("call")(
          py::make_tuple(python, script.path.string(), out.string())).cast<int>();
  } catch (const py::error_already_set& e) {
    if (!e.matches(PyExc_OSError)) throw;
  }
  const std::string line =
      fmt::format("vrv.verify: {}: the plot could not be drawn: {}", shown.string(), plot_failure(script, status));
  if (status != 0 && PyErr_WarnEx(PyExc_RuntimeWarning, line.c_str(), 1) < 0) throw py::error_already_set();
}

// The call as the report's "To reproduce" shows it (the images are the caller's arrays).
std::string python_call(const std::vector<double>& steps, std::optional<double> expected_order,
                        const std::optional<std::filesystem::path>& bounds,
                        const std::optional<std::string>& case_name, const std::filesystem::path& report) {
  std::string s = fmt::format("vrv.verify(scene, images, steps=[{}]", fmt::join(steps, ", "));
  if (expected_order) s += fmt::format(", expected_order={}", *expected_order);
  if (bounds) s += fmt::format(", bounds={}", nlohmann::json(bounds->string()).dump());
  if (case_name) s += fmt::format(", case={}", nlohmann::json(*case_name).dump());
  return s + fmt::format(", report={})  # images: the {} arrays given", nlohmann::json(report.string()).dump(),
                         steps.size());
}

// vrv.plan: `vrv plan` in-process (lib/discrete_plan.h), its JSON as Python objects.
py::object plan_py(const Scene& scene, double target, const std::string& metric, const std::string& rules,
                   const std::string& strategy, int width, int height, double max_work) {
  const PlanOptions options = plan_options({target, metric, rules, strategy, max_work});
  const Camera camera = scene_camera(scene, width, height);
  const DiscretePlan plan = interruptible([&] { return plan_discrete(scene, camera, options); });
  return py::module_::import("json").attr("loads")(to_json(plan).dump());
}

// `vrv verify` in-process: the report as a dict (the JSON line `vrv verify` prints: to_json of
// lib/verify.h, with the bounds' rows and `pass` including them when a bounds file is given),
// and its files written into `out` when given, with the plot unless `plots` is false.
py::object verify_py(const Scene& scene, const py::sequence& images, const std::vector<double>& steps,
                     std::optional<double> expected_order, double order_tolerance,
                     const std::string& order_metric, double tol, std::optional<double> threshold,
                     bool diagnose, double unit_distance, std::optional<std::filesystem::path> bounds,
                     std::optional<std::string> case_name, std::optional<std::filesystem::path> out,
                     bool plots, double max_work, const std::string& alpha,
                     std::optional<std::filesystem::path> report, const std::optional<std::string>& mode) {
  VerifyOptions options;
  options.mode = mode_keyword(mode);
  apply(VerifySettings{tol, order_tolerance, order_metric, unit_distance, alpha}, options);
  options.expected_order = expected_order;
  options.diagnose = diagnose;
  std::optional<BoundSet> set;
  if (bounds) {
    set = bounds_of(*bounds, case_name);
    use_bounds(*set, options, threshold);
  } else if (case_name) {
    throw std::invalid_argument("--case: needs --bounds");
  }
  if (threshold) options.threshold = *threshold;
  // The plot is drawn into `out`: without it plots=True would be accepted and ignored.
  if (plots && !out) throw std::invalid_argument("plots: the plot is drawn into out; give out= as well");
  // Written as `vrv verify --out` writes: staged beside `out` and published whole, with a lock.
  // Refused before anything is computed: a folder vrv did not write, a missing image module.  The
  // staging folder (and so `out`) is made only once the report exists: a refused or interrupted
  // call leaves nothing behind.
  if (out) {
    check_verify_out(*out);
    check_replaceable_dir(*out, cli::kVerifyOutMarker, "--out");
    image_module::functions();
  }
  if (report) check_verify_report_path(*report, {bounds.value_or("")}, out.value_or(""), "report");
  if (const auto [width, height] = image_size(images); width > 0)
    check_verification_work(scene, options, width, height, steps, 0, max_work, "--max-work");
  std::vector<ChannelImage> values;
  for (std::size_t i = 0; i < images.size(); ++i) values.push_back(array_image(images[i], i));
  const VerifyReport result = interruptible([&] { return verify(scene, values, steps, options); });
  std::vector<BoundRow> rows;
  if (set) rows = evaluate_bounds(case_name.value_or("verify"), result, *set);
  if (out) {
    cli::PublishedFolder folder(*out, cli::kVerifyOutMarker, "--out");
    std::vector<std::pair<std::string, Table>> extra;
    if (set) extra.emplace_back("bounds", bound_table(rows));
    const nlohmann::json parameters = {{"command", "python vrv.verify"}, {"steps", steps},
                                       {"bounds", bounds ? bounds->string() : ""},
                                       {"case", case_name.value_or("")}, {"threshold", options.threshold},
                                       {"tol", tol}, {"order_metric", order_metric}, {"alpha", alpha}};
    folder.write_and_publish([&](const std::filesystem::path& staging) {
      {
        py::gil_scoped_release release;
        write_verify_outputs(staging, result, extra, parameters, 0);
      }
      if (plots) draw_plot(staging, *out);
    });
  }
  if (report) {
    // Arrays cannot be shown as a command: the call itself, with what it was given.
    HtmlReportContext context{"vrv.verify (Python)", {python_call(steps, expected_order, bounds, case_name, *report)}, {}};
    if (set) context.bounds = bound_table(rows);
    py::gil_scoped_release release;
    try {
      write_verify_report_html(*report, result, context);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(fmt::format("report: {}: not written: {}", report->string(), e.what()));
    }
  }
  nlohmann::ordered_json j = to_json(result);
  j["pass"] = result.pass && worst(rows) < BoundVerdict::fail;
  if (set) j["bounds"] = nlohmann::ordered_json::parse(bound_table(rows).to_json());
  if (out) j["out"] = out->string();
  if (report) j["report"] = report->string();
  return py::module_::import("json").attr("loads")(j.dump());
}

}  // namespace
}  // namespace vrv::python

PYBIND11_MODULE(vrv, m) {
  using namespace vrv;
  using namespace vrv::python;
  // The keywords' defaults: the library's option structs' own (as the command line's).
  static const std::string render_doc = fmt::format(
      "The scene camera's image as a (height, width) float64 array: the reference (to tol, default {:g}; "
      "refused with method=...), or with method=... the discrete raycast (options as for `discrete`); "
      "max_work=1e9 as --max-work; mode=... (as `reference`) the projection's reference image, with method=... "
      "its discrete version (as `discrete`); (height, width, 3) for an RGB scene; alpha=True adds "
      "A = 1 - e^-Phi as a last channel ((height, width, 2) grey, (height, width, 4) RGB), as `vrv render --alpha`",
      ReferenceOptions{}.tol);
  const PlanSettings plan_defaults{};
  const VerifySettings verify_defaults{};
  m.doc() = "vrv: the emission-absorption integral to near machine precision, and discrete "
            "raycasts measured against it (docs/library.md)";
  py::register_exception<SceneFileError>(m, "SceneFileError", PyExc_ValueError);
  py::register_exception<BoundsFileError>(m, "BoundsFileError", PyExc_ValueError);
  // The library's option checks (lib/option_error.h), named as keywords.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const OptionError& e) {
      PyErr_SetString(PyExc_ValueError, e.message(Spelling::key).c_str());
    }
  });

  py::class_<Scene>(m, "Scene", "A vrv scene: volume box, field, transfer function, background, camera")
      .def_static("from_file", &from_file, py::arg("path"), py::arg("max_memory") = py::none(),
                  "Load a scene file (TOML); a volume file above max_memory GiB (default 3/4 of physical "
                  "memory) is refused from its header")
      .def_static("from_toml", [](const std::string& text, const std::string& name) {
                    return parse_scene(text, name);
                  }, py::arg("text"), py::arg("name") = "<toml>",
                  "Parse scene TOML text; `name` labels error messages")
      .def_static("default", &default_scene, "The embedded Marschner-Lobb scene (`vrv ray` without --scene)")
      .def_property_readonly("box", &box, "{'min': (x, y, z), 'max': (x, y, z)}")
      .def_property_readonly("dims", [](const Scene& s) { return s.dims; })
      .def_property_readonly("background", [](const Scene& s) -> py::object {
        if (s.color) return py::make_tuple(s.color->background[0], s.color->background[1], s.color->background[2]);
        return py::float_(s.background);
      }, "The background: a number, or (r, g, b) for an RGB scene")
      .def_property_readonly("channels", &Scene::channel_count,
                             "1 for a grey scene, 3 for an RGB one (docs/color.md): reference, discrete and render "
                             "then give a trailing axis of 3 (R, G, B); verify and projections take grey scenes only")
      .def("reference", &reference, py::arg("origins"), py::arg("directions"), py::arg("tol") = ReferenceOptions{}.tol,
           py::kw_only(), py::arg("max_work") = DiscreteOptions{}.max_work, py::arg("mode") = py::none(),
           "Reference values along rays (arrays of shape (..., 3)): a dict of arrays value, "
           "error_estimate, evaluations, hit, t_entry, t_exit (NaN on a miss), optical_depth, tolerance_met; "
           "mode='xray' | 'xray_classified' | 'mip' | 'mip_classified': the projection's reference instead "
           "(no optical_depth; MIP adds position and ambiguous); an RGB scene's value, error_estimate, "
           "optical_depth and tolerance_met have a trailing axis of 3 (R, G, B), evaluations shared")
      .def("discrete", &discrete, py::arg("origins"), py::arg("directions"),
           "A discrete raycast along rays: method=..., and the options of `vrv ray` "
           "(strategy, rate, step, oversample, correction, ...) and max_work (default 1e9 samples, "
           "as --max-work); a dict of arrays value, samples, and with bound=True error_bound, the "
           "a-priori bound |value - I| <= error_bound, error_estimate, the expected value - I, and asymptotic, "
           "whether the steps resolve the field there (docs/error-bounds.md; as `vrv ray --bound`); with mode='xray' | ... | 'mip_classified' "
           "the discrete projection (method riemann, trapezoid, simpson; max for MIP; strategy, rate, "
           "step), MIP adding position; an RGB scene's value has a trailing axis of 3, each channel "
           "cast alone, samples summed")
      .def("render", &render, py::arg("tol") = py::none(), py::arg("width") = py::none(),
           py::arg("height") = py::none(), py::arg("alpha") = false,
           render_doc.c_str())
      .def("rays", &rays, py::arg("width") = py::none(), py::arg("height") = py::none(),
           "The scene camera's rays: (origins, directions), each (height, width, 3)");
  m.def("plan", &plan_py, py::arg("scene"), py::arg("target"), py::kw_only(), py::arg("metric") = plan_defaults.metric,
        py::arg("rules") = plan_defaults.rules, py::arg("strategy") = plan_defaults.strategy,
        py::arg("width") = kPlanImageSide, py::arg("height") = kPlanImageSide, py::arg("max_work") = plan_defaults.max_work,
        "`vrv plan` in-process: per rule the largest step whose estimated error (max or rms over the scene camera's "
        "width x height pixels) is within `target`, predicted before rendering (docs/error-bounds.md); a dict with "
        "`ranked` (cheapest first: rule, strategy, step, estimated_error, met, samples_per_ray, seconds_per_sample, "
        "seconds) and `evaluations`");
  m.def("verify", &verify_py, py::arg("scene"), py::arg("images"), py::arg("steps"), py::kw_only(),
        py::arg("expected_order") = py::none(), py::arg("order_tolerance") = verify_defaults.order_tolerance,
        py::arg("order_metric") = verify_defaults.order_metric, py::arg("tol") = verify_defaults.tol,
        py::arg("threshold") = py::none(), py::arg("diagnose") = VerifyOptions{}.diagnose,
        py::arg("unit_distance") = verify_defaults.unit_distance, py::arg("bounds") = py::none(),
        py::arg("case") = py::none(), py::arg("out") = py::none(), py::arg("plots") = false,
        py::arg("max_work") = kDefaultVerifyWorkLimit, py::arg("alpha") = verify_defaults.alpha,
        py::arg("report") = py::none(), py::arg("mode") = py::none(),
        "`vrv verify` in-process: a renderer's images of the scene's camera ((height, width) arrays, "
        "or (height, width, 3 or 4) for RGB and RGBA as `vrv verify` reads them; one per sample "
        "distance in `steps`) against the reference; above `max_work` field evaluations (as "
        "--max-work) it is refused.  Returns the report `vrv verify` "
        "prints, as a dict (pass, verdict, images, orders, diagnosis, faults, ...); `bounds`: a bounds "
        "file (its [defaults], or `case`), whose rows are added and whose fail levels `pass` includes; "
        "`out`: a folder for its tables, error images and meta.json, with the log-log plot "
        "error_vs_step.{png,pdf} if `plots=True` (`vrv verify --plots`); `alpha`: colour with an alpha "
        "channel is 'auto' (the default: straight where the file declares it, else premultiplied), 'premultiplied' or 'straight', as --alpha; `report`: a file for the "
        "verification as one self-contained HTML page, as --report");
}
