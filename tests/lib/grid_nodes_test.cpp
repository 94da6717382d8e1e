// Node values in their stored type: every kind reads back, bit for bit, the double the mapping
// gives its sample (so a grid over int16 samples integrates exactly as the same grid over
// doubles), at the stored type's size.
#include "lib/grid_nodes.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <typeinfo>

#include "lib/grid_field.h"

namespace vrv {
namespace {

// The type's extremes, zero and a spread of values in between.
template <class T>
std::vector<T> samples_of() {
  std::vector<T> s{std::numeric_limits<T>::lowest(), std::numeric_limits<T>::max(), T(0), T(1)};
  std::mt19937_64 rng(11);
  for (int n = 0; n < 60; ++n) {
    if constexpr (std::is_floating_point_v<T>)
      s.push_back(static_cast<T>(std::uniform_real_distribution<double>(-1e4, 1e4)(rng)));
    else
      s.push_back(static_cast<T>(std::uniform_int_distribution<std::int64_t>(
          std::numeric_limits<T>::lowest(), std::numeric_limits<T>::max())(rng)));
  }
  return s;
}

std::vector<SampleMap> maps() {
  SampleMap raw;
  SampleMap rescale{true, -0.37, 1024.5};
  SampleMap window{false, 1, 0, true, -100, 3000};
  SampleMap both{true, 0.25, -7, true, -50, 50};
  return {raw, rescale, window, both};
}

template <class T>
void expect_reads_as_mapped(GridNodes::Kind kind, std::size_t table_entries) {
  for (const SampleMap& map : maps()) {
    const std::vector<T> s = samples_of<T>();
    const GridNodes nodes(VolumeSamples(s), map);
    EXPECT_EQ(nodes.kind(), kind);
    ASSERT_EQ(nodes.size(), s.size());
    EXPECT_EQ(nodes.bytes(), s.size() * sizeof(T) + table_entries * sizeof(double));
    for (std::size_t n = 0; n < s.size(); ++n)
      EXPECT_EQ(nodes[n], map(static_cast<double>(s[n]))) << n << " of " << typeid(T).name();
  }
}

TEST(GridNodes, EveryKindReadsTheMappedSampleBitForBitAtItsOwnSize) {
  expect_reads_as_mapped<std::uint8_t>(GridNodes::Kind::code8, 256);
  expect_reads_as_mapped<std::int8_t>(GridNodes::Kind::code8, 256);
  expect_reads_as_mapped<std::uint16_t>(GridNodes::Kind::code16, 65536);
  expect_reads_as_mapped<std::int16_t>(GridNodes::Kind::code16, 65536);
  expect_reads_as_mapped<std::uint32_t>(GridNodes::Kind::u32, 0);
  expect_reads_as_mapped<std::int32_t>(GridNodes::Kind::i32, 0);
  expect_reads_as_mapped<float>(GridNodes::Kind::f32, 0);
  expect_reads_as_mapped<double>(GridNodes::Kind::f64, 0);
}

TEST(GridNodes, MappedChangesOnlyTheTableOfCodedSamples) {
  const auto fn = [](double v) { return v * v - 3; };
  const std::vector<std::int16_t> s = samples_of<std::int16_t>();
  const GridNodes nodes(VolumeSamples(s), maps()[1]);
  const GridNodes m = nodes.mapped(fn);
  EXPECT_EQ(m.kind(), GridNodes::Kind::code16);
  EXPECT_EQ(m.bytes(), nodes.bytes());
  for (std::size_t n = 0; n < s.size(); ++n) {
    EXPECT_EQ(m[n], fn(nodes[n]));
    EXPECT_EQ(nodes[n], maps()[1](s[n]));  // the original is untouched
  }
  // 32-bit samples become doubles under an arbitrary function.
  const GridNodes f(VolumeSamples(samples_of<float>()), maps()[2]);
  const GridNodes mf = f.mapped(fn);
  EXPECT_EQ(mf.kind(), GridNodes::Kind::f64);
  for (std::size_t n = 0; n < f.size(); ++n) EXPECT_EQ(mf[n], fn(f[n]));
}

// A grid over uint16 samples is the grid over their mapped doubles, bit for bit, everywhere the
// reference and the raycaster look.
TEST(GridNodes, AGridOverStoredSamplesIsTheGridOverTheirDoubles) {
  const GridField::Index3 n{6, 5, 4};
  std::vector<std::uint16_t> s;
  std::mt19937_64 rng(5);
  for (int i = 0; i < n[0] * n[1] * n[2]; ++i) s.push_back(static_cast<std::uint16_t>(rng() % 4096));
  const SampleMap map{true, 0.5, -1024, true, 0, 700};
  std::vector<double> doubles;
  for (auto v : s) doubles.push_back(map(v));
  const Box box{Vec3(-1, 0, 2), Vec3(2, 1.5, 3)};
  for (GridLayout layout : {GridLayout::node, GridLayout::cell})
    for (Interpolation interp : {Interpolation::trilinear, Interpolation::nearest}) {
      const GridField stored(box, n, layout, interp, GridNodes(VolumeSamples(s), map));
      const GridField plain(box, n, layout, interp, doubles);
      std::uniform_real_distribution<double> u(-0.1, 1.1);
      for (int k = 0; k < 300; ++k) {
        const Vec3 p = box.min + box.extent().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
        const Vec3 q = box.min + box.extent().cwiseProduct(Vec3(u(rng), u(rng), u(rng)));
        EXPECT_EQ(stored.value(p), plain.value(p));
        EXPECT_EQ(stored.node_range_between(p, q), plain.node_range_between(p, q));
      }
      EXPECT_EQ(stored.max_change_within(0.3), plain.max_change_within(0.3));
      EXPECT_EQ(stored.value_noise(), plain.value_noise());
    }
}

TEST(GridNodes, AGridRefusesAWrongCountOrANonFiniteMappedValue) {
  const Box box;
  EXPECT_THROW(GridField(box, {2, 2, 2}, GridLayout::node, Interpolation::trilinear,
                         GridNodes(VolumeSamples(std::vector<std::int16_t>(7)), SampleMap{})),
               std::invalid_argument);
  // A rescale that overflows the double range.
  const SampleMap huge{true, 1e308, 0};
  EXPECT_THROW(GridField(box, {2, 2, 2}, GridLayout::node, Interpolation::trilinear,
                         GridNodes(VolumeSamples(std::vector<std::int16_t>(8, 100)), huge)),
               std::invalid_argument);
}

}  // namespace
}  // namespace vrv
