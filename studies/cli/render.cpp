// vrv render: one value per pixel of the scene's camera, by the reference integrator or by a
// discrete raycast, written as a float EXR plus an 8-bit PNG preview; optionally the signed
// error against another EXR.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include <fmt/format.h>

#include "lib/camera.h"
#include "lib/discrete_raycast.h"
#include "lib/io/image_io.h"
#include "lib/io/image_module.h"
#include "lib/util/parallel.h"
#include "lib/util/progress.h"
#include "lib/reference_integrator.h"
#include "studies/cli/cli_support.h"
#include "studies/cli/commands.h"
#include "studies/cli/discrete_options.h"

namespace vrv::cli {
namespace {

namespace fs = std::filesystem;

struct RenderOptions {
  std::string scene;
  bool reference = false;
  double tol = 1e-12;
  DiscreteOptions discrete;
  std::string output;
  std::string error_against;
  std::optional<int> width, height;
  int threads = 0;
  bool quiet = false;
  CLI::Option* tol_option = nullptr;
};

// The files written next to `-o out.exr` (the error pair only with --error-against).
struct OutputPaths {
  fs::path exr, png, error_exr, error_png;
  std::vector<fs::path> all(bool with_error) const {
    if (with_error) return {exr, png, error_exr, error_png};
    return {exr, png};
  }
};

OutputPaths output_paths(const std::string& output) {
  if (output.empty()) throw std::invalid_argument("-o: an output file (.exr) is required");
  const fs::path exr(output);
  std::string ext = exr.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".exr" || exr.stem().empty())
    throw std::invalid_argument(fmt::format("-o: '{}' must name an .exr file", output));
  const fs::path dir = exr.parent_path();
  const std::string stem = exr.stem().string();
  fs::path png = exr;
  png.replace_extension(".png");
  return {exr, png, dir / (stem + "_error.exr"), dir / (stem + "_error.png")};
}

// Fails now, not after the render, when an output cannot be written: creates and removes the
// temporary file the writers would use.  Every output is checked before any is written, so a
// render writes all its files or none.
void check_writable(const fs::path& file) {
  const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw std::invalid_argument(
        fmt::format("-o: {}: the directory {} does not exist", file.string(), dir.string()));
  if (fs::is_directory(file, ec))
    throw std::invalid_argument(fmt::format("-o: {}: is a directory", file.string()));
  if (fs::exists(file, ec) && !fs::is_regular_file(file, ec))
    throw std::invalid_argument(fmt::format("-o: {}: exists and is not a regular file", file.string()));
  fs::path probe = file;
  probe += ".tmp";
  if (fs::is_directory(probe, ec))
    throw std::invalid_argument(fmt::format("-o: {}: its temporary {} is a directory", file.string(),
                                            probe.string()));
  const bool existed = fs::exists(probe, ec);
  {
    std::ofstream out(probe, std::ios::app);
    if (!out)
      throw std::invalid_argument(
          fmt::format("-o: {}: cannot write into {}", file.string(), dir.string()));
  }
  if (!existed) fs::remove(probe, ec);
}

// The same file under two names (or one name): never overwrite the render's own input.
bool same_file(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

void check_outputs(const OutputPaths& out, const std::string& error_against) {
  const auto files = out.all(!error_against.empty());
  for (const fs::path& f : files) {
    if (!error_against.empty() && same_file(f, error_against))
      throw std::invalid_argument(fmt::format(
          "-o: {} would overwrite the --error-against input {}; choose another output name",
          f.string(), error_against));
    check_writable(f);
  }
}

Camera choose_camera(const Scene& scene, const RenderOptions& opt) {
  Camera camera;
  if (scene.camera) {
    camera = *scene.camera;
  } else {
    camera = default_camera(scene.box);
  }
  if (opt.width) camera.width = *opt.width;
  if (opt.height) camera.height = *opt.height;
  try {
    validate(camera);
  } catch (const CameraError& e) {
    if (e.field() == "width" && opt.width) throw std::invalid_argument("--width: " + e.reason());
    if (e.field() == "height" && opt.height) throw std::invalid_argument("--height: " + e.reason());
    throw std::invalid_argument(fmt::format("[camera]: {}", e.what()));
  }
  return camera;
}

struct Rendered {
  Image image;
  long work = 0;                  // field evaluations (reference) or samples (discrete)
  double max_error_estimate = 0;  // reference only
  long tolerance_missed = 0;      // reference pixels whose estimate exceeds --tol
  long not_finite = 0;            // pixels whose value is NaN or infinite as a float
  long first_not_finite = -1;     // the first such pixel (row-major index)
};

// Every pixel on TBB's threads, each writing its own slots; the sums run afterwards in pixel
// order, so the output is the same for any thread count.
template <class PerPixel>
Rendered render_pixels(const Camera& camera, bool quiet, PerPixel&& per_pixel) {
  Rendered r{Image(camera.width, camera.height)};
  const long pixels = static_cast<long>(camera.width) * camera.height;
  std::vector<long> work(pixels);
  std::vector<double> estimate(pixels);
  std::vector<char> met(pixels);
  Progress progress("render", pixels, !quiet);
  parallel_for_index(pixels, [&](long i) {
    const int x = static_cast<int>(i % camera.width), y = static_cast<int>(i / camera.width);
    const auto [value, w, e, m] = per_pixel(camera.ray(x, y));
    r.image.at(x, y) = static_cast<float>(value);
    work[i] = w;
    estimate[i] = e;
    met[i] = m;
    progress.advance();
  });
  progress.finish();
  for (long i = 0; i < pixels; ++i) {
    r.work += work[i];
    r.max_error_estimate = std::max(r.max_error_estimate, estimate[i]);
    if (!std::isfinite(r.image.pixels[i])) {
      if (r.not_finite++ == 0) r.first_not_finite = i;
    } else if (!met[i]) {
      ++r.tolerance_missed;
    }
  }
  return r;
}

struct PixelResult {
  double value;
  long work;
  double estimate;
  bool tolerance_met;
};

Rendered render_reference(const Scene& scene, const Camera& camera, double tol, bool quiet) {
  return visit_field(scene, [&](const auto& field) {
    return render_pixels(camera, quiet, [&](const Ray& ray) {
      const ReferenceResult v =
          integrate_reference(field, scene.box, scene.transfer, scene.background, ray, {tol});
      return PixelResult{v.value, v.evaluations, v.error_estimate, v.tolerance_met};
    });
  });
}

Rendered render_discrete(const Scene& scene, const Camera& camera, const DiscreteConfig& config,
                         bool quiet) {
  return visit_field(scene, [&](const auto& field) {
    using F = std::decay_t<decltype(field)>;
    const DiscreteRaycaster<F> caster(field, scene.box, scene.transfer, scene.background, config);
    return render_pixels(camera, quiet, [&](const Ray& ray) {
      const DiscreteResult v = caster.cast(ray);
      return PixelResult{v.value, v.samples, 0.0, true};
    });
  });
}

Image read_reference_image(const std::string& path, const Camera& camera) {
  Image ref;
  try {
    ref = read_exr(path);
  } catch (const std::exception& e) {
    throw std::invalid_argument(fmt::format("--error-against: {}", e.what()));
  }
  if (ref.width != camera.width || ref.height != camera.height)
    throw std::invalid_argument(fmt::format(
        "--error-against: {}: size {} x {} differs from the render's {} x {}", path, ref.width,
        ref.height, camera.width, camera.height));
  for (int y = 0; y < ref.height; ++y)
    for (int x = 0; x < ref.width; ++x)
      if (!std::isfinite(ref.at(x, y)))
        throw std::invalid_argument(fmt::format("--error-against: {}: pixel ({}, {}) is {}", path,
                                                x, y, ref.at(x, y)));
  return ref;
}

struct ErrorStats {
  double max_abs = 0, mean_abs = 0, rms = 0;
};

// this - ref, pixel by pixel, from the float values as stored in the two EXR files (so that
// out_error.exr equals out.exr - REF.exr up to the float rounding of the difference).
ErrorStats error_image(const Image& image, const Image& ref, Image& error) {
  error = Image(image.width, image.height);
  ErrorStats s;
  double sum_abs = 0, sum_sq = 0;
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    const double e = static_cast<double>(image.pixels[i]) - ref.pixels[i];
    error.pixels[i] = static_cast<float>(e);
    s.max_abs = std::max(s.max_abs, std::abs(e));
    sum_abs += std::abs(e);
    sum_sq += e * e;
  }
  const double n = static_cast<double>(image.pixels.size());
  s.mean_abs = sum_abs / n;
  s.rms = std::sqrt(sum_sq / n);
  return s;
}

void run_render(const RenderOptions& opt) {
  const OutputPaths out = output_paths(opt.output);
  const bool discrete_asked = !opt.discrete.method.empty();
  if (opt.reference && discrete_asked)
    throw std::invalid_argument("--reference: give --reference or --method, not both");
  if (!opt.reference && !discrete_asked)
    throw std::invalid_argument("--reference or --method is required (what should render the image?)");
  if (discrete_asked && opt.tol_option && opt.tol_option->count() > 0)
    throw std::invalid_argument("--tol: applies to --reference only");
  check_tolerance(opt.tol);
  check_threads(opt.threads);
  const Scene scene = load_scene_or_default(opt.scene);
  const auto discrete = discrete_config(opt.discrete, scene);
  const Camera camera = choose_camera(scene, opt);
  check_outputs(out, opt.error_against);
  image_module::functions();  // a missing image module fails now, not after the render
  std::optional<Image> ref;
  if (!opt.error_against.empty()) ref = read_reference_image(opt.error_against, camera);
  if (discrete)
    check_work(opt.discrete, *discrete, scene, static_cast<long>(camera.width) * camera.height,
               [&](long i) {
                 return camera.ray(static_cast<int>(i % camera.width), static_cast<int>(i / camera.width));
               });

  if (!scene.camera)
    std::cerr << fmt::format(
        "vrv render: the scene has no [camera]; using the default camera (perspective, fov {:g}, "
        "eye [{:g}, {:g}, {:g}] looking at the box centre)\n",
        camera.fov_degrees, camera.eye[0], camera.eye[1], camera.eye[2]);
  const long pixels = static_cast<long>(camera.width) * camera.height;
  const auto start = std::chrono::steady_clock::now();
  const ThreadLimit threads(opt.threads);
  const Rendered r = discrete ? render_discrete(scene, camera, *discrete, opt.quiet)
                              : render_reference(scene, camera, opt.tol, opt.quiet);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (r.not_finite > 0)
    throw CommandFailed(kExitNotFinite, fmt::format(
        "vrv: error: {} of {} pixels are NaN or infinite (the first at x = {}, y = {}); nothing "
        "written{}", r.not_finite, pixels, r.first_not_finite % camera.width,
        r.first_not_finite / camera.width,
        discrete ? " (check --precision and the transfer function's range)" : ""));
  std::cerr << fmt::format("vrv render: {} pixels ({} x {}, {} camera, {}) in {:.3f} s\n", pixels,
                           camera.width, camera.height, to_string(camera.projection),
                           discrete ? "--method " + opt.discrete.method : std::string("reference"),
                           seconds);


  write_exr(r.image, out.exr);
  const float max_value = *std::max_element(r.image.pixels.begin(), r.image.pixels.end());
  write_png_preview(r.image, out.png, 0, max_value > 0 ? max_value : 1);

  nlohmann::ordered_json j;
  j["output"] = out.exr.string();
  j["preview"] = out.png.string();
  j["width"] = camera.width;
  j["height"] = camera.height;
  j["method"] = discrete ? opt.discrete.method : "reference";
  j["max_value"] = max_value;
  if (discrete) j["samples"] = r.work;
  else {
    j["evaluations"] = r.work;
    j["max_error_estimate"] = r.max_error_estimate;
    j["tolerance_missed"] = r.tolerance_missed;
  }
  if (ref) {
    Image error;
    const ErrorStats s = error_image(r.image, *ref, error);
    write_exr(error, out.error_exr);
    write_error_map_png(error, out.error_png, s.max_abs);
    std::cerr << fmt::format("vrv render: error against {}: max |e| {:.6g}, mean |e| {:.6g}, RMS {:.6g}\n",
                             opt.error_against, s.max_abs, s.mean_abs, s.rms);
    j["error_against"] = opt.error_against;
    j["error_output"] = out.error_exr.string();
    j["error_preview"] = out.error_png.string();
    j["max_abs_error"] = s.max_abs;
    j["mean_abs_error"] = s.mean_abs;
    j["rms_error"] = s.rms;
  }
  std::cout << j.dump() << '\n' << std::flush;
  if (r.tolerance_missed > 0)
    throw CommandFailed(kExitToleranceMissed, fmt::format(
        "vrv render: {} of {} pixels missed --tol {:g} (largest error estimate {:.3g}); images "
        "written", r.tolerance_missed, pixels, opt.tol, r.max_error_estimate));
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto opt = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand(
      "render", "Render the scene's camera to a float EXR (and a PNG preview) by the reference "
                "integrator or a discrete raycast");
  cmd->footer(
      "Camera: the scene's [camera] table; without one, a perspective camera (vertical fov 40 "
      "degrees, 256 x 256, up +y) looking along +z at the box centre from 2.5 box diagonals "
      "away.\n"
      "Writes OUT.exr (one float channel) and OUT.png (8-bit grey, 0 to the image maximum); with "
      "--error-against REF.exr also OUT_error.exr (this - REF, signed float) and OUT_error.png "
      "(blue < 0 < red, symmetric range +-max|e|, colour bar on the right).\n"
      "stdout: one JSON line; stderr: pixel count, time and error statistics.\n"
      "Exit: 0; 2 bad input (nothing written); 3 reference pixels missed --tol (images written, "
      "count on stderr and as \"tolerance_missed\"); 4 NaN or infinite pixels (nothing written).");
  cmd->add_option("--scene", opt->scene, "Scene file (TOML); the embedded default when omitted");
  cmd->add_flag("--reference", opt->reference, "Render with the reference integrator");
  opt->tol_option =
      cmd->add_option("--tol", opt->tol, "Absolute tolerance on I per pixel (--reference)")
          ->capture_default_str();
  add_discrete_options(*cmd, opt->discrete);
  cmd->add_option("-o,--output", opt->output, "Output image, OUT.exr");
  cmd->add_option("--error-against", opt->error_against,
                  "Reference EXR of the same size: also write OUT_error.exr/.png and print error statistics");
  cmd->add_option("--width", opt->width, "Override the camera's width (pixels; rays of a fan)");
  cmd->add_option("--height", opt->height, "Override the camera's height (pixels; 1 for a fan)");
  cmd->add_option("--threads", opt->threads, "Threads (default: all cores); results do not depend on it");
  cmd->add_flag("--quiet", opt->quiet, "No progress bar on stderr");
  cmd->callback([opt] { run_render(*opt); });
}

}  // namespace vrv::cli
