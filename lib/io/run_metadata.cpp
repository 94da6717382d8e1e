#include "lib/io/run_metadata.h"

#include <unistd.h>

#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>

#include <fmt/format.h>

namespace vrv {
namespace {

#ifdef VRV_VERSION
constexpr const char* kVersion = VRV_VERSION;
#else
constexpr const char* kVersion = "0.1.0";
#endif

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

// Runs a command and returns its stdout, or nothing if it cannot start or exits non-zero.
std::optional<std::string> run(const std::string& command) {
  std::FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return std::nullopt;
  std::string out;
  std::array<char, 256> buffer{};
  std::size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) out.append(buffer.data(), n);
  if (::pclose(pipe) != 0) return std::nullopt;
  return out;
}

// The tree to ask git about: VRV_SOURCE_DIR, else the tree this file was compiled from, else ".".
std::string source_dir() {
#ifdef VRV_SOURCE_DIR
  return VRV_SOURCE_DIR;
#else
  std::error_code ec;
  const std::filesystem::path here(__FILE__);  // <source>/lib/io/run_metadata.cpp when CMake compiles it
  if (here.is_absolute()) {
    const auto dir = here.parent_path().parent_path().parent_path();
    if (std::filesystem::is_directory(dir, ec)) return dir.string();
  }
  return ".";
#endif
}

bool is_hash(const std::string& s) {
  if (s.size() != 40 && s.size() != 64) return false;
  for (char ch : s)
    if (!std::isxdigit(static_cast<unsigned char>(ch))) return false;
  return true;
}

void add_git(nlohmann::json& meta) {
  meta["git_commit"] = "unknown";
  meta["git_dirty"] = nullptr;
  try {
    const std::string git = "git -C " + shell_quote(source_dir()) + " ";
#ifdef VRV_GIT_COMMIT
    meta["git_commit"] = VRV_GIT_COMMIT;
    (void)is_hash;
#else
    auto head = run(git + "rev-parse HEAD 2>/dev/null");
    if (!head) return;
    while (!head->empty() && std::isspace(static_cast<unsigned char>(head->back()))) head->pop_back();
    if (!is_hash(*head)) return;
    meta["git_commit"] = *head;
#endif
    if (const auto status = run(git + "status --porcelain --untracked-files=no -- . ':!results' 2>/dev/null"))
      meta["git_dirty"] = !status->empty();
  } catch (...) {  // never let provenance stop a study
  }
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  if (now == static_cast<std::time_t>(-1) || ::gmtime_r(&now, &tm) == nullptr) return "unknown";
  std::array<char, 32> buffer{};
  const std::size_t n = std::strftime(buffer.data(), buffer.size(), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return n > 0 ? std::string(buffer.data(), n) : "unknown";
}

std::string host_name() {
  std::array<char, 256> buffer{};
  if (::gethostname(buffer.data(), buffer.size() - 1) != 0 || buffer[0] == '\0') return "unknown";
  return buffer.data();
}

std::string compiler() {
#if defined(__clang__)
  return fmt::format("Clang {}", __clang_version__);
#elif defined(__GNUC__)
  return fmt::format("GCC {}", __VERSION__);
#elif defined(__VERSION__)
  return __VERSION__;
#else
  return "unknown";
#endif
}

nlohmann::json flags() {
  nlohmann::json f;
#ifdef NDEBUG
  f["ndebug"] = true;
#else
  f["ndebug"] = false;
#endif
#ifdef __OPTIMIZE__
  f["optimize"] = true;
#else
  f["optimize"] = false;
#endif
#ifdef __FAST_MATH__
  f["fast_math"] = true;
#else
  f["fast_math"] = false;
#endif
  f["cplusplus"] = static_cast<long>(__cplusplus);
#ifdef VRV_BUILD_TYPE
  f["build_type"] = VRV_BUILD_TYPE;
#endif
#ifdef VRV_CXX_FLAGS
  f["cxx_flags"] = VRV_CXX_FLAGS;
#endif
  return f;
}

}  // namespace

nlohmann::json run_metadata(const nlohmann::json& parameters, double wall_seconds) {
  nlohmann::json meta;
  meta["vrv_version"] = kVersion;
  add_git(meta);
  meta["date"] = utc_now();
  meta["host"] = host_name();
  meta["compiler"] = compiler();
  meta["flags"] = flags();
  meta["parameters"] = parameters;
  meta["wall_seconds"] = std::isfinite(wall_seconds) ? nlohmann::json(wall_seconds) : nlohmann::json(nullptr);
  return meta;
}

}  // namespace vrv
