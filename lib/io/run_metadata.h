#pragma once
// What a study's meta.json records about the run, so that a result can be traced to the code,
// machine and settings that produced it:
//   vrv_version   VRV_VERSION if defined at compile time, else "0.1.0"
//   git_commit    VRV_GIT_COMMIT if defined, else `git rev-parse HEAD` at run time in the source tree
//                 (VRV_SOURCE_DIR if defined, else the tree this file was compiled from, else the
//                 current directory); "unknown" if none answers
//   git_dirty     true/false when tracked files outside results/ differ from that commit (results/
//                 is what studies write, so regenerating it does not make the tree dirty), null
//                 when unknown
//   date          when run_metadata is called, ISO 8601 UTC, e.g. "2024-05-01T12:34:56Z"
//   host          gethostname(), "unknown" on failure
//   compiler      compiler id and version, e.g. "GCC 12.2.0"
//   flags         {"ndebug", "optimize" (__OPTIMIZE__), "fast_math" (__FAST_MATH__), "cplusplus",
//                  and "build_type" / "cxx_flags" when VRV_BUILD_TYPE / VRV_CXX_FLAGS are defined}
//   parameters    the study's full parameters, as given
//   wall_seconds  as given (null if not finite)
// Compile definitions the CMake owner could add to vrvcore to make it exact:
//   VRV_VERSION="${PROJECT_VERSION}", VRV_SOURCE_DIR="${PROJECT_SOURCE_DIR}",
//   VRV_BUILD_TYPE="$<CONFIG>", VRV_CXX_FLAGS="${CMAKE_CXX_FLAGS} ${CMAKE_CXX_FLAGS_<CONFIG>}",
//   VRV_GIT_COMMIT (the commit at build time; the run-time query reports the tree as it is when
//   the study runs, which differs if the tree changed after the build).
// The flags describe how this file was compiled, which is how vrvcore was compiled.
#include <nlohmann/json.hpp>

namespace vrv {

// Never throws for lack of git, host name or clock (those fall back to "unknown").
nlohmann::json run_metadata(const nlohmann::json& parameters, double wall_seconds);

}  // namespace vrv
