#pragma once
// What every command checks of its outputs before it computes anything: that none of them is one
// of its inputs under any name (vrv render's -o against --error-against, vrv verify's --out
// against its images, scene and bounds file), and that an output folder can be written.
#include <filesystem>
#include <string_view>
#include <vector>

namespace vrv {

// The same file under two names (fs::equivalent), or the same path when one does not exist yet.
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b);

// `dir` (an output folder, which vrv writes and owns) holds none of `inputs` at any depth, under
// any name; std::invalid_argument "<option>: <dir>: holds the input <file> ..." otherwise.
void check_inputs_outside(const std::filesystem::path& dir, const std::vector<std::filesystem::path>& inputs,
                          std::string_view option);

// Creates `dir` (and its parents) if missing and a file in it, then removes that file: a folder
// that cannot be written is found before the work, not after it.  std::invalid_argument
// "<option>: <dir>: <reason>" otherwise.
void check_writable_dir(const std::filesystem::path& dir, std::string_view option);

// An output folder that a run replaces whole (vrv verify --out, vrv export --out) must be one vrv
// wrote: missing, empty, or holding `marker` (meta.json, export.json), since publishing the new
// run removes everything the folder held.  std::invalid_argument "<option>: <dir>: ..." otherwise.
void check_replaceable_dir(const std::filesystem::path& dir, std::string_view marker, std::string_view option);

}  // namespace vrv
