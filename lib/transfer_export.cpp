#include "lib/transfer_export.h"

#include <algorithm>
#include <array>
#include <utility>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "lib/option_error.h"

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

namespace {

void check_table_options(double L, int per_segment) {
  if (!(L > 0) || !std::isfinite(L))
    throw OptionError(Option::unit_distance, fmt::format("must be positive and finite, got {}", L));
  if (per_segment < 1) throw OptionError(Option::table_points, "must be at least 1");
}

// Every row at breakpoints `b` (a refinement of tf's own, so tf is affine between them), repeats
// included: the tail's left limit, per_segment + 1 rows a segment, the tail's right limit.
std::vector<TransferRow> rows_at(const TransferFunction& tf, const std::vector<double>& b, double L, int per_segment) {
  std::vector<TransferRow> rows;
  if (b.empty()) return rows;
  constexpr double inf = std::numeric_limits<double>::infinity();
  const double first_inside = b.size() > 1 ? value_inside(b[0], b[1]) : b.front();
  rows.push_back(tail_row(tf, value_inside(-inf, b.front()), b.front(), first_inside, L));
  for (std::size_t s = 0; s + 1 < b.size(); ++s) {
    const TransferSegment seg = tf.segment(value_inside(b[s], b[s + 1]));
    for (int k = 0; k <= per_segment; ++k) {
      const double v = k == per_segment ? b[s + 1] : b[s] + (b[s + 1] - b[s]) * k / per_segment;
      rows.push_back(row(seg, v, L));
    }
  }
  const double last_inside = b.size() > 1 ? value_inside(b[b.size() - 2], b.back()) : b.back();
  rows.push_back(tail_row(tf, value_inside(b.back(), inf), b.back(), last_inside, L));
  return rows;
}

// The largest gap between linear interpolation of the rows and the true opacity and colour, at
// the rows' midpoints (jumps skipped).
std::pair<double, double> interpolation_gaps(const TransferFunction& tf, const std::vector<TransferRow>& rows, double L) {
  double gap_a = 0, gap_c = 0;
  for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
    if (rows[i].value == rows[i + 1].value) continue;  // a jump
    const double v = 0.5 * (rows[i].value + rows[i + 1].value);
    const TransferRow mid = row(tf.segment(v), v, L);
    gap_a = std::max(gap_a, std::abs(mid.opacity - 0.5 * (rows[i].opacity + rows[i + 1].opacity)));
    gap_c = std::max(gap_c, std::abs(mid.color - 0.5 * (rows[i].color + rows[i + 1].color)));
  }
  return {gap_a, gap_c};
}

bool emits_without_extinction(const std::vector<TransferRow>& rows) {
  bool inexpressible = false;
  for (const auto& r : rows) inexpressible |= r.extinction == 0 && r.emission > 0;
  return inexpressible;
}

// What every transfer_function.json says first.
nlohmann::ordered_json convention_json(double L, const std::vector<double>& breakpoints) {
  nlohmann::ordered_json j;
  j["convention"] = "opacity per unit distance and colour";
  j["unit_distance"] = L;
  j["alpha_at_sample_distance"] = "1 - (1 - opacity)^(H / unit_distance) for a sample standing for distance H";
  j["emitted_per_sample"] = "color * alpha (straight colour; premultiplied: color * alpha is what is stored)";
  j["between_points"] = "linear in the scalar value; constant beyond the first and last points";
  j["scalar_range"] = {breakpoints.front(), breakpoints.back()};
  return j;
}

// The three channels' colour points [v, r, g, b] when they sit at the same values (an RGB
// opacity/colour scene's `color` table); empty otherwise.
nlohmann::ordered_json shared_colour_points(const ColorChannels& color) {
  const auto& r = color.transfer[0].second().points();
  auto j = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < r.size(); ++i) {
    nlohmann::ordered_json p = {r[i].v};
    for (const TransferFunction& tf : color.transfer) {
      const auto& q = tf.second().points();
      if (q.size() != r.size() || q[i].v != r[i].v) return nlohmann::ordered_json::array();
      p.push_back(q[i].y);
    }
    j.push_back(p);
  }
  return j;
}

}  // namespace

std::vector<TransferRow> tabulate_transfer(const TransferFunction& tf, double L, int per_segment) {
  check_table_options(L, per_segment);
  std::vector<TransferRow> rows;
  for (const TransferRow& r : rows_at(tf, tf.breakpoints(), L, per_segment))
    if (rows.empty() || !same(rows.back(), r)) rows.push_back(r);
  return rows;
}

std::array<std::vector<TransferRow>, 3> tabulate_color_transfer(const ColorChannels& color, double L,
                                                                int per_segment) {
  check_table_options(L, per_segment);
  std::vector<double> b;
  for (const TransferFunction& tf : color.transfer) b.insert(b.end(), tf.breakpoints().begin(), tf.breakpoints().end());
  std::sort(b.begin(), b.end());
  b.erase(std::unique(b.begin(), b.end()), b.end());
  std::array<std::vector<TransferRow>, 3> all, rows;
  for (int c = 0; c < 3; ++c) all[c] = rows_at(color.transfer[c], b, L, per_segment);
  // A row goes only where some channel changes, so that row i is the same value in every table.
  for (std::size_t i = 0; i < all[0].size(); ++i) {
    bool repeat = !rows[0].empty();
    for (int c = 0; c < 3 && repeat; ++c) repeat = same(rows[c].back(), all[c][i]);
    if (repeat) continue;
    for (int c = 0; c < 3; ++c) rows[c].push_back(all[c][i]);
  }
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
  const bool oc = tf.convention() == Convention::opacity_color;
  const double L = oc ? tf.unit_length() : unit_distance;
  const auto rows = tabulate_transfer(tf, L, per_segment);
  nlohmann::ordered_json j = convention_json(L, tf.breakpoints());
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
    const auto [gap_a, gap_c] = interpolation_gaps(tf, rows, L);
    j["max_interpolation_error"] = {{"opacity", gap_a}, {"color", gap_c}};
  }
  j["emission_without_extinction"] = emits_without_extinction(rows);
  return j;
}

std::string color_transfer_csv(const std::array<std::vector<TransferRow>, 3>& rows) {
  std::string out = "value,emission_r,emission_g,emission_b,extinction,opacity,color_r,color_g,color_b\n";
  for (std::size_t i = 0; i < rows[0].size(); ++i) {
    const TransferRow &r = rows[0][i], &g = rows[1][i], &b = rows[2][i];
    out += fmt::format("{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", r.value,
                       r.emission, g.emission, b.emission, r.extinction, r.opacity, r.color, g.color, b.color);
  }
  return out;
}

nlohmann::ordered_json color_transfer_json(const ColorChannels& color, double unit_distance, int per_segment) {
  const TransferFunction& red = color.transfer[0];
  const bool oc = red.convention() == Convention::opacity_color;
  const double L = oc ? red.unit_length() : unit_distance;
  const auto rows = tabulate_color_transfer(color, L, per_segment);
  std::vector<double> range = red.breakpoints();
  for (const TransferFunction& tf : color.transfer) {
    range.front() = std::min(range.front(), tf.breakpoints().front());
    range.back() = std::max(range.back(), tf.breakpoints().back());
  }
  nlohmann::ordered_json j = convention_json(L, range);
  j["channels"] = {"R", "G", "B"};
  const nlohmann::ordered_json shared = oc ? shared_colour_points(color) : nlohmann::ordered_json::array();
  if (!shared.empty()) {
    j["exact"] = true;
    j["opacity"] = points(red.first().points());
    j["color"] = shared;
  } else {
    j["exact"] = false;
    auto op = nlohmann::ordered_json::array(), co = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < rows[0].size(); ++i) {
      op.push_back({rows[0][i].value, rows[0][i].opacity});  // one extinction: every channel's opacity
      co.push_back({rows[0][i].value, rows[0][i].color, rows[1][i].color, rows[2][i].color});
    }
    j["opacity"] = op;
    j["color"] = co;
    double gap_a = 0, gap_c = 0;
    for (int c = 0; c < 3; ++c) {
      const auto [a, g] = interpolation_gaps(color.transfer[c], rows[c], L);
      gap_a = std::max(gap_a, a), gap_c = std::max(gap_c, g);
    }
    j["max_interpolation_error"] = {{"opacity", gap_a}, {"color", gap_c}};
  }
  bool inexpressible = false;
  for (const auto& r : rows) inexpressible |= emits_without_extinction(r);
  j["emission_without_extinction"] = inexpressible;
  return j;
}

}  // namespace vrv
