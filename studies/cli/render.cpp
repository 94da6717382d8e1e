// vrv render: one value per pixel of the scene's camera, by the reference integrator or by a
// discrete raycast, written as a float EXR plus an 8-bit PNG preview; optionally the signed
// error against another EXR.
#include <algorithm>
#include <array>
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
#include "lib/discrete_channels.h"
#include "lib/discrete_raycast.h"
#include "lib/image_loop.h"
#include "lib/io/image_io.h"
#include "lib/io/image_module.h"
#include "lib/io/output_paths.h"
#include "lib/util/parallel.h"
#include "lib/util/progress.h"
#include "lib/util/ranks.h"
#include "lib/metrics.h"
#include "lib/reference_pixels.h"
#include "lib/scene_hash.h"
#include "lib/vrv.h"
#include "lib/study_file.h"
#include "studies/cli/cli_support.h"
#include "studies/cli/commands.h"
#include "studies/cli/memory_limit.h"
#include "studies/cli/discrete_flags.h"
#include "studies/cli/projection_options.h"
#include "lib/scene_mode.h"
#include "lib/projection/projection_reference.h"

namespace vrv::cli {
namespace {

namespace fs = std::filesystem;

struct RenderOptions {
  std::string scene;
  bool reference = false;
  std::string mode;  // --mode: a projection instead of emission-absorption
  double tol = ReferenceOptions{}.tol;
  DiscreteOptions discrete;
  std::string output;
  std::string error_against;
  std::optional<int> width, height;
  int threads = 0;
  bool quiet = false;
  bool alpha = false;  // --alpha: A = 1 - e^-Phi after the colour channels
  std::optional<double> max_memory_gib;  // not given: default_memory_limit(), as vrv study
  CLI::Option* tol_option = nullptr;
};

// The files written next to `-o out.exr` (f64: the same values in double, OUT.f64.tiff; the
// error pair only with --error-against).
struct OutputPaths {
  fs::path exr, png, error_exr, error_png, f64;
  std::vector<fs::path> all(bool with_error) const {
    if (with_error) return {exr, png, f64, error_exr, error_png};
    return {exr, png, f64};
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
  return {exr, png, dir / (stem + "_error.exr"), dir / (stem + "_error.png"), dir / (stem + ".f64.tiff")};
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

// The double image beside a reference EXR (REF.f64.tiff next to REF.exr), if there is one.
fs::path double_sibling(const fs::path& exr) {
  fs::path f64 = exr;
  f64.replace_extension(".f64.tiff");
  return f64;
}

// Every output writable and none of them the reference being read (or the double beside it).
void check_outputs(const OutputPaths& out, const std::string& error_against) {
  for (const fs::path& f : out.all(!error_against.empty())) {
    if (!error_against.empty())
      for (const fs::path& input : {fs::path(error_against), double_sibling(error_against)})
        if (same_file(f, input))
          throw std::invalid_argument(fmt::format(
              "-o: {} would overwrite the --error-against input {}; choose another output name",
              f.string(), input.string()));
    check_writable(f);
  }
}

// The render's memory before anything is allocated: per pixel, the image in double and, as it is
// written, in float (12 bytes a channel), each pixel's work, estimate and verdict (17; grey: 29 bytes; 1024^2 ->
// 2048^2 pixels took 157 -> 246 MB resident, 29 bytes a pixel), and with --error-against the
// reference in double and the error image (12 more a channel).  Refused above --max-memory naming
// the input that sets the size.
struct Rendered {
  ImageF64 image;                 // in double: the .f64.tiff; the EXR and the preview round it to float
  long work = 0;                  // field evaluations (reference) or samples (discrete)
  double max_error_estimate = 0;  // reference only
  long tolerance_missed = 0;      // reference pixels whose estimate exceeds --tol
  long not_finite = 0;            // pixels whose value (as a float) or error estimate is NaN or infinite
  long first_not_finite = -1;     // the first such pixel (row-major index)
};

struct PixelResult {
  std::array<double, 4> value;  // the first `channels` of the render
  long work;
  double estimate;  // the largest of the channels'
  bool tolerance_met;  // by every channel
};

void check_render_memory(const RenderOptions& opt, const Camera& camera, int channels) {
  const double pixels = double(camera.width) * camera.height;
  // Under MPI each rank also holds every pixel's value as the image loop exchanges it.
  const std::size_t exchanged = !opt.reference ? std::max(sizeof(ChannelsDiscreteResult), sizeof(PixelResult))
                                               : std::max(sizeof(ReferenceResult), sizeof(PixelResult));
  const double per_pixel = 17 + channels * (12 + (opt.error_against.empty() ? 0 : 12)) +
                           (rank_count() > 1 ? double(exchanged) : 0.0);
  const std::string who = opt.width || opt.height ? std::string("--width/--height")
                          : opt.scene.empty()     ? std::string("<default scene>: camera")
                                                  : opt.scene + ": camera";
  check_memory(pixels * per_pixel, memory_limit_bytes(opt.max_memory_gib), who, "render",
               fmt::format("{} x {} pixels, {:g} bytes each", camera.width, camera.height, per_pixel));
}

// The pixels as the image loop puts them, each part in its own plane (the 29 bytes a pixel of
// check_render_memory); the sums run afterwards in pixel order, so the output is the same for
// any thread count.
class PixelPlanes {
 public:
  PixelPlanes(const Camera& camera, int channels)
      : r_{ImageF64(camera.width, camera.height, 0.0, channels)},
        channels_(channels), work_(pixel_count(camera)), estimate_(work_.size()), met_(work_.size()) {}
  void put(long i, const PixelResult& p) {
    for (int c = 0; c < channels_; ++c) r_.image.value(i, c) = p.value[c];
    work_[i] = p.work;
    estimate_[i] = p.estimate;
    met_[i] = p.tolerance_met;
  }
  Rendered finish() {
    for (std::size_t i = 0; i < work_.size(); ++i) {
      r_.work += work_[i];
      r_.max_error_estimate = std::max(r_.max_error_estimate, estimate_[i]);
      const auto first = r_.image.pixels.begin() + static_cast<long>(i) * channels_;
      // A NaN estimate is as wrong as a NaN value (std::max would drop it from the largest).
      if (!std::isfinite(estimate_[i]) ||
          !std::all_of(first, first + channels_, [](double v) { return std::isfinite(static_cast<float>(v)); })) {
        if (r_.not_finite++ == 0) r_.first_not_finite = static_cast<long>(i);
      } else if (!met_[i]) {
        ++r_.tolerance_missed;
      }
    }
    return std::move(r_);
  }

 private:
  Rendered r_;
  int channels_;
  std::vector<long> work_;
  std::vector<double> estimate_;
  std::vector<char> met_;
};

// A progress bar the image loop advances block by block.
ImageLoopHooks progress_hooks(Progress& bar) {
  ImageLoopHooks hooks;
  hooks.progress = [&bar](long done) { bar.advance(done); };
  return hooks;
}

// A pixel of several channels (ImageChannels, alpha already A).
PixelResult channels_pixel(const ChannelsReferenceResult& v) {
  PixelResult p{{}, v.evaluations, 0.0, v.tolerance_met()};
  for (int c = 0; c < v.count; ++c) {
    p.value[c] = v.channel[c].value;
    p.estimate = std::max(p.estimate, v.channel[c].error_estimate);
  }
  return p;
}

Rendered render_reference(const Scene& scene, const Camera& camera, double tol, bool quiet, bool alpha) {
  const ImageChannels channels(scene, alpha);
  PixelPlanes planes(camera, channels.count());
  Progress bar("render", pixel_count(camera), !quiet);
  const auto put = [&](long i, const PixelResult& p) { planes.put(i, p); };
  if (channels.count() > 1) {
    // Each pixel's channels are reduced to a PixelResult on the rank that casts it.
    image_channel_pixels(scene, camera, channels, {tol}, channels_pixel, put, progress_hooks(bar));
  } else {
    reference_pixels(scene, camera, {tol}, [&](long i, const ReferenceResult& v) {
      put(i, {{v.value}, v.evaluations, v.error_estimate, v.tolerance_met});
    }, progress_hooks(bar));
  }
  bar.finish();
  return planes.finish();
}

// Each channel cast alone (lib/discrete_channels.h).
Rendered render_discrete(const Scene& scene, const Camera& camera, const DiscreteConfig& config,
                         bool quiet, bool alpha) {
  PixelPlanes planes(camera, scene.channel_count() + (alpha ? 1 : 0));
  Progress bar("render", pixel_count(camera), !quiet);
  discrete_channel_pixels(scene, camera, config, [&](long i, const ChannelsDiscreteResult& r) {
    planes.put(i, {r.value, r.samples, 0.0, true});
  }, progress_hooks(bar), {}, alpha);
  bar.finish();
  return planes.finish();
}

// A projection (--mode) per pixel: its reference, or its discrete version with --method.
Rendered render_projection(const Scene& scene, const Camera& camera, const ProjectionSetup& p, double tol,
                           bool quiet) {
  PixelPlanes planes(camera, 1);
  Progress bar("render", pixel_count(camera), !quiet);
  visit_field(scene, [&](const auto& field) {
    image_loop_into(camera, {}, [&](const Ray& ray) {
      if (p.discrete) {
        const DiscreteProjectionResult v = discrete_projection(field, scene.box, scene.transfer, ray, *p.discrete);
        return PixelResult{{v.value}, v.samples, 0.0, true};
      }
      const ProjectionResult v = projection_reference(field, scene.box, scene.transfer, ray, p.mode, {tol});
      return PixelResult{{v.value}, v.evaluations, v.error_estimate, v.tolerance_met};
    }, [&](long i, const PixelResult& px) { planes.put(i, px); }, progress_hooks(bar));
  });
  bar.finish();
  return planes.finish();
}

// A reference a verification can trust: floating point (an 8-bit preview is refused), the render's
// size, of this scene and camera by its provenance, every pixel finite; read in double from
// REF.f64.tiff, which vrv render writes beside REF.exr: a REF.f64.tiff of another render (a stale
// half of the pair) is refused rather than passed over for the EXR's float values.
ImageF64 read_reference_image(const std::string& path, const Camera& camera, const std::string& hash,
                              int channels) {
  auto bad = [&](const std::string& reason) {
    return std::invalid_argument(fmt::format("--error-against: {}: {}", path, reason));
  };
  ImageF64 ref;
  std::optional<ImageProvenance> provenance;
  fs::path source = path;
  try {
    const ImageInfo info = read_image_info(path);
    if (!info.floating)
      throw bad(fmt::format("{}-bit {} pixels ({}): a reference must be floating point (the .exr "
                            "or .f64.tiff of vrv render, not its preview)", info.bits, info.pixel_type, info.format));
    provenance = read_provenance(path);
    std::error_code ec;
    const fs::path f64 = double_sibling(path);
    if (fs::path(path).extension() == ".exr" && fs::exists(f64, ec)) {
      const auto p64 = read_provenance(f64);
      if (provenance && !(p64 && p64->scene_hash == provenance->scene_hash && p64->camera == provenance->camera &&
                          p64->method == provenance->method))
        throw bad(fmt::format("{} beside it is not the same render ({}; the EXR: {}), so one of the pair is stale: "
                              "render the reference again or remove it", f64.filename().string(),
                              p64 ? p64->method + " scene " + p64->scene_hash.substr(0, 12) : "no vrv provenance",
                              provenance->method + " scene " + provenance->scene_hash.substr(0, 12)));
      source = f64;
    }
    ref = read_image_f64(source, 4);
  } catch (const std::invalid_argument&) {
    throw;
  } catch (const std::exception& e) {
    throw std::invalid_argument(fmt::format("--error-against: {}", e.what()));
  }
  if (ref.width != camera.width || ref.height != camera.height)
    throw bad(fmt::format("size {} x {} differs from the render's {} x {}", ref.width, ref.height,
                          camera.width, camera.height));
  if (ref.channels != channels)
    throw bad(fmt::format("{} channel{} where the render has {} ({})", ref.channels, ref.channels == 1 ? "" : "s",
                          channels, std::array{"grey", "grey and alpha", "RGB", "RGBA"}[channels - 1]));
  if (!provenance)
    throw bad("carries no vrv provenance (scene hash, camera), so it cannot be checked against this "
              "scene and camera; render the reference with this version of vrv render");
  if (provenance->scene_hash != hash) {
    const std::string here = camera_description(camera);
    if (provenance->camera != here)
      throw bad(fmt::format("rendered with another camera ({}; this render: {})", provenance->camera, here));
    throw bad(fmt::format("rendered from another scene (scene hash {}; this render's {})",
                          provenance->scene_hash.substr(0, 12), hash.substr(0, 12)));
  }
  // Errors are measured against the reference integral: a discrete render in its place would
  // report the difference of two raycasts as an error.
  if (provenance->method.find("reference") == std::string::npos)
    throw bad(fmt::format("a discrete render ({}), not a reference: render the reference with vrv render --reference",
                          provenance->method));
  for (std::size_t i = 0; i < ref.pixels.size(); ++i) {
    const double v = ref.pixels[i];
    const std::size_t pixel = i / channels;
    if (!std::isfinite(v))
      throw bad(fmt::format("pixel ({}, {}){} is {}", pixel % ref.width, pixel / ref.width,
                            channels > 1 ? fmt::format(" channel {}", channel_names(channels)[i % channels]) : std::string(), v));
  }
  return ref;
}

// Scene hash, camera, method and step, for the images' metadata.
ImageProvenance render_provenance(const Scene& scene, const Camera& camera,
                                  const std::optional<DiscreteConfig>& discrete, double tol) {
  ImageProvenance p{scene_hash(scene, camera), camera_description(camera), "", std::nullopt};
  if (!discrete) {
    p.method = fmt::format("reference tol={:g}", tol);
    return p;
  }
  StudyMethodSpec spec;
  spec.config = *discrete;
  p.method = method_label(spec);
  if (step_based(discrete->sampling.strategy)) p.step = discrete->sampling.step;
  return p;
}

// this - ref, pixel by pixel and channel by channel, in double (the reference from its .f64.tiff
// when there is one, so errors below a float ulp are measured); out_error.exr holds them rounded
// to float.  The statistics of all channels' errors together (so max |e| is the largest over the
// channels), then of each channel (RGB).
std::vector<ErrorStats> error_image(const ImageF64& image, const ImageF64& ref, Image& error) {
  error = Image(image.width, image.height, 0, image.channels);
  std::vector<ErrorSums> sums(image.channels == 1 ? 1 : 1 + image.channels);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    const double e = image.pixels[i] - ref.pixels[i];
    error.pixels[i] = static_cast<float>(e);
    sums[0].add(e);
    if (image.channels > 1) sums[1 + i % image.channels].add(e);
  }
  std::vector<ErrorStats> stats;
  for (const ErrorSums& s : sums) stats.push_back(s.stats());
  return stats;
}

// The colour channels of an image whose last channel is alpha (the PNG preview: PNG's alpha is
// straight, vrv's colour is premultiplied, so the preview shows the colour over black).
Image without_alpha(const Image& image) {
  Image out(image.width, image.height, 0, image.channels - 1);
  for (std::size_t p = 0; p < out.pixels.size() / out.channels; ++p)
    for (int c = 0; c < out.channels; ++c) out.pixels[p * out.channels + c] = image.pixels[p * image.channels + c];
  return out;
}

// The error map's one value a pixel: the channel error of largest magnitude, sign kept.
Image largest_channel_error(const Image& error) {
  if (error.channels == 1) return error;
  Image out(error.width, error.height);
  for (std::size_t p = 0; p < out.pixels.size(); ++p)
    for (int c = 0; c < error.channels; ++c) {
      const float e = error.pixels[p * error.channels + c];
      if (std::fabs(e) > std::fabs(out.pixels[p]) || std::isnan(e)) out.pixels[p] = e;
    }
  return out;
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
  const Scene scene = load_scene_or_default(opt.scene, memory_limit_bytes(opt.max_memory_gib));
  const auto projection = projection_setup(chosen_mode(opt.mode, scene_text_or_default(opt.scene)), opt.discrete, scene);
  if (projection && opt.alpha)
    throw std::invalid_argument(fmt::format("--alpha: {}: a projection's image has one channel",
                                            projection_mode_name(projection->mode)));
  if (projection && scene.color)
    throw std::invalid_argument(fmt::format("--mode: {}: the scene is RGB, and projections take one channel so far",
                                            projection_mode_name(projection->mode)));
  // A projection's work is estimated as the emission-absorption cast's of the same sampling.
  const auto discrete = projection ? projection->work : discrete_config(opt.discrete, scene);
  const Camera camera = scene_camera(scene, opt.width, opt.height);  // --width/--height errors named
  check_render_memory(opt, camera, scene.channel_count() + (opt.alpha ? 1 : 0));
  ImageProvenance provenance = render_provenance(scene, camera, discrete, opt.tol);
  if (opt.alpha) provenance.method += " alpha";  // the colour over nothing, A last
  if (projection) {
    // The mode is part of what the image is: --error-against refuses an image of another mode.
    const std::string_view mode = projection_mode_name(projection->mode);
    provenance.scene_hash = fmt::format("{}:{}", mode, provenance.scene_hash);
    provenance.method = projection->discrete
                            ? fmt::format("{} {} strategy={}", mode, opt.discrete.method,
                                          strategy_name(projection->discrete->sampling.strategy))
                            : fmt::format("{} reference tol={:g}", mode, opt.tol);
  }
  // Under MPI (lib/util/ranks.h) every rank renders its share of the pixels and ends with the
  // whole image; rank 0 alone checks the outputs, reads --error-against and writes.
  if (is_output_rank()) check_outputs(out, opt.error_against);
  // The image module loads beside the render (a missing one fails now, not after it).
  parallel_for_index(64, [](long) {});  // TBB's workers first: dlopen's lock would stall their start
  std::optional<image_module::BackgroundLoad> image_io;  // rank 0 alone writes images
  if (is_output_rank()) image_io.emplace();
  std::optional<ImageF64> ref;
  if (!opt.error_against.empty() && is_output_rank())
    ref = read_reference_image(opt.error_against, camera, provenance.scene_hash,
                               scene.channel_count() + (opt.alpha ? 1 : 0));
  check_work(opt.discrete, discrete, opt.tol, scene, pixel_count(camera),
             [&](long i) { return pixel_ray(camera, i); });

  if (!scene.camera)
    std::cerr << fmt::format(
        "vrv render: the scene has no [camera]; using the default camera (perspective, fov {:g}, "
        "eye [{:g}, {:g}, {:g}] looking at the box centre)\n",
        camera.fov_degrees, camera.eye[0], camera.eye[1], camera.eye[2]);
  const long pixels = static_cast<long>(camera.width) * camera.height;
  const auto start = std::chrono::steady_clock::now();
  const ThreadLimit threads(opt.threads);
  const Rendered r = [&] {
    const PixelSharing sharing;  // the pixel loop alone is dealt to MPI ranks
    return projection ? render_projection(scene, camera, *projection, opt.tol, opt.quiet)
           : discrete ? render_discrete(scene, camera, *discrete, opt.quiet, opt.alpha)
                      : render_reference(scene, camera, opt.tol, opt.quiet, opt.alpha);
  }();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (r.not_finite > 0)
    throw CommandFailed(kExitNotFinite, fmt::format(
        "vrv: error: {} of {} pixels are NaN or infinite in value or error estimate (the first at x = {}, y = {}); nothing "
        "written{}", r.not_finite, pixels, r.first_not_finite % camera.width,
        r.first_not_finite / camera.width,
        discrete ? " (check --precision and the transfer function's range)" : ""));
  std::cerr << fmt::format("vrv render: {} pixels ({} x {}, {} camera, {}) in {:.3f} s\n", pixels,
                           camera.width, camera.height, to_string(camera.projection),
                           discrete ? "--method " + opt.discrete.method : std::string("reference"),
                           seconds);

  if (!is_output_rank()) return;
  image_io->wait();
  const Image image = to_float(r.image);
  write_exr(image, out.exr, &provenance);
  write_tiff_f64(r.image, out.f64, &provenance);
  std::optional<Image> stripped;
  if (opt.alpha) stripped = without_alpha(image);
  const Image& colour = stripped ? *stripped : image;
  const float max_value = *std::max_element(colour.pixels.begin(), colour.pixels.end());
  write_png_preview(colour, out.png, 0, max_value > 0 ? max_value : 1, &provenance);

  nlohmann::ordered_json j;
  j["output"] = out.exr.string();
  j["preview"] = out.png.string();
  j["output_f64"] = out.f64.string();
  // The scene and camera hashed together, named as export.json names the same hash.
  j["scene_camera_hash"] = provenance.scene_hash;
  j["seconds"] = seconds;  // the pixels alone, as stderr says (there to 1 ms): for benchmarks
  j["width"] = camera.width;
  j["height"] = camera.height;
  if (projection) j["mode"] = projection_mode_name(projection->mode);
  j["method"] = discrete ? opt.discrete.method : "reference";
  if (opt.alpha) j["alpha"] = true;  // the colour over nothing, A last
  j["max_value"] = max_value;
  if (discrete) j["samples"] = r.work;
  else {
    j["evaluations"] = r.work;
    j["max_error_estimate"] = r.max_error_estimate;
    j["tolerance_missed"] = r.tolerance_missed;
  }
  if (ref) {
    Image error;
    const std::vector<ErrorStats> stats = error_image(r.image, *ref, error);
    const ErrorStats& s = stats[0];
    write_exr(error, out.error_exr);
    write_error_map_png(largest_channel_error(error), out.error_png, s.max);
    std::cerr << fmt::format("vrv render: error against {}: max |e| {:.6g}, mean |e| {:.6g}, RMS {:.6g}{}\n",
                             opt.error_against, s.max, s.mean, s.rms, stats.size() > 1 ? " (all channels)" : "");
    j["error_against"] = opt.error_against;
    j["error_output"] = out.error_exr.string();
    j["error_preview"] = out.error_png.string();
    j["max_abs_error"] = s.max;
    j["mean_abs_error"] = s.mean;
    j["rms_error"] = s.rms;
    for (std::size_t c = 1; c < stats.size(); ++c) {
      const std::string name = channel_names(r.image.channels)[c - 1];
      std::cerr << fmt::format("vrv render:   channel {}: max |e| {:.6g}, mean |e| {:.6g}, RMS {:.6g}\n", name,
                               stats[c].max, stats[c].mean, stats[c].rms);
      j["channels"][name] = {{"max_abs_error", stats[c].max}, {"mean_abs_error", stats[c].mean}, {"rms_error", stats[c].rms}};
    }
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
      "Writes OUT.exr (float: one channel Y, or R, G, B for an RGB scene; with --alpha also A = 1 - e^-Phi, the colour then "
      "rendered over nothing: premultiplied, as EXR expects), OUT.f64.tiff (the same in "
      "double, bit for bit) and OUT.png (8-bit, 0 to the image maximum), each carrying its provenance (scene hash, camera, "
      "method, step) in its metadata; with "
      "--error-against REF.exr also OUT_error.exr (this - REF, signed float, per channel) and OUT_error.png "
      "(blue < 0 < red, symmetric range +-max|e|, colour bar on the right; RGB: the channel error of "
      "largest magnitude), with statistics over all channels and per channel.\n"
      "stdout: one JSON line; stderr: pixel count, time and error statistics.\n"
      "MPI: in a build with -DVRV_WITH_MPI=ON, `mpirun -np P vrv render ...` spreads the pixels over P "
      "ranks; every output is bitwise that of one process (docs/distributed.md).\n"
      "Exit: 0; 2 bad input (nothing written); 3 reference pixels missed --tol (images written, "
      "count on stderr and as \"tolerance_missed\"); 4 NaN or infinite pixels or error estimates (nothing written).");
  cmd->add_option("--scene", opt->scene, "Scene file (TOML); the embedded default when omitted");
  cmd->add_flag("--reference", opt->reference, "Render with the reference integrator");
  opt->tol_option =
      add_shared_option(*cmd, Option::tol, opt->tol, "(--reference)")
          ->capture_default_str();
  add_discrete_options(*cmd, opt->discrete);
  add_mode_option(*cmd, opt->mode);
  cmd->add_option("-o,--output", opt->output, "Output image, OUT.exr");
  cmd->add_option("--error-against", opt->error_against,
                  "Reference EXR of the same scene and camera (checked by its provenance; its .f64.tiff is "
                  "used when beside it): also write OUT_error.exr/.png and print error statistics in double");
  add_shared_option(*cmd, Option::width, opt->width);
  add_shared_option(*cmd, Option::height, opt->height);
  cmd->add_option("--threads", opt->threads, "Threads (default: all cores); results do not depend on it");
  cmd->add_flag("--quiet", opt->quiet, "No progress bar on stderr");
  cmd->add_flag("--alpha", opt->alpha,
                "Add an alpha channel A = 1 - e^-Phi (the opacity the ray accumulates; the discrete raycast's "
                "1 - its transmittance through the same samples) after Y or R, G, B, and render the colour over "
                "nothing (premultiplied: over the scene's background it is C + I0 (1 - A)); the PNG preview "
                "shows the colour");
  cmd->add_option("--max-memory", opt->max_memory_gib,
                  "GiB the render may take, estimated from the camera before anything is allocated "
                  "(default: 3/4 of physical memory)");
  cmd->callback([opt] { run_render(*opt); });
}

}  // namespace vrv::cli
