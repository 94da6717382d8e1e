#pragma once
// The fixtures make_volume_fixtures.py wrote (data/) and what they must read back
// (expected.json): shared by the readers' tests.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "lib/volume/volume.h"
#include "lib/volume/volume_file.h"

namespace vrv::test {

inline std::filesystem::path volume_fixture_dir() {
  return std::filesystem::path(VRV_SOURCE_DIR) / "tests" / "lib" / "volume" / "data";
}

inline const nlohmann::json& volume_expected(std::string_view name = "expected.json") {
  static std::map<std::string, nlohmann::json, std::less<>> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    std::ifstream in(std::filesystem::path(VRV_SOURCE_DIR) / "tests" / "lib" / "volume" / std::string(name));
    it = cache.emplace(std::string(name), nlohmann::json::parse(in)).first;
  }
  return it->second;
}

// Type, dims, steps (column a: index axis a), origin exactly; off-axis entries of the expected
// matrix below 1e-6 of their column are the writer's rounding and read as 0.
inline void expect_geometry(const nlohmann::json& c, const Volume& v) {
  EXPECT_EQ(to_string(v.type()), c["type"].get<std::string>());
  for (int a = 0; a < 3; ++a) EXPECT_EQ(v.dims[a], c["dims"][a].get<int>()) << "axis " << a;
  const Eigen::Matrix3d steps = v.steps();
  for (int a = 0; a < 3; ++a) {
    double norm = 0;
    for (int w = 0; w < 3; ++w) norm = std::hypot(norm, c["steps"][w][a].get<double>());
    for (int w = 0; w < 3; ++w) {
      const double e = c["steps"][w][a].get<double>();
      EXPECT_EQ(steps(w, a), std::abs(e) < 1e-6 * norm ? 0.0 : e) << "step of index axis " << a << ", world " << w;
    }
  }
  for (int w = 0; w < 3; ++w) EXPECT_EQ(v.origin[w], c["origin"][w].get<double>()) << "origin " << w;
}

inline void expect_case(const nlohmann::json& c, const Volume& v) {
  expect_geometry(c, v);
  const auto& values = c["values"];
  ASSERT_EQ(v.count(), values.size());
  for (std::size_t n = 0; n < v.count(); ++n) {
    const double e = values[n].get<double>();
    EXPECT_EQ(v.sample(n), e) << "sample " << n;
    EXPECT_EQ(std::signbit(v.sample(n)), std::signbit(e)) << "sign of sample " << n;
  }
  if (c.contains("slope")) {
    EXPECT_TRUE(v.has_rescale);
    EXPECT_EQ(v.slope, c["slope"].get<double>());
    EXPECT_EQ(v.intercept, c["intercept"].get<double>());
  } else {
    EXPECT_FALSE(v.has_rescale);
  }
}

using VolumeReader = std::function<Volume(const std::filesystem::path&)>;

// Every fixture whose name starts with `prefix`, through `read` and through read_volume; returns
// how many (a test asserts it found its files).
inline int expect_fixtures(std::string_view prefix, const VolumeReader& read) {
  int n = 0;
  for (const auto& c : volume_expected()["cases"]) {
    const std::string file = c["file"];
    if (file.rfind(prefix, 0) != 0) continue;
    SCOPED_TRACE(file);
    const auto path = volume_fixture_dir() / file;
    expect_case(c, read(path));
    expect_case(c, read_volume(path));
    ++n;
  }
  return n;
}

// The one line a refused file gets: "<path>: <message>" (exactly, or its start).
inline void expect_refused(const std::filesystem::path& path, const nlohmann::json& b, const VolumeReader& read) {
  SCOPED_TRACE(path.string());
  try {
    read(path);
    ADD_FAILURE() << "read, expected a refusal";
  } catch (const VolumeFileError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    if (b.contains("message"))
      EXPECT_EQ(msg, path.string() + ": " + b["message"].get<std::string>());
    else
      EXPECT_EQ(msg.rfind(path.string() + ": " + b["starts"].get<std::string>(), 0), 0u) << msg;
  }
}

inline int expect_bad_fixtures(std::string_view prefix, const VolumeReader& read) {
  int n = 0;
  for (const auto& b : volume_expected()["bad"]) {
    const std::string file = b["file"];
    if (file.rfind(prefix, 0) != 0) continue;
    expect_refused(volume_fixture_dir() / file, b, read);
    expect_refused(volume_fixture_dir() / file, b, [](const auto& p) { return read_volume(p); });
    ++n;
  }
  return n;
}

}  // namespace vrv::test
