#include "lib/io/npy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace vrv {
namespace {

TEST(Npy, DoublesRoundTripBitwiseWithShapeAndAlignedData) {
  const std::vector<double> v{0.1, -0.0, std::numeric_limits<double>::denorm_min(), 1e308, -3, 2.5};
  const std::string bytes = npy_bytes(v, {2, 3});
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  EXPECT_EQ((bytes.size() - v.size() * 8) % 64, 0u);  // header padded so the data are aligned
  const NpyArray a = parse_npy(bytes, "test");
  EXPECT_EQ(a.dtype, "<f8");
  EXPECT_EQ(a.shape, (std::vector<std::size_t>{2, 3}));
  ASSERT_EQ(a.values.size(), v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    EXPECT_EQ(a.values[i], v[i]);
    EXPECT_EQ(std::signbit(a.values[i]), std::signbit(v[i]));
  }
}

TEST(Npy, FloatsAndOneDimensionalShapes) {
  const std::vector<float> v{1.5f, 0.1f, -2.f};
  const NpyArray a = parse_npy(npy_bytes(v, {3}), "test");
  EXPECT_EQ(a.dtype, "<f4");
  EXPECT_EQ(a.shape, (std::vector<std::size_t>{3}));
  for (std::size_t i = 0; i < v.size(); ++i) EXPECT_EQ(a.values[i], v[i]);
  EXPECT_NE(npy_bytes(v, {3}).find("(3,)"), std::string::npos);  // Python's one-tuple
}

TEST(Npy, RefusesAShapeThatDoesNotMatchAndBrokenFiles) {
  const std::vector<double> v{1, 2, 3};
  EXPECT_THROW(npy_bytes(v, {2, 2}), std::invalid_argument);
  std::string bytes = npy_bytes(v, {3});
  EXPECT_THROW(parse_npy(bytes.substr(0, bytes.size() - 1), "x.npy"), std::runtime_error);
  EXPECT_THROW(parse_npy("not numpy at all", "x.npy"), std::runtime_error);
  std::string fortran = bytes;
  fortran.replace(fortran.find("False"), 5, "True ");
  EXPECT_THROW(parse_npy(fortran, "x.npy"), std::runtime_error);
}

}  // namespace
}  // namespace vrv
