#pragma once
// An independent reference for the emission-absorption integral along a ray, in long double,
// written from the definition
//   I = int_{t0}^{t1} g(f(r(s))) exp(-int_{t0}^{s} tau(f(r(u))) du) ds + I0 exp(-int_{t0}^{t1} tau)
// and sharing no numerical code with lib/: the ray is normalised and clipped here, the fields
// and the transfer-function curves are evaluated here (only the control points and the grid's
// node values are read from the vrv objects), and the quadrature is plain composite
// Gauss-Legendre with a nested Gauss-Legendre for the optical depth at every node.
//
// Method:
//  1. structural breaks (grid node planes for trilinear, half-way planes for nearest) are
//     computed directly;
//  2. on every structural piece, f(t) is scanned finely; local extrema of the samples are
//     refined by golden-section search, which leaves intervals on which f is monotone; on each
//     of them every transfer-function control value is crossed at most once, and the crossing
//     is found by bisection to full long-double precision;
//  3. between consecutive breaks g and tau are smooth; they are integrated on sub-panels of
//     length <= max_panel (shorter where the optical depth of a panel would exceed
//     max_panel_depth) by 20-point Gauss-Legendre, the optical depth at each outer node by a
//     nested (12-point) Gauss-Legendre from the panel start plus the running depth; once the
//     emission still to come is below 1e-30 only the depth is integrated.
// Checked against closed forms and for convergence (finer scan, shorter panels, more points)
// in independent_reference_test.cpp; on Marschner-Lobb rays it agrees with itself to ~1e-18.
// It is slow (hundreds of thousands of long-double field evaluations per ray) and meant only
// for tests.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

#include "lib/geometry.h"
#include "lib/grid_field.h"
#include "lib/transfer_function.h"

namespace vrv::independent {

using LD = long double;

struct P3 {
  LD c[3] = {0, 0, 0};
  LD operator[](int a) const { return c[a]; }
};

inline P3 to_p3(const Vec3& v) { return P3{{v.x(), v.y(), v.z()}}; }

inline P3 along(const P3& o, const P3& d, LD t) {
  return P3{{o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]}};
}

// ---------------------------------------------------------------------------------------------
// Fields in long double.

class FieldLD {
 public:
  virtual ~FieldLD() = default;
  // f at p; `inside` is a point of the same smooth piece of the ray (its midpoint), which
  // grids use to choose the cell, so that a piece's end points use the piece's own formula.
  virtual LD value(const P3& p, const P3& inside) const = 0;
  // Parameters in (t0, t1) where f is not smooth along origin + t dir.
  virtual void structural_breaks(const P3& /*origin*/, const P3& /*dir*/, LD /*t0*/, LD /*t1*/,
                                 std::vector<LD>& /*out*/) const {}
};

class MarschnerLobbLD final : public FieldLD {
 public:
  MarschnerLobbLD(LD fM = 6, LD alpha = 0.25L) : fM_(fM), alpha_(alpha) {}
  LD value(const P3& p, const P3&) const override {
    constexpr LD pi = std::numbers::pi_v<LD>;
    const LD r = std::hypot(p[0], p[1]);
    const LD rho = std::cos(2 * pi * fM_ * std::cos(pi * r / 2));
    return (1 - std::sin(pi * p[2] / 2) + alpha_ * (1 + rho)) / (2 * (1 + alpha_));
  }

 private:
  LD fM_, alpha_;
};

class LinearRampLD final : public FieldLD {
 public:
  LinearRampLD(const Vec3& gradient, LD offset) : g_(to_p3(gradient)), offset_(offset) {}
  LD value(const P3& p, const P3&) const override {
    return offset_ + g_[0] * p[0] + g_[1] * p[1] + g_[2] * p[2];
  }

 private:
  P3 g_;
  LD offset_;
};

// The interpolant of a vrv::GridField's node values, evaluated in long double.
class GridLD final : public FieldLD {
 public:
  explicit GridLD(const GridField& grid)
      : nearest_(grid.interpolation() == Interpolation::nearest),
        offset_(grid.layout() == GridLayout::cell ? 0.5L : 0.0L) {
    const auto n = grid.resolution();
    for (int a = 0; a < 3; ++a) {
      n_[a] = n[a];
      min_[a] = grid.box().min[a];
      const LD extent = static_cast<LD>(grid.box().max[a]) - static_cast<LD>(grid.box().min[a]);
      h_[a] = extent / (grid.layout() == GridLayout::node ? n[a] - 1 : n[a]);
    }
    values_.resize(static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]);
    for (int k = 0; k < n_[2]; ++k)
      for (int j = 0; j < n_[1]; ++j)
        for (int i = 0; i < n_[0]; ++i) values_[index(i, j, k)] = grid.node(i, j, k);
  }

  LD value(const P3& p, const P3& inside) const override {
    int i0[3], i1[3];
    LD w[3];
    for (int a = 0; a < 3; ++a) {
      const LD ui = coordinate(inside[a], a);
      if (nearest_) {
        i0[a] = i1[a] = std::clamp(static_cast<int>(std::floor(ui + 0.5L)), 0, n_[a] - 1);
        w[a] = 0;
      } else {
        i0[a] = std::clamp(static_cast<int>(std::floor(ui)), 0, std::max(n_[a] - 2, 0));
        i1[a] = std::min(i0[a] + 1, n_[a] - 1);
        w[a] = coordinate(p[a], a) - i0[a];
      }
    }
    if (nearest_) return values_[index(i0[0], i0[1], i0[2])];
    LD sum = 0;
    for (int corner = 0; corner < 8; ++corner) {
      LD weight = 1;
      int idx[3];
      for (int a = 0; a < 3; ++a) {
        const bool upper = (corner >> a) & 1;
        idx[a] = upper ? i1[a] : i0[a];
        weight *= upper ? w[a] : 1 - w[a];
      }
      sum += weight * values_[index(idx[0], idx[1], idx[2])];
    }
    return sum;
  }

  void structural_breaks(const P3& o, const P3& d, LD t0, LD t1,
                         std::vector<LD>& out) const override {
    // Trilinear: node planes; nearest: planes half way between nodes.
    const LD shift = offset_ + (nearest_ ? 0.5L : 0.0L);
    for (int a = 0; a < 3; ++a) {
      if (d[a] == 0) continue;
      const int planes = nearest_ ? n_[a] - 1 : n_[a];
      for (int i = 0; i < planes; ++i) {
        const LD t = (min_[a] + (i + shift) * h_[a] - o[a]) / d[a];
        if (t > t0 && t < t1) out.push_back(t);
      }
    }
  }

 private:
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * n_[1] + j) * n_[0] + i;
  }
  LD coordinate(LD x, int a) const {
    const LD u = (x - min_[a]) / h_[a] - offset_;
    return std::clamp(u, LD{0}, static_cast<LD>(n_[a] - 1));
  }

  bool nearest_;
  LD offset_;
  int n_[3];
  LD min_[3], h_[3];
  std::vector<LD> values_;
};

// ---------------------------------------------------------------------------------------------
// Transfer function in long double.

class CurveLD {
 public:
  explicit CurveLD(const PiecewiseLinear& curve) {
    for (const auto& p : curve.points()) pts_.push_back({p.v, p.y});
  }
  // Index of the branch that holds v (right-continuous at jumps): 0 before the first point,
  // size() after the last, else the segment from point k-1 to point k.
  int branch(LD v) const {
    int k = 0;
    while (k < static_cast<int>(pts_.size()) && pts_[k].first <= v) ++k;
    return k;
  }
  // The branch's line, extended beyond its own interval.
  LD on_branch(int k, LD v) const {
    if (k == 0) return pts_.front().second;
    if (k == static_cast<int>(pts_.size())) return pts_.back().second;
    const auto& a = pts_[k - 1];
    const auto& b = pts_[k];
    return a.second + (b.second - a.second) * ((v - a.first) / (b.first - a.first));
  }
  LD operator()(LD v) const { return on_branch(branch(v), v); }
  LD max_y() const {
    LD m = 0;
    for (const auto& p : pts_) m = std::max(m, p.second);
    return m;
  }
  const std::vector<std::pair<LD, LD>>& points() const { return pts_; }

 private:
  std::vector<std::pair<LD, LD>> pts_;
};

class TransferLD {
 public:
  struct Branch {
    int first = 0;
    int second = 0;
  };

  explicit TransferLD(const TransferFunction& tf)
      : opacity_color_(tf.convention() == Convention::opacity_color),
        unit_length_(tf.unit_length()),
        first_(tf.first()),
        second_(tf.second()) {
    for (const CurveLD* c : {&first_, &second_})
      for (const auto& p : c->points()) levels_.push_back(p.first);
    std::sort(levels_.begin(), levels_.end());
    levels_.erase(std::unique(levels_.begin(), levels_.end()), levels_.end());
  }

  Branch branch(LD v) const { return {first_.branch(v), second_.branch(v)}; }
  LD tau(const Branch& b, LD v) const {
    const LD y = std::max(LD{0}, first_.on_branch(b.first, v));
    if (!opacity_color_) return std::max(LD{0}, second_.on_branch(b.second, v));
    return -std::log1p(-y) / unit_length_;
  }
  LD g(const Branch& b, LD v) const {
    if (!opacity_color_) return std::max(LD{0}, first_.on_branch(b.first, v));
    return std::max(LD{0}, second_.on_branch(b.second, v)) * tau(b, v);
  }
  LD tau(LD v) const { return tau(branch(v), v); }
  LD g(LD v) const { return g(branch(v), v); }
  // An upper bound on g.
  LD max_g() const {
    if (!opacity_color_) return first_.max_y();
    return second_.max_y() * -std::log1p(-first_.max_y()) / unit_length_;
  }
  const std::vector<LD>& levels() const { return levels_; }

 private:
  bool opacity_color_;
  LD unit_length_;
  CurveLD first_, second_;
  std::vector<LD> levels_;
};

// ---------------------------------------------------------------------------------------------
// Gauss-Legendre rules in long double (Newton on the Legendre polynomial).

struct GaussRule {
  std::vector<LD> x, w;  // on [-1, 1]
};

inline GaussRule gauss_legendre(int n) {
  constexpr LD pi = std::numbers::pi_v<LD>;
  GaussRule r;
  r.x.resize(n);
  r.w.resize(n);
  for (int i = 0; i < n; ++i) {
    LD x = std::cos(pi * (i + 0.75L) / (n + 0.5L));
    for (int it = 0; it < 100; ++it) {
      LD p0 = 1, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const LD p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      const LD dx = p1 / (n * (x * p1 - p0) / (x * x - 1));
      x -= dx;
      if (std::abs(dx) <= 2 * std::numeric_limits<LD>::epsilon()) break;
    }
    // Weights from the converged node.
    LD p0 = 1, p1 = x;
    for (int k = 2; k <= n; ++k) {
      const LD p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    const LD dp = n * (x * p1 - p0) / (x * x - 1);
    r.x[i] = x;
    r.w[i] = 2 / ((1 - x * x) * dp * dp);
  }
  return r;
}

// ---------------------------------------------------------------------------------------------
// The integral.

struct Options {
  LD scan_density = 5000;    // scan samples per unit length (extrema are refined, so crossings
                             // closer together than a sample step are still separated)
  LD max_panel = 0.02L;      // sub-panel length (world units)
  LD max_panel_depth = 2;    // optical depth of one sub-panel while emission still counts
  int points = 20;           // Gauss-Legendre points of the outer rule
  int inner_points = 12;     // ... and of the nested rule for the depth at each outer node
  LD negligible = 1e-30L;    // emission still to come below which only the depth is integrated
};

struct Result {
  LD value = 0;
  LD optical_depth = 0;
  bool hit = false;
  LD t_entry = 0;
  LD t_exit = 0;
  long evaluations = 0;
  long pieces = 0;  // smooth pieces integrated
};

// The ray origin + t dir / |dir| (normalised here, in long double) clipped to the closed box.
inline std::optional<std::pair<LD, LD>> clip_ld(const P3& o, const P3& d, const Box& box) {
  LD t0 = 0, t1 = std::numeric_limits<LD>::infinity();
  for (int a = 0; a < 3; ++a) {
    const LD lo = box.min[a], hi = box.max[a];
    if (d[a] == 0) {
      if (o[a] < lo || o[a] > hi) return std::nullopt;
      continue;
    }
    LD n = (lo - o[a]) / d[a], f = (hi - o[a]) / d[a];
    if (n > f) std::swap(n, f);
    t0 = std::max(t0, n);
    t1 = std::min(t1, f);
  }
  if (!(t0 <= t1)) return std::nullopt;
  return std::make_pair(t0, t1);
}

inline Result independent_integral(const FieldLD& field, const Box& box, const TransferFunction& tf,
                                   LD background, const Vec3& origin, const Vec3& direction,
                                   const Options& opt = {}) {
  Result res;
  const P3 o = to_p3(origin);
  P3 d = to_p3(direction);
  {
    const LD s = std::max({std::abs(d[0]), std::abs(d[1]), std::abs(d[2])});
    LD norm2 = 0;
    for (auto& c : d.c) c /= s, norm2 += c * c;
    const LD norm = std::sqrt(norm2);
    for (auto& c : d.c) c /= norm;
  }
  const auto iv = clip_ld(o, d, box);
  if (!iv) {
    res.value = background;
    return res;
  }
  const auto [t0, t1] = *iv;
  res.hit = true;
  res.t_entry = t0;
  res.t_exit = t1;

  const TransferLD tfl(tf);
  const LD gmax = tfl.max_g();
  const std::vector<LD>& levels = tfl.levels();
  const GaussRule rule = gauss_legendre(opt.points);
  const GaussRule inner = gauss_legendre(opt.inner_points);

  std::vector<LD> structural{t0};
  field.structural_breaks(o, d, t0, t1, structural);
  structural.push_back(t1);
  std::sort(structural.begin(), structural.end());

  LD phi = 0, value = 0;
  bool emitting = true;
  std::vector<LD> ts, fs, cuts, extrema;

  for (std::size_t s = 0; s + 1 < structural.size(); ++s) {
    const LD a = structural[s], b = structural[s + 1];
    if (!(b > a)) continue;
    const P3 inside = along(o, d, a + (b - a) / 2);
    auto f = [&](LD t) {
      ++res.evaluations;
      return field.value(along(o, d, t), inside);
    };

    // Scan.
    const long n = std::max(16L, static_cast<long>(std::ceil(opt.scan_density * (b - a))));
    ts.assign(n + 1, 0);
    fs.assign(n + 1, 0);
    for (long k = 0; k <= n; ++k) {
      ts[k] = k == n ? b : a + (b - a) * k / n;
      fs[k] = f(ts[k]);
    }
    // Extrema of the samples, refined by golden-section search.
    extrema.clear();
    for (long k = 1; k < n; ++k) {
      const LD d0 = fs[k] - fs[k - 1], d1 = fs[k + 1] - fs[k];
      if (!((d0 > 0 && d1 < 0) || (d0 < 0 && d1 > 0))) continue;
      const LD sign = d0 > 0 ? 1 : -1;  // maximise sign * f
      LD lo = ts[k - 1], hi = ts[k + 1];
      constexpr LD r = 0.6180339887498948482045868343656381L;
      LD x1 = hi - r * (hi - lo), x2 = lo + r * (hi - lo);
      LD f1 = sign * f(x1), f2 = sign * f(x2);
      for (int it = 0; it < 200 && hi - lo > 64 * std::numeric_limits<LD>::epsilon() * (std::abs(lo) + 1); ++it) {
        if (f1 >= f2) {
          hi = x2;
          x2 = x1;
          f2 = f1;
          x1 = hi - r * (hi - lo);
          f1 = sign * f(x1);
        } else {
          lo = x1;
          x1 = x2;
          f1 = f2;
          x2 = lo + r * (hi - lo);
          f2 = sign * f(x2);
        }
      }
      const LD te = (lo + hi) / 2;
      if (te > a && te < b) extrema.push_back(te);
    }
    std::sort(extrema.begin(), extrema.end());
    // Monotone intervals [m_j, m_{j+1}]: each level is crossed at most once.
    std::vector<LD> mono{a};
    mono.insert(mono.end(), extrema.begin(), extrema.end());
    mono.push_back(b);
    std::vector<LD> mono_f(mono.size());
    for (std::size_t j = 0; j < mono.size(); ++j) mono_f[j] = f(mono[j]);
    cuts.assign(mono.begin(), mono.end());
    for (std::size_t j = 0; j + 1 < mono.size(); ++j) {
      for (LD v : levels) {
        const LD fa = mono_f[j] - v, fb = mono_f[j + 1] - v;
        if (fa == 0 || fb == 0 || (fa > 0) == (fb > 0)) continue;
        LD lo = mono[j], hi = mono[j + 1];
        for (int it = 0; it < 20000; ++it) {
          const LD m = lo + (hi - lo) / 2;
          if (!(m > lo && m < hi)) break;
          const LD fm = f(m) - v;
          if (fm == 0) {
            lo = hi = m;
            break;
          }
          if ((fm > 0) == (fa > 0)) lo = m;
          else hi = m;
        }
        cuts.push_back(lo + (hi - lo) / 2);
      }
    }
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());

    // Integrate every smooth piece.
    for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
      const LD pa = cuts[c], pb = cuts[c + 1];
      if (!(pb > pa)) continue;
      ++res.pieces;
      const auto br = tfl.branch(f(pa + (pb - pa) / 2));
      auto tau_at = [&](LD t) { return tfl.tau(br, f(t)); };
      auto depth = [&](LD x0, LD x1, const GaussRule& q) {
        const LD half = (x1 - x0) / 2, mid = x0 + half;
        LD sum = 0;
        for (std::size_t i = 0; i < q.x.size(); ++i) sum += q.w[i] * tau_at(mid + half * q.x[i]);
        return half * sum;
      };
      LD p = pa;
      while (p < pb) {
        LD h = std::min(opt.max_panel, pb - p);
        LD q = h >= pb - p ? pb : p + h;
        LD dphi = depth(p, q, rule);
        while (emitting && dphi > opt.max_panel_depth && h > (pb - pa) * 1e-12L) {
          h /= 2;
          q = p + h;
          dphi = depth(p, q, rule);
        }
        if (emitting) {
          const LD half = (q - p) / 2, mid = p + half;
          LD sum = 0;
          for (std::size_t i = 0; i < rule.x.size(); ++i) {
            const LD x = mid + half * rule.x[i];
            const LD v = f(x);
            const LD gx = tfl.g(br, v);
            if (gx == 0) continue;
            sum += rule.w[i] * gx * std::exp(-(phi + depth(p, x, inner)));
          }
          value += half * sum;
        }
        phi += dphi;
        p = q;
        if (emitting && std::exp(-phi) * gmax * (t1 - p) < opt.negligible) emitting = false;
      }
    }
  }
  res.optical_depth = phi;
  res.value = value + background * std::exp(-phi);
  return res;
}

inline Result independent_integral(const FieldLD& field, const Box& box, const TransferFunction& tf,
                                   LD background, const Ray& ray, const Options& opt = {}) {
  return independent_integral(field, box, tf, background, ray.origin, ray.direction, opt);
}

}  // namespace vrv::independent
