#pragma once
// The opacity-correction study's computations inside one voxel (Lee & Newman, WSCG 2007): one
// group of N oversamples corrected and composited (Figs. 3 and 4), the quadratic fit's error
// against the exact p (sec. 4.4), 8-bit sample groups, and the cost of the correction alone
// (Table 1, upper row).  The corrections themselves are lib/opacity_correction.h.
#include <cstdint>
#include <span>
#include <vector>

#include "lib/opacity_correction.h"

namespace vrv {

// One group corrected by `c` (colours as given; eq. 3: intensity C alpha) and composited front to
// back (eq. 1).  opacity = 1 - prod(1 - alpha'_k), from log1p terms; p is the Lee & Newman factor
// (1 for the other corrections).
struct GroupResult {
  double opacity = 0;
  double intensity = 0;
  double p = 1;
};
GroupResult composite_group(Correction c, std::span<const double> alphas, std::span<const double> colors, int N);

// |p_quadratic - p_exact| over a set of groups (each of N samples, alpha_unit = the first).
struct FitErrorStats {
  long groups = 0;
  double mean = 0, sd = 0, max = 0;
  double fraction_above = 0;  // of the groups whose error exceeds `threshold`
  bool all_in_unit = true;    // every p_quadratic finite and in [0, 1]
};
// groups: consecutive runs of N opacities.  Sums in index order (deterministic).
FitErrorStats fit_error_stats(std::span<const double> groups, int N, double threshold);

// count groups of N independent uniform 8-bit opacities k / 255 from mt19937_64(seed), the byte
// taken as the top 8 bits of each draw (no std distributions: the same on every platform).
std::vector<double> random_byte_groups(int N, long count, std::uint64_t seed);
// Every 8-bit pair (D0, D1): the linear ramp D_k = D0 + (D1 - D0) k / N, k = 0..N-1, over 255.
std::vector<double> ramp_groups(int N);

// Fig. 3: for every pair of 8-bit codes (a, b) (alpha = colour = code / 255, N = 2), the
// composited opacity and intensity per correction; row-major with b the row (index b * 256 + a).
struct PairSurface {
  Correction correction;
  std::vector<double> opacity, intensity, p;  // 256 * 256
};
PairSurface pair_surface(Correction c);

// Table 1, upper row: seconds per sample of correct_group(c) over the groups (copied into a
// scratch buffer first, as in a renderer's loop), the best of `repeats` passes.
double correction_seconds_per_sample(Correction c, std::span<const double> groups, int N, int repeats);

}  // namespace vrv
