#pragma once
// Studies as data: a TOML file names a kind of experiment, its scene and its parameters; the
// engine runs it deterministically (any thread count gives the same bits) and writes tidy tables.
// One kind so far, "convergence": the verification method of Etiene et al. (TVCG 2014) —
// the observed order of each discrete method, the least-squares slope of log(mean error) against
// log(step), must match the expected order within a tolerance.  See docs/studies.md.
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "lib/discrete_raycast.h"
#include "lib/scene.h"

namespace vrv {

// A bad study file: one line, "<file>: <key>: <reason>".
class StudyFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct StudyMethod {
  SegmentRule rule = SegmentRule::riemann;
  double expected_order = 1;
};

struct ConvergenceStudy {
  std::string name;         // `name` key, else the file's stem
  std::string source;       // the file (or source name) it came from
  std::string description;
  std::string scene_toml;   // the [scene] table, as TOML text
  Scene scene;
  std::vector<StudyMethod> methods;
  Strategy strategy = Strategy::inviwo;
  std::vector<double> steps;  // world units, each > 0
  long count = 64;            // rays
  long quick_count = 8;       // rays with --quick
  std::uint64_t seed = 1;
  double tolerance = 0.25;    // on |observed - expected|
  double reference_tol = 1e-13;
};

// Throws StudyFileError for any problem (unknown kind, method or key; missing key; empty or
// non-positive steps; a bad [scene]).
ConvergenceStudy parse_study(std::string_view toml_text, std::string_view source_name,
                             std::string_view default_name);
ConvergenceStudy load_study(const std::filesystem::path& path);

// The fixed-seed ray set: origins uniform on the sphere of radius 3 x the box half-diagonal
// around the box centre, each aimed at a uniform point of the box.  Same rays on every platform
// (own conversion of mt19937_64 output, no std distributions).
std::vector<Ray> study_rays(const Box& box, long count, std::uint64_t seed);

struct ErrorRow {
  SegmentRule rule;
  double step = 0;
  double max_error = 0, mean_error = 0, samples_per_ray = 0;
};

struct OrderRow {
  SegmentRule rule;
  double expected = 0, observed = 0;
  bool pass = false;
};

struct StudyResult {
  std::vector<ErrorRow> errors;  // method-major, steps in file order
  std::vector<OrderRow> orders;
  long rays = 0;
  bool pass = true;
};

// Least-squares slope of log(error) against log(step) (Eigen).  NaN if fewer than two points
// or an error is not positive.
double observed_order(const std::vector<double>& steps, const std::vector<double>& errors);

// Runs the study with parallel_for_index over rays (respects any ThreadLimit alive); the result
// does not depend on the number of threads.  progress: a Progress bar on stderr.
StudyResult run_convergence(const ConvergenceStudy& study, bool quick, bool progress);

struct StudyFiles {
  std::string errors_csv, orders_csv, orders_md, orders_tex;
};
StudyFiles study_tables(const ConvergenceStudy& study, const StudyResult& result);

// The full parameters recorded in meta.json.
nlohmann::json study_parameters(const ConvergenceStudy& study, bool quick, int threads);

// Writes errors.csv, orders.csv, orders.md, orders.tex and meta.json into `dir` (created if
// missing), each atomically.
void write_study(const std::filesystem::path& dir, const ConvergenceStudy& study,
                 const StudyResult& result, const nlohmann::json& parameters, double seconds);

}  // namespace vrv
