#pragma once
// The sampling study's computations (Steneteg et al., "Volume Raycasting Sampling Revisited"):
// the paper's 2D set-up, a square rotated by alpha seen from an eye by a fan of rays, placed in
// vrv's axis-aligned box by rotating the eye and the fan by -alpha about the square's centre;
// per-ray intensities of each sample-placement strategy against the continuous solution (Fig. 2),
// the extruded 3D version as images (Fig. 4), and error statistics with observed orders.
// The driver (driver.cpp) reads the study file and writes the tables.
#include <array>
#include <vector>

#include "lib/camera.h"
#include "lib/discrete_raycast.h"
#include "lib/io/image_io.h"
#include "lib/metrics.h"
#include "lib/scene.h"
#include "studies/engine/reference_audit.h"
#include "lib/vrv.h"  // camera_rays: every ray of a camera (fan: width rays; images: row-major)

namespace vrv::sampling_study {

// The paper's set-up in its own (world) coordinates: eye and central ray direction in the
// plane z = 0, the square rotated counter-clockwise by `rotation_degrees` about `centre`.
struct FanSetup {
  std::array<double, 2> eye{-9, 0};
  std::array<double, 2> centre{0, 0};
  double rotation_degrees = 180.0 / 7;  // alpha = pi/7
  double angle_degrees = 0;             // the fan's central ray, 0 = +x
  double fov_degrees = 30;
  int rays = 120;
};

// A point of the paper's plane in the square's own frame: rotated by -alpha about the centre.
std::array<double, 2> to_square_frame(const FanSetup& s, std::array<double, 2> p);

// The paper's fan in the square's frame (plane z = 0): ray i at world angle
// angle - fov/2 + fov (i + 1/2) / rays, i.e. vrv's fan camera with eye and angle rotated.
Camera fan_camera(const FanSetup& s);

// The 3D view of the extruded volume: a perspective camera at the same eye looking along the
// fan's central ray, `fov_degrees` vertically (square images: the same horizontally), up = -z so
// that image columns run the way the fan's ray index does.
Camera image_camera(const FanSetup& s, int width, int height);

// One discrete configuration: a rule (the paper's eq. (5) is riemann) with a rate-based strategy
// over the scene's dims, the eye strategy aligned with the camera's eye.
DiscreteConfig strategy_config(const Scene& scene, SegmentRule rule, Strategy strategy, double rate,
                               const Vec3& eye);

struct RayValue {
  double value = 0;
  long samples = 0;
};

// Per ray: chord length, the continuous solution (vrv's reference) and its estimate.
struct ContinuousRay {
  double chord = 0;  // world length inside the box, 0 for a miss
  double value = 0, estimate = 0;
};

// The world (paper) angle of fan ray i, in degrees.
double fan_angle_degrees(const FanSetup& s, int i);

// Each ray in its own slot: the same numbers for any thread count.  continuous_rays counts its
// truths in `audit`.
std::vector<ContinuousRay> continuous_rays(const Scene& scene, const std::vector<Ray>& rays, double tol,
                                           ReferenceAudit& audit);
std::vector<RayValue> discrete_rays(const Scene& scene, const std::vector<Ray>& rays,
                                    const DiscreteConfig& c);

// Errors |discrete - continuous| over the rays that meet the box (chord > 0): `error` (lib/metrics;
// count = those rays; max and mean are the study's).  dropped: rays that meet it with a chord of
// positive length but receive no sample.
struct FanStats {
  vrv::ErrorStats error;
  double mean_samples = 0;
  long dropped = 0, nonfinite = 0;
};
FanStats ray_error_stats(const std::vector<ContinuousRay>& truth, const std::vector<RayValue>& rays);

// Values as a float image of the camera's size (row-major rays).
Image to_image(const Camera& camera, const std::vector<double>& values);

}  // namespace vrv::sampling_study
