#pragma once
// Verifying any renderer from its images (`vrv verify`, docs/verify.md).
//
// Given a scene and a renderer's images of it at several sample distances, verify_images
//  1. renders the reference image for the images' size (once per size; cached on disk when
//     VerifyOptions::cache_dir and scene_text are given): lib/verify/reference_image.h,
//     reference_cache.h; and fails if it misses its tolerance;
//  2. per image and channel, the signed error against it and its statistics (lib/metrics.h) over
//     the whole image and over regions (lib/verify/pixel_geometry.h, channel_errors.h):
//     `silhouette` (pixels within silhouette_band pixels of the volume's outline, from which
//     pixels' rays hit the box), `tf_jump` (other pixels whose ray crosses a value where the
//     transfer function jumps), `interior` (the remaining pixels that hit the box) and `outside`
//     (the remaining pixels that miss it);
//  3. across images: the observed order against the reference and the self-convergence order
//     (differences of successive images, no reference), each with its standard error, and a
//     verdict per channel and overall (the worst): lib/verify/convergence_orders.h;
//  4. a diagnosis: vrv casts its own discrete models (lib/verify/model_catalogue.h) at the same
//     steps and lists them by RMS difference from the images (lib/verify/diagnosis.h), and the
//     known faults whose pattern the errors match (lib/verify/fault_hints.h); with an expected
//     order, a placement or rule consistent with it is the renderer's convention, not a fault
//     (lib/verify/conventions.h); a step-independent floor is decomposed by the fitted fault
//     catalogue (lib/verify/fault_fit.h) and its best entry named.
// The options are lib/verify/verify_options.h, the inputs lib/verify/verify_inputs.h, the report
// and its JSON lib/verify/verify_report.h.
#include <vector>

#include "lib/camera.h"
#include "lib/scene.h"
#include "lib/verify/diagnosis.h"
#include "lib/verify/reference_image.h"
#include "lib/verify/verify_inputs.h"
#include "lib/verify/verify_options.h"
#include "lib/verify/verify_report.h"

namespace vrv {

// Throws VerifyInputError for bad input (no images, images of different sizes, a non-positive
// or repeated step, NaN pixels when allow_nan is false); std::invalid_argument for bad options.
VerifyReport verify_images(const Scene& scene, const std::vector<ImageWithStep>& images,
                           const VerifyOptions& options);

// The camera images of w x h pixels are judged with: VerifyOptions::camera, else the scene's, else
// default_camera(scene.box), at the images' size; VerifyInputError when it is not valid.
Camera verify_camera(const Scene& scene, const VerifyOptions& options, int width, int height);

// Field evaluations a verification of w x h images at `steps` takes, estimated before any work:
// the reference on every pixel at options.reference_tol (camera_work, lib/work_estimate.h) and,
// with options.diagnose, the diagnosis' casts (diagnosis_work, lib/verify/diagnosis.h).
struct VerificationWork {
  double reference = 0, diagnosis = 0;
  double total() const { return reference + diagnosis; }
};
VerificationWork verification_work(const Scene& scene, const VerifyOptions& options, int width, int height,
                                   const std::vector<double>& steps);

}  // namespace vrv
