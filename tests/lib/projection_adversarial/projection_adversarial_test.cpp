// The projection references (lib/projection/) on adversarial rays with an independent mpmath truth
// (issue 26).  The rays, their fields and their truths come from make_projection_truth.py (same
// folder; how the truth is computed is documented there).  On every ray, every mode (xray,
// xray_classified, mip, mip_classified) and tolerances 1e-12 and 1e-8:
//   honest:     |value - truth| <= error_estimate, both finite;
//   not absurd: error_estimate <= max(100 max(|error|, floor), tol), floor the ray's double
//               precision floor: the field's own rounding eta (MIP) or eta x length (X-ray), times
//               the extinction's largest slope for the classified modes, or their sensitivity to a
//               field moved by -+eta where that is larger (a field at a jump's level);
//   position:   a MIP that does not call itself ambiguous reports the truth's first maximum: within
//               sqrt(2 (estimate + |error|) / |f''|) at a smooth maximum, within 1e-9 (1 + |t|) at
//               an end, a kink or a plateau's start;
//   tolerance:  the estimate is within tol wherever the floor is (else tolerance_met is false);
//   misses:     hit false, value 0.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "analytic/linear_ramp.h"
#include "analytic/marschner_lobb.h"
#include "lib/grid_field.h"
#include "lib/projection/projection_reference.h"
#include "lib/transfer_function.h"
#include "tests/lib/truth_lines.h"

namespace vrv {
namespace {

using test::hex_double;
long double long_double(const nlohmann::json& j) { return std::strtold(j.get<std::string>().c_str(), nullptr); }

struct TruthRay {
  nlohmann::json j;
  std::string cls, tag;
  Box box;
  Vec3 origin, direction;
  TransferFunction tf;
};

std::vector<TruthRay> load() {
  std::vector<TruthRay> out;
  for (nlohmann::json& j : test::truth_lines("tests/lib/projection_adversarial/projection_truth.jsonl")) {
    TruthRay r;
    r.cls = j["class"];
    r.tag = j["tag"];
    for (int a = 0; a < 3; ++a) {
      r.box.min[a] = j["box"]["min"][a].get<double>();
      r.box.max[a] = j["box"]["max"][a].get<double>();
    }
    r.origin = test::hex_vec3(j["origin"]);
    r.direction = test::hex_vec3(j["direction"]);
    std::vector<ControlPoint> pts;
    for (const auto& p : j["extinction"]) pts.push_back({p[0].get<double>(), p[1].get<double>()});
    r.tf = TransferFunction::emission_extinction(PiecewiseLinear(pts), PiecewiseLinear(pts));
    r.j = std::move(j);
    out.push_back(std::move(r));
  }
  return out;
}

// The grid of explicit node values (node layout): each node's index from its position.
GridField make_grid(const TruthRay& r) {
  const auto& f = r.j["field"];
  const GridField::Index3 n{f["resolution"][0].get<int>(), f["resolution"][1].get<int>(), f["resolution"][2].get<int>()};
  std::vector<double> nodes;
  for (const auto& v : f["nodes"]) nodes.push_back(hex_double(v));
  const Vec3 h = r.box.extent().cwiseQuotient(Vec3(n[0] - 1.0, n[1] - 1.0, n[2] - 1.0));
  const Interpolation interp = f["interpolation"] == "nearest" ? Interpolation::nearest : Interpolation::trilinear;
  return GridField(r.box, n, GridLayout::node, interp, [&](const Vec3& p) {
    int idx[3];
    for (int a = 0; a < 3; ++a) idx[a] = static_cast<int>(std::lround((p[a] - r.box.min[a]) / h[a]));
    return nodes[(static_cast<std::size_t>(idx[2]) * n[1] + idx[1]) * n[0] + idx[0]];
  });
}

template <class Fn>
auto with_field(const TruthRay& r, Fn&& fn) {
  const auto& f = r.j["field"];
  if (f["kind"] == "ml") return fn(MarschnerLobb{f["fM"].get<double>(), f["alpha"].get<double>()});
  if (f["kind"] == "ramp") {
    LinearRamp ramp;
    for (int a = 0; a < 3; ++a) ramp.gradient[a] = hex_double(f["gradient"][a]);
    ramp.offset = hex_double(f["offset"]);
    return fn(ramp);
  }
  return fn(make_grid(r));
}

struct Tally {
  int rays = 0, failures = 0;
  double worst_ratio = 0;  // estimate / max(|error|, floor)
};

constexpr ProjectionMode kModes[] = {ProjectionMode::xray, ProjectionMode::xray_classified, ProjectionMode::mip,
                                     ProjectionMode::mip_classified};

std::string truth_key(ProjectionMode m) { return std::string(projection_mode_name(m)); }

class ProjectionAdversarial : public ::testing::TestWithParam<double> {};

TEST_P(ProjectionAdversarial, HonestNotAbsurdAndFirstPosition) {
  const double tol = GetParam();
  const auto rays = load();
  ASSERT_GE(rays.size(), 30u);
  std::map<std::string, Tally> tally;
  for (const TruthRay& r : rays) {
    const Ray ray = make_ray(r.origin, r.direction);
    for (ProjectionMode mode : kModes) {
      const ProjectionResult res = with_field(r, [&](const auto& field) {
        return projection_reference(field, r.box, r.tf, ray, mode, {tol});
      });
      Tally& t = tally[r.cls + " " + truth_key(mode)];
      ++t.rays;
      const std::string what = fmt::format("[{} | {} | {} | tol {:g}]", r.cls, r.tag, truth_key(mode), tol);
      if (!r.j["hit"].get<bool>()) {
        EXPECT_FALSE(res.hit) << what;
        EXPECT_EQ(res.value, 0.0) << what;
        EXPECT_TRUE(std::isnan(res.position)) << what;
        continue;
      }
      ASSERT_TRUE(res.hit) << what;
      const long double truth = long_double(r.j[truth_key(mode)]);
      const long double error = static_cast<long double>(res.value) - truth;
      const double err = static_cast<double>(std::fabs(error));
      const double eta = r.j["eta"];
      const double length = r.j["length"];
      const double slope = is_classified(mode) ? r.j["tau_slope"].get<double>() : 1.0;
      double floor = slope * (is_mip(mode) ? eta : eta * length);
      if (is_classified(mode))  // a field at a jump's level: the truth moves by the jump under eta
        floor = std::max(floor, r.j[truth_key(mode) + "_sensitivity"].get<double>());
      const bool finite = std::isfinite(res.value) && std::isfinite(res.error_estimate);
      const bool honest = finite && std::fabs(error) <= static_cast<long double>(res.error_estimate);
      const double bound = std::max(100 * std::max(err, floor), tol);
      const bool not_absurd = finite && res.error_estimate <= bound;
      t.worst_ratio = std::max(t.worst_ratio, res.error_estimate / std::max(err, std::max(floor, 1e-300)));
      EXPECT_TRUE(honest) << what << " error " << err << " > estimate " << res.error_estimate << " (value "
                          << fmt::format("{:.17g}", res.value) << ", truth " << r.j[truth_key(mode)] << ")";
      EXPECT_TRUE(not_absurd) << what << " estimate " << res.error_estimate << " > " << bound << " (error " << err
                              << ", floor " << floor << ")";
      // Within the tolerance, unless double precision cannot reach it on this ray (a field at a
      // jump's level): then it must say so.
      if (floor < tol) EXPECT_LE(res.error_estimate, tol) << what;
      else EXPECT_FALSE(res.tolerance_met) << what;
      if (mode == ProjectionMode::mip && !res.ambiguous) {
        const long double pos = long_double(r.j["mip_position"]);
        const double curvature = r.j["mip_curvature"];
        const double t_abs = std::fabs(static_cast<double>(pos));
        double within = 1e-9 * (1 + t_abs);
        if (curvature > 0) within += std::sqrt(2 * (res.error_estimate + err) / curvature);
        EXPECT_LE(std::fabs(static_cast<long double>(res.position) - pos), within)
            << what << " position " << fmt::format("{:.17g}", res.position) << " truth " << r.j["mip_position"];
      }
      if (!(honest && not_absurd)) ++t.failures;
    }
  }
  std::string table = fmt::format("| class mode (tol {:g}) | rays | failures | worst estimate / max(error, floor) |\n", tol);
  for (const auto& [k, t] : tally) table += fmt::format("| {} | {} | {} | {:.3g} |\n", k, t.rays, t.failures, t.worst_ratio);
  std::cout << table;
}

INSTANTIATE_TEST_SUITE_P(Tolerances, ProjectionAdversarial, ::testing::Values(1e-12, 1e-8));

// Exact ties and plateaus report the first maximum, ambiguous or not (the mirror peaks of
// Marschner-Lobb 1e-14 apart are flagged ambiguous at their estimate of 1.2e-14, the field's
// rounding through the proxy; the position check above then does not apply).
TEST(ProjectionAdversarialTies, ExactTiesReportTheFirst) {
  for (const TruthRay& r : load()) {
    if (r.cls != "two_peaks" && r.cls != "plateau") continue;
    if (r.tag.find("exact") == std::string::npos && r.cls != "plateau") continue;
    const Ray ray = make_ray(r.origin, r.direction);
    const ProjectionResult res = with_field(r, [&](const auto& field) {
      return projection_reference(field, r.box, r.tf, ray, ProjectionMode::mip, {1e-12});
    });
    const double pos = std::strtod(r.j["mip_position"].get<std::string>().c_str(), nullptr);
    EXPECT_NEAR(res.position, pos, 1e-9 * (1 + std::abs(pos))) << r.tag;
  }
}

}  // namespace
}  // namespace vrv
