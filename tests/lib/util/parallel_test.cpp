// Results do not depend on the number of threads.
#include "lib/util/parallel.h"

#include <atomic>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include "lib/discrete_raycast.h"
#include "lib/reference_integrator.h"
#include "lib/scene_file.h"
#include "lib/util/ranks.h"
#include "lib/util/task_rows.h"

namespace vrv {
namespace {

std::vector<double> row_of_values(int threads, bool reference) {
  const ThreadLimit limit(threads);
  const Scene scene = default_scene();
  DiscreteConfig config;
  config.rule = SegmentRule::trapezoid;
  constexpr int n = 64;
  std::vector<double> out(n);
  parallel_for_index(n, [&](long i) {
    const Ray ray = make_ray(Vec3(-3, -1 + (i + 0.5) * 2.0 / n, 0.1), Vec3(1, 0.01, 0.02));
    out[i] = reference ? integrate_reference(scene, ray).value : discrete_raycast(scene, ray, config).value;
  });
  return out;
}

TEST(Parallel, OneAndTwoThreadsGiveBitwiseIdenticalResults) {
  for (bool reference : {true, false}) {
    const auto one = row_of_values(1, reference);
    const auto two = row_of_values(2, reference);
    ASSERT_EQ(one.size(), two.size());
    for (std::size_t i = 0; i < one.size(); ++i) EXPECT_EQ(one[i], two[i]) << i;  // bitwise
  }
}

// An image loop shares its blocks over MPI ranks only outside parallel tasks (lib/util/ranks.h),
// where every rank meets the loops in the same order; a loop inside a task is a task's own.
TEST(Parallel, TasksKnowTheyAreInsideAParallelLoop) {
  EXPECT_FALSE(inside_parallel_task());
  std::atomic<int> inside{0}, nested{0};
  parallel_for_index(100, [&](long) {
    inside += inside_parallel_task();
    parallel_for_index(3, [&](long) { nested += inside_parallel_task(); });
  });
  EXPECT_EQ(inside.load(), 100);
  EXPECT_EQ(nested.load(), 300);
  EXPECT_FALSE(inside_parallel_task());
  // A run of one process never shares, whatever asks for it.
  const PixelSharing sharing;
  EXPECT_EQ(rank_count(), 1);
  EXPECT_FALSE(pixels_shared_over_ranks());
}

// task_rows (lib/util/task_rows.h): each task fills its own row, inside a parallel task (so the
// image loops a task runs stay its own), for one thread or two alike; empty tables are fine.
TEST(Parallel, TaskRowsFillEachRowInsideATask) {
  const auto fill = [](long task, std::span<double> row) {
    for (std::size_t j = 0; j < row.size(); ++j)
      row[j] = static_cast<double>(task) + 0.001 * static_cast<double>(j) + inside_parallel_task();
  };
  std::vector<std::vector<double>> tables;
  for (int threads : {1, 2}) {
    const ThreadLimit limit(threads);
    tables.push_back(task_rows(7, 5, fill));
  }
  ASSERT_EQ(tables[0].size(), 35u);
  EXPECT_EQ(tables[0], tables[1]);
  EXPECT_EQ(tables[0][3 * 5 + 2], 3 + 0.002 + 1);
  EXPECT_TRUE(task_rows(0, 5, fill).empty());
  EXPECT_TRUE(task_rows(4, 0, fill).empty());
}

TEST(Parallel, TaskValuesHoldEachTasksValueInOrder) {
  struct Value {
    long task;
    bool flag;  // padding after it: values are exchanged as bytes under MPI
    double inside;
  };
  const auto f = [](long i) { return Value{i, i % 3 == 0, static_cast<double>(inside_parallel_task())}; };
  for (int threads : {1, 2}) {
    const ThreadLimit limit(threads);
    const std::vector<Value> v = task_values(1000, f);
    ASSERT_EQ(v.size(), 1000u);
    for (long i = 0; i < 1000; ++i) {
      EXPECT_EQ(v[i].task, i);
      EXPECT_EQ(v[i].flag, i % 3 == 0);
      EXPECT_EQ(v[i].inside, 1.0);
    }
  }
  EXPECT_TRUE(task_values(0, f).empty());
  EXPECT_EQ(task_block(10), 1);      // a few costly rays: one a block
  EXPECT_EQ(task_block(320), 20);
  EXPECT_EQ(task_block(100000), 64);
}

TEST(Ranks, OneProcessCountsItsWorkAndReducesToItself) {
  // Without MPI ranks (or outside PixelSharing) the reductions are the value itself.
  EXPECT_TRUE(counts_on_this_rank());
  const PixelSharing sharing;
  EXPECT_EQ(sum_over_ranks(41), 41);
  EXPECT_EQ(max_over_ranks(2.5), 2.5);
  EXPECT_TRUE(std::isnan(max_over_ranks(std::numeric_limits<double>::quiet_NaN())));
}

}  // namespace
}  // namespace vrv
