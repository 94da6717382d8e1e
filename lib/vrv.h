#pragma once
// vrv as a library: the one header a renderer's tests include (installed as <vrv/vrv.h>).
//
//   #include <vrv/vrv.h>
//   const vrv::Scene scene = vrv::load_scene("scene.toml");       // or parse_scene(text, name),
//                                                                   // or vrv::default_scene()
//   const auto ref = vrv::render_reference_image(scene, vrv::scene_camera(scene));
//   const auto mine = my_renderer(scene, 0.01);                    // your image, same camera
//
// Every number here is the one the command line gives: reference_values() on a ray is bitwise
// `vrv ray --json` on it; render_reference_image() and render_discrete_image() are `vrv render`
// before its float EXR.  Batches run in parallel (TBB); each ray writes its own slot, so results do not
// depend on the thread count.  Bad input throws: SceneFileError (file and key) from the
// scene loaders, std::invalid_argument (option and reason) for a bad ray, camera or
// DiscreteConfig, with the one-line messages the command line prints.
#include <functional>
#include <optional>
#include <span>
#include <vector>

#include "lib/camera.h"
#include "lib/discrete_channels.h"
#include "lib/discrete_error_bound.h"
#include "lib/discrete_raycast.h"
#include "lib/reference_channels.h"
#include "lib/gate.h"
#include "lib/geometry.h"
#include "lib/io/image_io.h"
#include "lib/projection/discrete_projection.h"
#include "lib/projection/projection_reference.h"
#include "lib/reference_integrator.h"
#include "lib/scene.h"
#include "lib/bounds_file.h"
#include "lib/scene_file.h"
#include "lib/verify.h"

namespace vrv {

// The camera `vrv render` uses for the scene: its [camera] table, else default_camera(box),
// with the width and height overridden when given.  Throws std::invalid_argument with the
// command line's message ("--width: ...", "[camera]: camera.fov: ...") when it is invalid.
Camera scene_camera(const Scene& scene, std::optional<int> width = std::nullopt,
                    std::optional<int> height = std::nullopt);


// The ray through every pixel, row-major from the top-left (index y * width + x): the rays
// render_reference_image() and render_discrete_image() cast.  Throws CameraError (invalid camera).
std::vector<Ray> camera_rays(const Camera& camera);

// The reference along each ray (ReferenceOptions::tol is absolute on I; validated).
std::vector<ReferenceResult> reference_values(const Scene& scene, std::span<const Ray> rays,
                                              const ReferenceOptions& options = {});
// The same into caller-owned storage (out.size() == rays.size()), e.g. a numpy array's rows.
void reference_values(const Scene& scene, std::span<const Ray> rays,
                      const ReferenceOptions& options, std::span<ReferenceResult> out);
// The functions here take grey scenes and throw std::invalid_argument for an RGB one (Scene::color,
// docs/color.md) but this: the three channels' references along each ray, one set of panels for
// all three.  Throws std::invalid_argument for a grey scene.  A discrete cast of an RGB scene is
// discrete_channel_values() or discrete_channel_image() (lib/discrete_channels.h): each channel
// cast alone, as vrv render does.
std::vector<ChannelsReferenceResult> color_reference_values(const Scene& scene, std::span<const Ray> rays,
                                                            const ReferenceOptions& options = {});
// Every channel of the scene's image along each ray, one set of panels for all of them: grey or
// RGB, and with `alpha` one more, last, A = 1 - e^-Phi within its estimate, the colour then over
// nothing (lib/reference_channels.h ImageChannels, integrate_image_channels).  Any scene.
std::vector<ChannelsReferenceResult> channel_reference_values(const Scene& scene, std::span<const Ray> rays,
                                                              const ReferenceOptions& options, bool alpha);

// The discrete raycast `config` describes along each ray.  Throws std::invalid_argument
// (naming the option) when validate(config, grid field) refuses it.  As on the command line,
// rate-based strategies count voxels of config.sampling.dims: set it to scene.dims.
std::vector<DiscreteResult> discrete_values(const Scene& scene, std::span<const Ray> rays,
                                            const DiscreteConfig& config);

// X-ray and MIP projections (docs/projections.md): the reference along each ray (options.tol
// validated), or the discrete projection `config` describes; as `vrv ray --mode`.
std::vector<ProjectionResult> projection_values(const Scene& scene, std::span<const Ray> rays, ProjectionMode mode,
                                                const ProjectionOptions& options = {});
std::vector<DiscreteProjectionResult> discrete_projection_values(const Scene& scene, std::span<const Ray> rays,
                                                                 const DiscreteProjectionConfig& config);

// A grey image (lib/io/image_io.h's ImageF64 of one channel: `pixels` row-major, row 0 at the
// top, at(x, y)) and what it cost.
struct ValueImage : ImageF64 {
  long work = 0;                  // field evaluations (reference) or samples (discrete)
  double max_error_estimate = 0;  // reference: the largest per-pixel estimate; discrete: 0

  ValueImage() = default;
  // ValueImage{width, height, pixels, work, max_error_estimate}, the members in that order as a
  // plain struct's braces would take them.  The pixels are not checked against the size here:
  // verify() refuses a mismatch as a VerifyInputError naming the image, as for a file.
  ValueImage(int w, int h, std::vector<double> given = {}, long cost = 0, double largest_estimate = 0)
      : work(cost), max_error_estimate(largest_estimate) {
    width = w, height = h, pixels = std::move(given);
  }
};

ValueImage render_reference_image(const Scene& scene, const Camera& camera,
                           const ReferenceOptions& options = {});
ValueImage render_discrete_image(const Scene& scene, const Camera& camera,
                                 const DiscreteConfig& config);

// Verification in-process: the report `vrv verify` writes (lib/verify.h: errors per image and
// region, orders against the reference and by self-convergence with their standard errors, the
// verdict, vrv's nearest discrete models, the faults the errors match) for a renderer's images
// of the scene's camera (scene_camera(scene) at the images' size, or options.camera), one per
// sample distance in `steps`.  Throws VerifyInputError (a std::invalid_argument, the command
// line's one-line message) for bad input: steps not matching the images, an image of another
// size, NaN pixels (unless options.allow_nan), a repeated or non-positive step.
VerifyReport verify(const Scene& scene, const std::vector<ValueImage>& images,
                    const std::vector<double>& steps, const VerifyOptions& options = {});
// The same for images of 1 to 4 channels as `vrv verify` reads them from files (grey, grey+alpha,
// RGB, RGBA: lib/io/image_channels.h, e.g. channel_image() of an array).  An RGB scene needs this
// form, with three colour channels: each is judged against its own channel (docs/color.md).
VerifyReport verify(const Scene& scene, const std::vector<ChannelImage>& images,
                    const std::vector<double>& steps, const VerifyOptions& options = {});

// The same with the renderer as a callback: render(camera, step) for every step, in the order
// given; the camera is options.camera or scene_camera(scene).  Its images must have the
// camera's size (VerifyInputError otherwise).
using Renderer = std::function<ValueImage(const Camera& camera, double step)>;
VerifyReport verify(const Scene& scene, const std::vector<double>& steps, const Renderer& render,
                    const VerifyOptions& options = {});

// True when the report passes (the reference met its tolerance and, with an expected order, the
// images converge at it) and no bound of `bounds` reaches its fail level: `vrv verify --bounds`'s
// exit 0.  The rows are evaluate_bounds() of lib/gate.h; use_bounds() sets the options a bounds
// set needs (its threshold; NaN pixels counted when it bounds them) before verifying.  Bounds
// come from a file with load_bounds(path).defaults (or a case's .bounds), lib/bounds_file.h.
bool passes(const VerifyReport& report, const BoundSet& bounds);

}  // namespace vrv
