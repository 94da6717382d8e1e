// The speed-vs-error study's own computations: the Pareto front and the cheapest configuration
// reaching a target.  (The study itself runs, --quick, as the CTest study.speed-vs-error.quick.)
#include <gtest/gtest.h>

#include "studies/speed-vs-error/speed_vs_error.h"

namespace vrv {
namespace {

TEST(SpeedVsError, ParetoFrontKeepsOnlyUndominatedPoints) {
  // (cost, error): b dominates a; c and d trade off; e equals d (both kept); f is worse than d.
  const std::vector<double> cost{2, 1, 0.5, 3, 3, 4};
  const std::vector<double> error{1e-3, 1e-4, 1e-2, 1e-6, 1e-6, 1e-5};
  const std::vector<bool> front = pareto_front(cost, error);
  EXPECT_EQ(front, (std::vector<bool>{false, true, true, true, true, false}));
}

TEST(SpeedVsError, ParetoFrontOfOnePointAndOfNone) {
  EXPECT_EQ(pareto_front({1.0}, {1.0}), std::vector<bool>{true});
  EXPECT_TRUE(pareto_front({}, {}).empty());
}

TEST(SpeedVsError, CheapestReachingPicksLeastTimeUnderTarget) {
  std::vector<SpeedErrorPoint> pts(4);
  pts[0] = {"alpha", 0.1, 5e-3, 1e-3, 0, 1e-6, 20};
  pts[1] = {"alpha", 0.01, 5e-5, 1e-5, 0, 1e-5, 200};
  pts[2] = {"alpha", 0.001, 5e-7, 1e-7, 0, 1e-4, 2000};
  pts[3] = {"riemann", 0.001, 2e-3, 1e-3, 0, 5e-5, 2000};
  EXPECT_EQ(cheapest_reaching(pts, "alpha", 1e-3), std::optional<std::size_t>(1));
  EXPECT_EQ(cheapest_reaching(pts, "alpha", 1e-6), std::optional<std::size_t>(2));
  EXPECT_EQ(cheapest_reaching(pts, "alpha", 1e-9), std::nullopt);
  EXPECT_EQ(cheapest_reaching(pts, "riemann", 1e-3), std::nullopt);
  EXPECT_EQ(cheapest_reaching(pts, "moreland", 1.0), std::nullopt);
}

}  // namespace
}  // namespace vrv
