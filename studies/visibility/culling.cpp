// Block culling with plenoptic opacity functions; see culling.h.
#include "studies/visibility/culling.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include <Eigen/Geometry>

#include "lib/discrete_raycast.h"
#include "lib/image_loop.h"
#include "lib/util/parallel.h"
#include "lib/sampling.h"

namespace vrv {

Box BlockGrid::block(int b) const {
  const int i = b % n[0], j = (b / n[0]) % n[1], k = b / (n[0] * n[1]);
  const Vec3 s = size();
  const Vec3 lo = box.min + Vec3(i * s[0], j * s[1], k * s[2]);
  // The last block ends exactly on the box, not a rounding error short of it.
  Vec3 hi = lo + s;
  if (i + 1 == n[0]) hi[0] = box.max[0];
  if (j + 1 == n[1]) hi[1] = box.max[1];
  if (k + 1 == n[2]) hi[2] = box.max[2];
  return {lo, hi};
}

int BlockGrid::index_of(const Vec3& p) const {
  std::array<int, 3> c{};
  const Vec3 e = box.extent();
  for (int a = 0; a < 3; ++a)
    c[a] = std::clamp(static_cast<int>(std::floor((p[a] - box.min[a]) / e[a] * n[a])), 0, n[a] - 1);
  return c[0] + n[0] * (c[1] + n[1] * c[2]);
}

namespace {

// tau at the ends of [lo, hi] and at every breakpoint inside (both sides of a jump).
template <class Pick>
double extinction_extreme(const TransferFunction& tf, double lo, double hi, double start, Pick pick) {
  double m = pick(start, pick(tf.extinction(lo), tf.extinction(hi)));
  for (double b : tf.breakpoints())
    if (b > lo && b <= hi) {
      m = pick(m, tf.extinction(b));
      m = pick(m, tf.extinction(std::nextafter(b, lo)));  // left limit at a jump
    }
  return m;
}

}  // namespace

double extinction_min(const TransferFunction& tf, double lo, double hi) {
  return extinction_extreme(tf, lo, hi, std::numeric_limits<double>::infinity(),
                            [](double a, double b) { return std::min(a, b); });
}

double extinction_max(const TransferFunction& tf, double lo, double hi) {
  return extinction_extreme(tf, lo, hi, 0.0, [](double a, double b) { return std::max(a, b); });
}

BlockExtinction block_extinction(const GridField& field, const TransferFunction& tf,
                                 const BlockGrid& blocks) {
  const int nb = blocks.count();
  std::vector<double> lo(nb, std::numeric_limits<double>::infinity()),
      hi(nb, -std::numeric_limits<double>::infinity());
  const auto r = field.resolution();
  const Vec3 spacing = field.box().extent().cwiseQuotient(
      Vec3(std::max(r[0] - 1, 1), std::max(r[1] - 1, 1), std::max(r[2] - 1, 1)));
  // A node counts for every block within one node spacing of it (a superset of the nodes the
  // interpolant inside the block depends on, for either layout).
  for (int b = 0; b < nb; ++b) {
    const Box bb = blocks.block(b);
    std::array<int, 2> range[3];
    for (int a = 0; a < 3; ++a) {
      const Vec3 p0 = field.node_position(0, 0, 0);
      const double cell = spacing[a];
      range[a][0] = std::max(0, static_cast<int>(std::floor((bb.min[a] - p0[a]) / cell)) - 1);
      range[a][1] = std::min(r[a] - 1, static_cast<int>(std::ceil((bb.max[a] - p0[a]) / cell)) + 1);
    }
    for (int k = range[2][0]; k <= range[2][1]; ++k)
      for (int j = range[1][0]; j <= range[1][1]; ++j)
        for (int i = range[0][0]; i <= range[0][1]; ++i) {
          const double v = field.node(i, j, k);
          lo[b] = std::min(lo[b], v);
          hi[b] = std::max(hi[b], v);
        }
  }
  BlockExtinction ext{std::vector<double>(nb), std::vector<double>(nb)};
  for (int b = 0; b < nb; ++b) {
    ext.tau_min[b] = extinction_min(tf, lo[b], hi[b]);
    ext.tau_max[b] = extinction_max(tf, lo[b], hi[b]);
  }
  return ext;
}

double view_theta_degrees(int i, int n_theta) { return 360.0 * i / n_theta; }
double view_phi_degrees(int j, int n_phi) { return 180.0 * (j + 0.5) / n_phi; }

Vec3 view_direction(int i, int j, int n_theta, int n_phi) {
  constexpr double deg = std::numbers::pi / 180;
  const double theta = view_theta_degrees(i, n_theta) * deg, phi = view_phi_degrees(j, n_phi) * deg;
  return Vec3(std::sin(phi) * std::cos(theta), std::sin(phi) * std::sin(theta), std::cos(phi));
}

double credited_chord(const Vec3& block_size, const Vec3& d, double chord_fraction) {
  int a = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(d[k]) > std::abs(d[a])) a = k;
  return chord_fraction * block_size[a] / std::abs(d[a]);
}

double pof_depth(double tau_min, double chord, double h) { return tau_min * std::max(chord - h, 0.0); }

Camera view_camera(const Box& box, const Vec3& d, int side) {
  const Vec3 centre = 0.5 * (box.min + box.max);
  const double diag = box.extent().norm();
  Camera c;
  c.projection = Projection::orthographic;
  c.eye = centre - 2 * diag * d;
  c.target = centre;
  c.up = std::abs(d[2]) < 0.9 ? Vec3(0, 0, 1) : Vec3(1, 0, 0);
  c.extent = diag;
  c.width = c.height = side;
  return c;
}

namespace {

struct Sample {
  int block;
  double alpha, color, depth;  // depth = tau h
};

// Pixel rectangle [x0, x1] x [y0, y1] (inclusive) holding the block's projection, one pixel wider.
struct PixelRect {
  int x0, x1, y0, y1;
};

PixelRect footprint(const Camera& cam, const Box& b) {
  const Vec3 f = (cam.target - cam.eye).normalized();
  const Vec3 right = f.cross(cam.up).normalized(), up = right.cross(f);
  const double half = cam.extent / 2;
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (int c = 0; c < 8; ++c) {
    const Vec3 p((c & 1) ? b.max[0] : b.min[0], (c & 2) ? b.max[1] : b.min[1],
                 (c & 4) ? b.max[2] : b.min[2]);
    const double u = (p - cam.eye).dot(right) / half, v = (p - cam.eye).dot(up) / half;
    const double x = (u + 1) / 2 * cam.width - 0.5, y = (1 - v) / 2 * cam.height - 0.5;
    xmin = std::min(xmin, x), xmax = std::max(xmax, x), ymin = std::min(ymin, y), ymax = std::max(ymax, y);
  }
  auto lo = [](double v, int n) { return std::clamp(static_cast<int>(std::floor(v)) - 1, 0, n - 1); };
  auto hi = [](double v, int n) { return std::clamp(static_cast<int>(std::ceil(v)) + 1, 0, n - 1); };
  return {lo(xmin, cam.width), hi(xmax, cam.width), lo(ymin, cam.height), hi(ymax, cam.height)};
}

// Front to back over the samples, skipping those of culled blocks.
double composite(const std::vector<Sample>& s, const std::vector<char>& culled, double background,
                 long& used) {
  double value = 0, transmittance = 1;
  for (const Sample& x : s) {
    if (!culled.empty() && culled[x.block]) continue;
    ++used;
    value += transmittance * x.color * x.alpha;
    transmittance *= 1 - x.alpha;
  }
  return value + transmittance * background;
}

}  // namespace

ViewCulling cull_view(const Scene& scene, const GridField& field, const BlockGrid& blocks,
                      const BlockExtinction& ext, const std::vector<double>& pof, const Vec3& d,
                      const CullingOptions& o) {
  const Camera cam = view_camera(scene.box, d, o.side);
  const int W = o.side, P = W * W, nb = blocks.count();
  const double dthr = -std::log1p(-o.threshold);  // optical depth of the threshold opacity

  // 1. The samples of every pixel (strategy "step"), with their blocks.
  SamplingConfig sampling;
  sampling.strategy = Strategy::step;
  sampling.step = o.step;
  const std::vector<std::vector<Sample>> samples = image_loop(cam, [&](const Ray& ray) {
    std::vector<Sample> s;
    // One classifier per pixel: it caches the transfer function's current branch (not shared).
    const detail::Classifier classes(scene.transfer, o.step);
    const auto iv = clip(ray, scene.box);
    if (!iv) return s;
    const SamplePlan plan = plan_samples(sampling, ray, *iv, scene.box);
    s.reserve(plan.count);
    for (long m = 0; m < plan.count; ++m) {
      const Vec3 x = ray.at(plan.t(m));
      const auto c = classes.from_value<double>(field.value(x));
      s.push_back({blocks.index_of(x), c.alpha_unit, c.color, c.tau * o.step});
    }
    return s;
  });

  // 2. Per block, the pixels whose samples reach it and the depth they take there.
  struct Hit {
    int pixel;
    double depth;
  };
  std::vector<std::vector<Hit>> hits(nb);
  for (int p = 0; p < P; ++p) {
    int last = -1;
    for (const Sample& x : samples[p]) {
      if (x.block != last) hits[x.block].push_back({p, 0.0});
      hits[x.block].back().depth += x.depth;
      last = x.block;
    }
  }
  std::vector<int> order(nb);
  std::iota(order.begin(), order.end(), 0);
  std::vector<double> key(nb);
  for (int b = 0; b < nb; ++b) {
    const Box bb = blocks.block(b);
    key[b] = (0.5 * (bb.min + bb.max)).dot(d);
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return key[a] < key[b]; });
  // Each non-empty block's footprint: its pixels and their chords through it.  They do not depend
  // on the culling, which is sequential, so they are found first, in parallel.
  std::vector<std::vector<std::pair<int, double>>> feet(nb);  // pixel, chord
  parallel_for_index(nb, [&](long b) {
    if (!(ext.tau_max[b] > 0)) return;
    const Box bb = blocks.block(static_cast<int>(b));
    const PixelRect r = footprint(cam, bb);
    for (int y = r.y0; y <= r.y1; ++y)
      for (int x = r.x0; x <= r.x1; ++x) {
        const auto iv = clip(cam.ray(x, y), bb);
        if (iv && iv->length() > 0) feet[b].emplace_back(y * W + x, iv->length());
      }
  });

  ViewCulling out;
  std::vector<std::vector<char>> culled(kCullMethods, std::vector<char>(nb, 0));
  std::vector<std::vector<double>> buffer(kCullMethods, std::vector<double>(P, 0.0));
  const double chord = credited_chord(blocks.size(), d, o.chord_fraction);
  auto cull = [&](int method, int b) {
    culled[method][b] = 1;
    ++out.culled[method];
  };
  for (int b : order) {
    if (!(ext.tau_max[b] > 0)) continue;
    ++out.nonempty;
    // Sequential: the opacity the kept blocks really put in front, on the pixels that reach b.
    auto& seq = buffer[kSequential];
    bool opaque = !hits[b].empty();
    for (const Hit& h : hits[b]) opaque = opaque && seq[h.pixel] >= dthr;
    if (opaque) cull(kSequential, b);
    else
      for (const Hit& h : hits[b]) seq[h.pixel] += h.depth;
    // POF and chord: every pixel whose ray meets the block must be opaque enough in the buffer.
    const std::vector<std::pair<int, double>>& foot = feet[b];
    for (int method : {kPof, kChord}) {
      auto& buf = buffer[method];
      bool hidden = !foot.empty();
      for (const auto& [p, len] : foot) hidden = hidden && buf[p] >= dthr;
      if (hidden) {
        cull(method, b);
        continue;
      }
      for (const auto& [p, len] : foot) {
        if (method == kPof && len >= chord) buf[p] += pof[b];
        if (method == kChord) buf[p] += pof_depth(ext.tau_min[b], len, o.step);
      }
    }
  }

  // 3. The images, and the true opacity in front of each culled block.
  const std::vector<char> none;
  std::vector<long> used_all(P, 0);
  std::vector<double> v_all(P);
  std::vector<std::vector<long>> used(kCullMethods, std::vector<long>(P, 0));
  std::vector<std::vector<double>> v(kCullMethods, std::vector<double>(P)), front(kCullMethods, std::vector<double>(P, 1.0));
  parallel_for_index(P, [&](long p) {
    const auto& s = samples[p];
    v_all[p] = composite(s, none, scene.background, used_all[p]);
    for (int m = 0; m < kCullMethods; ++m) {
      v[m][p] = composite(s, culled[m], scene.background, used[m][p]);
      double depth = 0;
      for (const Sample& q : s) {
        if (culled[m][q.block]) {
          front[m][p] = -std::expm1(-depth);
          break;
        }
        depth += q.depth;
      }
    }
  });
  out.image_all = Image(W, W);
  for (int m = 0; m < kCullMethods; ++m) out.image[m] = Image(W, W);
  for (int p = 0; p < P; ++p) {
    out.image_all.pixels[p] = static_cast<float>(v_all[p]);
    out.samples_all += used_all[p];
    for (int m = 0; m < kCullMethods; ++m) {
      out.image[m].pixels[p] = static_cast<float>(v[m][p]);
      out.max_error[m] = std::max(out.max_error[m], std::abs(v[m][p] - v_all[p]));
      out.min_front_opacity[m] = std::min(out.min_front_opacity[m], front[m][p]);
      out.samples[m] += used[m][p];
    }
  }
  return out;
}

}  // namespace vrv
