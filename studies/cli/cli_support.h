#pragma once
// Small pieces shared by the subcommands: exit codes, parsing vectors as users type them,
// loading the scene (or the embedded default), turning results into JSON, shared checks.
#include <optional>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "lib/reference_integrator.h"
#include "lib/scene.h"

namespace vrv::cli {

// Exit codes of every vrv command (README, "Exit codes").
inline constexpr int kExitPass = 0;
inline constexpr int kExitCheckFailed = 1;      // a study check, verify bound or gate failed
inline constexpr int kExitBadInput = 2;         // bad option, file or combination; nothing computed
inline constexpr int kExitToleranceMissed = 3;  // results written, but a reference value missed --tol
inline constexpr int kExitNotFinite = 4;        // a result is NaN or infinite (never printed as a number)
inline constexpr int kExitWriteFailed = 5;      // writing standard output failed: the results are incomplete

// Thrown by a command that must end with a non-zero status other than kExitBadInput;
// main prints what() (one line; nothing when empty) on stderr and exits with code().
class CommandFailed : public std::runtime_error {
 public:
  CommandFailed(int code, const std::string& line) : std::runtime_error(line), code_(code) {}
  int code() const { return code_; }

 private:
  int code_;
};

// "x,y,z" -> Vec3; throws std::invalid_argument naming `option` and the reason.
Vec3 parse_vec3(const std::string& text, const std::string& option);
// The scene file, or the embedded default when `path` is empty, with a volume field's file refused
// above max_volume_bytes (--max-memory, studies/cli/memory_limit.h) from its header, before its
// data are read: every command has the limit.
Scene load_scene_or_default(const std::string& path, double max_volume_bytes);
// Its TOML text (the reference cache's key): the file's bytes, or the embedded default's.
std::string scene_text_or_default(const std::string& path);
// Throws std::invalid_argument naming the file and `mode` when the scene file asks for a projection
// (lib/scene_mode.h): for the commands that draw emission-absorption only (`what`: "vrv plan",
// "vrv demo"), so that the key is refused, never ignored.  The file was parsed already.
void require_emission_absorption(const std::string& path, std::string_view what);
// Every field of the result; value and error estimate are null when not finite.
nlohmann::ordered_json to_json(const ReferenceResult& r);
// Validates --threads: 0 (the default) is every core; negative values are refused, as by study.
void check_threads(int threads);

// The JSON value of a double: null when it is NaN or infinite (JSON has no such numbers).
nlohmann::ordered_json finite_or_null(double x);

}  // namespace vrv::cli
