#pragma once
// The work of a ray, estimated before it is cast, in field evaluations: what `vrv study`,
// `vrv render` and `vrv ray` compare with their work limits so that a run of hours is refused
// up front instead of discovered.  A discrete sample is one evaluation (times its oversampling);
// the reference's work is its first panels, which refinement can add to (measured on the
// shipped studies in docs/robustness.md, "Work limits").
#include <array>
#include <string>

#include "lib/camera.h"
#include "lib/discrete_raycast.h"
#include "lib/geometry.h"
#include "lib/scene.h"

namespace vrv {

// The longest chord through the box, its main diagonal: the ray the per-ray estimates below
// use when a run's rays are not built yet (a study's file is checked before anything is cast).
Ray box_diagonal(const Box& box);

// Samples the raycast takes on `ray` before early termination, from its sample plan alone (its
// `samples`, exactly).
double discrete_samples(const DiscreteConfig& config, const Scene& scene, const Ray& ray);
// ... on the box's diagonal: an upper estimate for any ray through the box.
double discrete_samples(const DiscreteConfig& config, const Scene& scene);

// Field evaluations of the reference on `ray` at tolerance `tol`: one panel of degree + 1 nodes
// per stretch between breaks for a field of known degree (exact), else the first panels sized
// for the field's bandwidth (integrate_reference), kPanelNodes each; at most the work cap.
double reference_evaluations(const Scene& scene, const Ray& ray, double tol);
// ... on the box's diagonal.
double reference_evaluations(const Scene& scene, double tol);

// The reference on a grid of `nodes` of known degree along rays (trilinear: 3) before the grid
// is built: one panel per cell the box's diagonal crosses, at most the sum of the cells per axis.
double grid_reference_evaluations(const std::array<int, 3>& nodes, int degree);

// Field evaluations per sample of a discrete raycast: 1, and on a shaded scene its gradient's too
// (central differences 7 in all, the exact gradient about 2, node gradients 4).
double evaluations_per_sample(const DiscreteConfig& config, const Scene& scene);

// Over every pixel of `camera`: the reference's evaluations at `tol`, or with `config` a discrete
// raycast's samples times evaluations_per_sample, from at most 4096 pixels on a regular sub-grid scaled to all of them (each
// of a 8192 x 8192 image's 67 M rays, one by one, took a minute to estimate).
double camera_work(const Scene& scene, const Camera& camera, double tol, const DiscreteConfig* config = nullptr);

// "2.1e+09": a work limit that allows `work`, rounded up to two significant digits (what a
// refusal tells the user to pass).
std::string work_limit_allowing(double work);

}  // namespace vrv
