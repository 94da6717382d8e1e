#pragma once
// Block culling with plenoptic opacity functions (Gao, Huang, Shen, Kohl, IEEE Vis 2003, sec. 3):
// the volume is cut into blocks; for every block and every sample view (theta, phi) a table holds
// a conservative lower bound on the opacity the block adds to a ray (the POF); a view visits the
// blocks front to back, culls a block when every pixel of its footprint already has accumulated
// at least `threshold` opacity, and otherwise composites the block's POF into its pixels.
//
// Our POF (the paper renders each block and keeps its least opaque pixel, which is not a bound):
//   POF_b(d) = 1 - exp(-tau_min,b * max(l*(d) - h, 0)),   l*(d) = c * L_a / |d_a|,
// credited only to pixels whose ray crosses the block over a chord >= l*(d).  a is the dominant
// axis of d, L_a the block side along it (l* = c times the longest chord), c = chord_fraction.
// tau_min,b is the least extinction of any value the field takes in the block (trilinear values
// lie between the nodes within one spacing of the block); a sampled renderer with step h takes at
// least l/h - 1 samples on a chord of length l, hence the - h.  So the buffer is a lower bound on
// the opacity the renderer really accumulated, and culling loses at most (1 - threshold) times
// the most any remainder of the ray can add, max(max colour, background).
#include <array>
#include <vector>

#include "lib/camera.h"
#include "lib/geometry.h"
#include "lib/grid_field.h"
#include "lib/io/image_io.h"
#include "lib/scene.h"
#include "lib/transfer_function.h"

namespace vrv {

struct BlockGrid {
  Box box;
  std::array<int, 3> n{8, 8, 8};
  int count() const { return n[0] * n[1] * n[2]; }
  Vec3 size() const { return box.extent().cwiseQuotient(Vec3(n[0], n[1], n[2])); }
  Box block(int b) const;
  // The block holding p (clamped to the grid); ties go to the block above, as floor does.
  int index_of(const Vec3& p) const;
};

// Least and greatest extinction over the values the field can take inside each block.
struct BlockExtinction {
  std::vector<double> tau_min, tau_max;
};
BlockExtinction block_extinction(const GridField& field, const TransferFunction& tf,
                                 const BlockGrid& blocks);
// min / max of tau(v) over v in [lo, hi]: at the ends or at a breakpoint inside.
double extinction_min(const TransferFunction& tf, double lo, double hi);
double extinction_max(const TransferFunction& tf, double lo, double hi);

// The 36 x 36 grid of the paper: theta (azimuth) = 360 i / n_theta, phi (polar angle from +z)
// = 180 (j + 1/2) / n_phi, so no view sits on a pole.  Unit view direction (eye towards scene).
Vec3 view_direction(int i, int j, int n_theta, int n_phi);
double view_theta_degrees(int i, int n_theta);
double view_phi_degrees(int j, int n_phi);

// l*(d) = c * L_a / |d_a| for the dominant axis a of d.
double credited_chord(const Vec3& block_size, const Vec3& d, double chord_fraction);
// The POF entry as an optical depth: tau_min * max(chord - h, 0).
double pof_depth(double tau_min, double chord, double h);

// The orthographic camera of a view: looks at the box centre along d, sees the whole box.
Camera view_camera(const Box& box, const Vec3& d, int side);

// One view rendered three ways: all blocks, POF culling, and the paper's sequential check
// (culling against the opacity the rendered, unculled-so-far blocks really accumulated).
struct CullingOptions {
  double threshold = 0.95;
  double step = 0.03125;  // sample step h (world), samples as strategy "step"
  double chord_fraction = 0.5;
  int side = 32;          // image side (pixels)
};

// The three culling tests: the POF table (one number per block and view), the same bound with
// each pixel's own chord, tau_min * max(chord - h, 0) (tighter, but not a table over views), and
// the paper's sequential check against the opacity the kept blocks really rendered.
enum CullMethod { kPof = 0, kChord = 1, kSequential = 2 };
inline constexpr int kCullMethods = 3;
inline constexpr const char* kCullMethodNames[kCullMethods] = {"POF", "chord", "sequential"};

struct ViewCulling {
  int nonempty = 0;  // blocks with tau_max > 0
  std::array<int, kCullMethods> culled{};            // of those, culled by each test
  std::array<double, kCullMethods> max_error{};      // max |culled - all| over pixels
  // Least true opacity (of the kept blocks) in front of a culled block, over every pixel whose
  // samples reach it; 1 when nothing was culled.  Conservative means >= threshold.
  std::array<double, kCullMethods> min_front_opacity{1, 1, 1};
  long samples_all = 0;
  std::array<long, kCullMethods> samples{};
  Image image_all;
  std::array<Image, kCullMethods> image;
};

// `pof` holds the block's POF optical depth for this view (one entry per block).
ViewCulling cull_view(const Scene& scene, const GridField& field, const BlockGrid& blocks,
                      const BlockExtinction& ext, const std::vector<double>& pof, const Vec3& d,
                      const CullingOptions& options);

}  // namespace vrv
