#include "lib/io/run_metadata.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>

namespace vrv {
namespace {

TEST(RunMetadata, AllKeysPresent) {
  const nlohmann::json meta = run_metadata(nlohmann::json::object(), 1.5);
  for (const char* key : {"vrv_version", "git_commit", "git_dirty", "date", "host", "compiler", "flags",
                          "parameters", "wall_seconds"})
    EXPECT_TRUE(meta.contains(key)) << key;
  EXPECT_TRUE(meta["vrv_version"].is_string());
  EXPECT_FALSE(meta["vrv_version"].get<std::string>().empty());
  EXPECT_TRUE(meta["git_commit"].is_string());
  EXPECT_TRUE(meta["git_dirty"].is_boolean() || meta["git_dirty"].is_null());
  EXPECT_TRUE(meta["host"].is_string());
  EXPECT_FALSE(meta["host"].get<std::string>().empty());
  EXPECT_TRUE(meta["compiler"].is_string());
  EXPECT_FALSE(meta["compiler"].get<std::string>().empty());
  ASSERT_TRUE(meta["flags"].is_object());
  EXPECT_TRUE(meta["flags"]["ndebug"].is_boolean());
  EXPECT_TRUE(meta["flags"]["optimize"].is_boolean());
  EXPECT_EQ(meta["wall_seconds"], 1.5);
}

TEST(RunMetadata, DateIsIso8601Utc) {
  const std::string date = run_metadata({}, 0.0)["date"];
  // "YYYY-MM-DDThh:mm:ssZ": digits where the template has 'd', the separators exactly.
  const std::string shape = "dddd-dd-ddTdd:dd:ddZ";
  ASSERT_EQ(date.size(), shape.size()) << date;
  for (std::size_t i = 0; i < shape.size(); ++i) {
    if (shape[i] == 'd') EXPECT_TRUE(std::isdigit(static_cast<unsigned char>(date[i]))) << date;
    else EXPECT_EQ(date[i], shape[i]) << date;
  }
  const auto field = [&](std::size_t at, std::size_t n) { return std::stoi(date.substr(at, n)); };
  EXPECT_GE(field(0, 4), 2024);
  EXPECT_TRUE(field(5, 2) >= 1 && field(5, 2) <= 12) << date;
  EXPECT_TRUE(field(8, 2) >= 1 && field(8, 2) <= 31) << date;
  EXPECT_LE(field(11, 2), 23);
  EXPECT_LE(field(14, 2), 59);
  EXPECT_LE(field(17, 2), 60);
}

TEST(RunMetadata, ParametersEmbeddedWhole) {
  const nlohmann::json parameters = {{"scene", "marschner_lobb"},
                                     {"rates", {1, 2, 4, 8}},
                                     {"tolerance", 1e-12},
                                     {"nested", {{"method", "alpha"}, {"correction", nullptr}}}};
  const nlohmann::json meta = run_metadata(parameters, 42.0);
  EXPECT_EQ(meta["parameters"], parameters);
  EXPECT_EQ(meta["wall_seconds"], 42.0);
  // Serialises and reads back (what meta.json needs).
  EXPECT_EQ(nlohmann::json::parse(meta.dump(2)), meta);
}

TEST(RunMetadata, GitCommitIsAHashInThisCheckout) {
  const std::string commit = run_metadata({}, 0.0)["git_commit"];
  if (commit == "unknown") GTEST_SKIP() << "no git or not a checkout";
  EXPECT_TRUE(commit.size() == 40 || commit.size() == 64) << commit;
  for (char ch : commit) EXPECT_TRUE(std::isxdigit(static_cast<unsigned char>(ch))) << commit;
}

TEST(RunMetadata, NeverThrows) {
  // Non-finite wall time becomes null rather than an unserialisable number.
  nlohmann::json meta;
  EXPECT_NO_THROW(meta = run_metadata(nullptr, std::numeric_limits<double>::quiet_NaN()));
  EXPECT_TRUE(meta["wall_seconds"].is_null());
  EXPECT_TRUE(meta["parameters"].is_null());
  EXPECT_NO_THROW((void)meta.dump());

  // No git on PATH and a directory that is not a checkout: "unknown", not an exception.
  const char* old_path = std::getenv("PATH");
  const std::string saved = old_path ? old_path : "";
  const auto old_dir = std::filesystem::current_path();
  ::setenv("PATH", "/nonexistent", 1);
  std::filesystem::current_path(std::filesystem::temp_directory_path());
  EXPECT_NO_THROW(meta = run_metadata({{"a", 1}}, 1.0));
  std::filesystem::current_path(old_dir);
  if (old_path) ::setenv("PATH", saved.c_str(), 1);
  else ::unsetenv("PATH");
  EXPECT_EQ(meta["git_commit"], "unknown");
  EXPECT_TRUE(meta["git_dirty"].is_null());
  EXPECT_EQ(meta["parameters"]["a"], 1);
}

}  // namespace
}  // namespace vrv
