#include "lib/transfer_export.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace vrv {
namespace {

// The colour g/tau.  Where tau = 0 a sample emits nothing whatever its colour, but a renderer
// interpolates the colour between rows: written 0 there, the table dips towards 0 beside it and
// charges a correct renderer a floor (the default scene's g = v, tau = v/2: colour 2, written 0
// at v = 0).  So where emission and extinction vanish together the colour is its limit within
// the segment, the ratio of their slopes; it stays 0 only where the scene emits without
// absorbing (inexpressible, flagged as emission_without_extinction) or both are 0 throughout.
double colour(const TransferSegment& s, double v, double g, double tau) {
  if (tau > 0) return g / tau;
  if (s.convention == Convention::opacity_color) return s.second(v);
  if (g == 0 && s.first.slope != 0 && s.second.slope != 0) return s.first.slope / s.second.slope;
  return 0;
}

TransferRow row(const TransferSegment& s, double v, double L) {
  const double g = s.g(v), tau = s.tau(v);
  return {v, g, tau, -std::expm1(-tau * L), colour(s, v, g, tau)};
}

bool same(const TransferRow& a, const TransferRow& b) {
  return a.value == b.value && a.emission == b.emission && a.extinction == b.extinction && a.color == b.color;
}

// The constant tail beyond an end has no colour of its own where it does not absorb: it takes the
// colour of the segment it continues, as a renderer clamping to the end row would.
TransferRow tail_row(const TransferFunction& tf, double outside, double end, double inside, double L) {
  TransferRow r = row(tf.segment(outside), end, L);
  if (r.extinction == 0) r.color = row(tf.segment(inside), end, L).color;
  return r;
}

nlohmann::ordered_json points(const std::vector<ControlPoint>& p) {
  auto j = nlohmann::ordered_json::array();
  for (const auto& c : p) j.push_back({c.v, c.y});
  return j;
}

}  // namespace

std::vector<TransferRow> tabulate_transfer(const TransferFunction& tf, double L, int per_segment) {
  if (!(L > 0) || !std::isfinite(L))
    throw std::invalid_argument(fmt::format("--unit-distance: must be positive and finite, got {}", L));
  if (per_segment < 1) throw std::invalid_argument("--table-points: must be at least 1");
  const auto& b = tf.breakpoints();
  std::vector<TransferRow> rows;
  auto push = [&](const TransferRow& r) {
    if (rows.empty() || !same(rows.back(), r)) rows.push_back(r);
  };
  if (b.empty()) return rows;
  // Left limit at the first breakpoint (the constant tail below it).
  push(tail_row(tf, b.front() - 1, b.front(), b.size() > 1 ? 0.5 * (b[0] + b[1]) : b.front(), L));
  for (std::size_t s = 0; s + 1 < b.size(); ++s) {
    const TransferSegment seg = tf.segment(0.5 * (b[s] + b[s + 1]));
    for (int k = 0; k <= per_segment; ++k) {
      const double v = k == per_segment ? b[s + 1] : b[s] + (b[s + 1] - b[s]) * k / per_segment;
      push(row(seg, v, L));
    }
  }
  // Right limit at the last breakpoint.
  push(tail_row(tf, b.back() + 1, b.back(), b.size() > 1 ? 0.5 * (b[b.size() - 2] + b.back()) : b.back(), L));
  return rows;
}

std::string transfer_csv(const std::vector<TransferRow>& rows) {
  std::string out = "value,emission,extinction,opacity,color\n";
  for (const auto& r : rows)
    out += fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", r.value, r.emission, r.extinction,
                       r.opacity, r.color);
  return out;
}

nlohmann::ordered_json transfer_json(const TransferFunction& tf, double unit_distance, int per_segment) {
  nlohmann::ordered_json j;
  const bool oc = tf.convention() == Convention::opacity_color;
  const double L = oc ? tf.unit_length() : unit_distance;
  const auto rows = tabulate_transfer(tf, L, per_segment);
  j["convention"] = "opacity per unit distance and colour";
  j["unit_distance"] = L;
  j["alpha_at_sample_distance"] = "1 - (1 - opacity)^(H / unit_distance) for a sample standing for distance H";
  j["emitted_per_sample"] = "color * alpha (straight colour; premultiplied: color * alpha is what is stored)";
  j["between_points"] = "linear in the scalar value; constant beyond the first and last points";
  j["scalar_range"] = {tf.breakpoints().front(), tf.breakpoints().back()};
  if (oc) {
    j["exact"] = true;
    j["opacity"] = points(tf.first().points());
    j["color"] = points(tf.second().points());
  } else {
    j["exact"] = false;
    auto op = nlohmann::ordered_json::array(), co = nlohmann::ordered_json::array();
    for (const auto& r : rows) {
      op.push_back({r.value, r.opacity});
      co.push_back({r.value, r.color});
    }
    j["opacity"] = op;
    j["color"] = co;
    // How far linear interpolation between rows is from the true opacity and colour.
    double gap_a = 0, gap_c = 0;
    for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
      if (rows[i].value == rows[i + 1].value) continue;  // a jump
      const double v = 0.5 * (rows[i].value + rows[i + 1].value);
      const TransferRow mid = row(tf.segment(v), v, L);
      gap_a = std::max(gap_a, std::abs(mid.opacity - 0.5 * (rows[i].opacity + rows[i + 1].opacity)));
      gap_c = std::max(gap_c, std::abs(mid.color - 0.5 * (rows[i].color + rows[i + 1].color)));
    }
    j["max_interpolation_error"] = {{"opacity", gap_a}, {"color", gap_c}};
  }
  bool inexpressible = false;
  for (const auto& r : rows) inexpressible |= r.extinction == 0 && r.emission > 0;
  j["emission_without_extinction"] = inexpressible;
  return j;
}

}  // namespace vrv
