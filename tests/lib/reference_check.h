#pragma once
// The reference integrator against the independent long-double reference (independent_reference.h),
// ray by ray: the transfer functions (a)-(e), the random rays, and the check that runs each vrv
// integration in a forked child with a CPU-time limit (POSIX), so a runaway integration fails its
// ray instead of hanging, while the long-double references run on all cores.  For every ray:
// |vrv - independent| <= error_estimate + 1e-16 (the estimate is honest), the estimate meets the
// tolerance, and the value is finite.  Shared by the tests of the integrator, the grid field and
// the transfer function (and the oracle's own tests).
#include <gtest/gtest.h>

#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iomanip>
#include <iostream>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

#include "analytic/marschner_lobb.h"
#include "lib/reference_integrator.h"
#include "lib/scene.h"
#include "tests/lib/independent_reference.h"

namespace vrv::reference_check {

namespace ind = vrv::independent;
using LD = long double;

inline constexpr double kTol = 1e-12;
inline constexpr double kSlack = 1e-16;  // absolute slack on top of the error estimate

inline const Box kBox{};  // [-1, 1]^3

inline PiecewiseLinear curve(std::vector<ControlPoint> p) { return PiecewiseLinear(std::move(p)); }

inline TransferFunction scaled_extinction(const std::vector<ControlPoint>& emission,
                                          std::vector<ControlPoint> extinction, double scale) {
  for (auto& p : extinction) p.y *= scale;
  return TransferFunction::emission_extinction(curve(emission), curve(extinction));
}

inline const std::vector<ControlPoint> kEmissionB{{0, 0}, {0.3, 0.1}, {0.5, 1.0}, {0.7, 0.2}, {1, 0.5}};
inline const std::vector<ControlPoint> kExtinctionB{{0, 0}, {0.4, 0.8}, {1, 0.3}};

// (a) proportional: g = 2 tau.
inline TransferFunction tf_proportional() {
  return TransferFunction::emission_extinction(curve({{0, 0}, {1, 1}}), curve({{0, 0}, {1, 0.5}}));
}
// (b) not proportional.
inline TransferFunction tf_general() { return scaled_extinction(kEmissionB, kExtinctionB, 1); }
// (c) steps: jumps in g and tau at 0.5.
inline TransferFunction tf_step() {
  return TransferFunction::emission_extinction(curve({{0, 0}, {0.5, 0}, {0.5, 1}, {1, 1}}),
                                               curve({{0, 0.1}, {0.5, 0.1}, {0.5, 2}, {1, 2}}));
}
// (d) a narrow peak at 0.5.
inline TransferFunction tf_peak() {
  return TransferFunction::emission_extinction(
      curve({{0, 0}, {0.49, 0}, {0.5, 5}, {0.51, 0}, {1, 0}}),
      curve({{0, 0}, {0.49, 0}, {0.5, 3}, {0.51, 0}, {1, 0}}));
}
// (e) the renderer's opacity / colour convention.
inline TransferFunction tf_opacity() {
  return TransferFunction::opacity_color(curve({{0, 0}, {1, 0.3}}), curve({{0, 1}, {1, 0.2}}),
                                         0.05);
}

struct RaySpec {
  Vec3 origin;
  Vec3 direction;  // as given (not normalised)
};

inline std::string describe(const RaySpec& r) {
  std::ostringstream s;
  s << std::setprecision(17) << "origin (" << r.origin.x() << ", " << r.origin.y() << ", "
    << r.origin.z() << ") direction (" << r.direction.x() << ", " << r.direction.y() << ", "
    << r.direction.z() << ")";
  return s.str();
}

// Uniform in [0, 1) from the top 53 bits (portable, unlike std:: distributions).
inline double uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1p-53; }

// Origins on the sphere of radius 3 aimed at random points of the box.
inline std::vector<RaySpec> random_rays(int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<RaySpec> rays;
  for (int i = 0; i < count; ++i) {
    const double z = 2 * uniform(rng) - 1;
    const double phi = 2 * std::numbers::pi * uniform(rng);
    const double s = std::sqrt(1 - z * z);
    const Vec3 origin = 3 * Vec3(s * std::cos(phi), s * std::sin(phi), z);
    const Vec3 target(2 * uniform(rng) - 1, 2 * uniform(rng) - 1, 2 * uniform(rng) - 1);
    rays.push_back({origin, target - origin});
  }
  return rays;
}

struct Stats {
  int rays = 0;
  long evaluations = 0;
  double max_error_estimate = 0;
  double max_difference = 0;
  double max_ratio = 0;  // |difference| / (estimate + slack)
  int dishonest = 0;
  int over_tolerance = 0;
  int timeouts = 0;
  double max_seconds = 0;  // slowest vrv ray (wall clock, including the fork)
  double mean_evaluations() const { return rays ? static_cast<double>(evaluations) / rays : 0; }
};

// Runs one vrv integration in a child process with a CPU-time limit, so that a runaway
// integration fails its case instead of hanging the whole test binary.  nullopt on timeout.
// A healthy ray takes well under a millisecond; the limit only guards against runaway loops
// (the time per ray is reported, not asserted).
inline constexpr double kDeadlineSeconds = 2;

inline std::optional<ReferenceResult> guarded(const std::function<ReferenceResult()>& fn) {
  static_assert(std::is_trivially_copyable_v<ReferenceResult>);
  int fds[2];
  if (pipe(fds) != 0) return fn();
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    return fn();
  }
  if (pid == 0) {
    close(fds[0]);
    itimerval limit{};
    limit.it_value.tv_sec = static_cast<time_t>(kDeadlineSeconds);
    limit.it_value.tv_usec =
        static_cast<suseconds_t>(1e6 * (kDeadlineSeconds - static_cast<double>(limit.it_value.tv_sec)));
    setitimer(ITIMER_VIRTUAL, &limit, nullptr);  // SIGVTALRM ends the child
    const ReferenceResult r = fn();
    const char* p = reinterpret_cast<const char*>(&r);
    std::size_t left = sizeof r;
    while (left > 0) {
      const ssize_t n = write(fds[1], p, left);
      if (n <= 0) _exit(2);
      p += n;
      left -= static_cast<std::size_t>(n);
    }
    _exit(0);
  }
  close(fds[1]);
  ReferenceResult r;
  char* p = reinterpret_cast<char*>(&r);
  std::size_t got = 0;
  while (got < sizeof r) {
    const ssize_t n = read(fds[0], p + got, sizeof r - got);
    if (n <= 0) break;
    got += static_cast<std::size_t>(n);
  }
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (got != sizeof r || !WIFEXITED(status) || WEXITSTATUS(status) != 0) return std::nullopt;
  return r;
}

// The independent reference for many rays, on all cores.
inline std::vector<ind::Result> references(const ind::FieldLD& ref_field, const TransferFunction& tf,
                                           LD background, const std::vector<RaySpec>& rays,
                                           const Box& box = kBox) {
  std::vector<ind::Result> out(rays.size());
  const std::size_t workers =
      std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, rays.size() ? rays.size() : 1);
  std::vector<std::thread> threads;
  for (std::size_t w = 0; w < workers; ++w)
    threads.emplace_back([&, w] {
      for (std::size_t i = w; i < rays.size(); i += workers)
        out[i] = ind::independent_integral(ref_field, box, tf, background, rays[i].origin,
                                           rays[i].direction);
    });
  for (auto& t : threads) t.join();
  return out;
}

// One ray: the vrv result against the independent reference `ref`.
inline std::optional<ReferenceResult> compare(const std::function<ReferenceResult()>& run,
                                              const ind::Result& ref, const RaySpec& spec,
                                              Stats* stats = nullptr, double tol = kTol) {
  const auto start = std::chrono::steady_clock::now();
  const std::optional<ReferenceResult> result = guarded(run);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (stats) stats->max_seconds = std::max(stats->max_seconds, seconds);
  if (!result) {
    ADD_FAILURE() << "vrv did not finish within " << kDeadlineSeconds << " s of CPU time: "
                  << describe(spec);
    if (stats) ++stats->timeouts;
    return std::nullopt;
  }
  const ReferenceResult& r = *result;
  const double diff = static_cast<double>(std::abs(static_cast<LD>(r.value) - ref.value));
  std::ostringstream msg;
  msg << std::setprecision(17) << describe(spec) << "\n  vrv value " << r.value
      << "  error estimate " << r.error_estimate << "\n  independent "
      << static_cast<double>(ref.value) << "  difference " << diff << "  evaluations "
      << r.evaluations << "  time " << seconds << " s";
  EXPECT_TRUE(std::isfinite(r.value)) << msg.str();
  EXPECT_TRUE(std::isfinite(r.error_estimate)) << msg.str();
  EXPECT_EQ(r.hit, ref.hit) << msg.str();
  EXPECT_LE(diff, r.error_estimate + kSlack) << "estimate not honest: " << msg.str();
  EXPECT_LE(r.error_estimate, tol) << "tolerance missed: " << msg.str();
  if (stats) {
    ++stats->rays;
    stats->evaluations += r.evaluations;
    stats->max_error_estimate = std::max(stats->max_error_estimate, r.error_estimate);
    stats->max_difference = std::max(stats->max_difference, diff);
    stats->max_ratio = std::max(stats->max_ratio, diff / (r.error_estimate + kSlack));
    if (diff > r.error_estimate + kSlack) ++stats->dishonest;
    if (r.error_estimate > tol) ++stats->over_tolerance;
  }
  return r;
}

template <class F>
inline std::optional<ReferenceResult> check_ray(const F& field, const ind::FieldLD& ref_field,
                                                const TransferFunction& tf, double background,
                                                const RaySpec& spec, ind::Result* ref_out = nullptr) {
  // (The reference runs first, in this process; vrv then runs in a guarded child.)
  const ind::Result ref =
      ind::independent_integral(ref_field, kBox, tf, background, spec.origin, spec.direction);
  if (ref_out) *ref_out = ref;
  return compare(
      [&] {
        return integrate_reference(field, kBox, tf, background,
                                   make_ray(spec.origin, spec.direction), {kTol});
      },
      ref, spec);
}

inline void report(const std::string& name, const Stats& s) {
  std::cout << std::setprecision(4) << "[ " << name << " ] rays " << s.rays
            << ", mean evaluations " << s.mean_evaluations() << ", max estimate "
            << s.max_error_estimate << ", max |diff| " << s.max_difference
            << ", max |diff|/(estimate+1e-16) " << s.max_ratio << "; not honest " << s.dishonest
            << ", estimate > tol " << s.over_tolerance << ", timeouts " << s.timeouts
            << ", slowest ray " << 1e3 * s.max_seconds << " ms\n";
  ::testing::Test::RecordProperty("mean_evaluations", std::to_string(s.mean_evaluations()));
  ::testing::Test::RecordProperty("max_abs_difference", std::to_string(s.max_difference));
}

template <class F>
inline Stats check_rays(const std::string& name, const F& field, const ind::FieldLD& ref_field,
                        const TransferFunction& tf, double background, const std::vector<RaySpec>& rays) {
  Stats stats;
  const std::vector<ind::Result> refs = references(ref_field, tf, background, rays);
  for (std::size_t i = 0; i < rays.size(); ++i)
    compare(
        [&] {
          return integrate_reference(field, kBox, tf, background,
                                     make_ray(rays[i].origin, rays[i].direction), {kTol});
        },
        refs[i], rays[i], &stats);
  report(name, stats);
  return stats;
}

inline const MarschnerLobb kML{6, 0.25};
inline const ind::MarschnerLobbLD kMLRef{6, 0.25L};

}  // namespace vrv::reference_check
