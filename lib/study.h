#pragma once
// Studies as data: a TOML file names a kind of experiment, its scene and its parameters; the
// engine runs it deterministically (any thread count gives the same bits) and writes tidy tables.
// Two kinds: "convergence", the verification method of Etiene et al. (TVCG 2014) — the observed
// order of each discrete method, the least-squares slope of log(mean error) against log(step),
// must match the expected order within a tolerance; and "hard_cases", the stability cases (extreme
// optical depth, near-zero extinction, grazing and corner rays, N = 1024, float at tiny steps,
// steps and peaks in the transfer function), each a scene, a ray and a list of methods whose
// value, error, bound and finiteness are recorded and gated.  See docs/studies.md.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "lib/discrete_raycast.h"
#include "lib/order_estimate.h"
#include "lib/scene.h"
#include "lib/study_file.h"

namespace vrv {

struct StudyMethod {
  SegmentRule rule = SegmentRule::riemann;
  double expected_order = 1;
};

// One method run on a hard case: see StudyMethodSpec (lib/study_file.h).
using HardCaseMethod = StudyMethodSpec;

struct HardCase {
  std::string name;
  std::string description;
  std::string scene_toml;  // the case's [scene] table, as TOML text
  Scene scene;
  Vec3 origin{0, 0, 0}, direction{1, 0, 0};
  std::vector<HardCaseMethod> methods;
};

struct StudyDefinition {
  std::string kind = "convergence";  // "convergence" or "hard_cases"
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
  // |observed - expected| <= max(margin x c_1 x SE, floor) (lib/order_estimate.h); the file's
  // `order_tolerance = { margin, floor }`, else these.
  OrderTolerance order_tolerance{2, 0.05};
  double reference_tol = 1e-13;  // hard_cases: the tolerance of the "truth" each error is against
  // Convergence under grid refinement ([grid_refinement], optional): the analytic field sampled
  // on node grids of these resolutions (cubic, trilinear), each method's error against the
  // analytic reference with the step tied to the cell (steps_per_cell x cell size).
  std::vector<int> grid_resolutions, quick_grid_resolutions;
  double grid_expected_order = 2;  // trilinear reconstruction
  double grid_steps_per_cell = 0.5;
  std::vector<HardCase> cases;   // hard_cases only (then scene, methods, steps, rays are unused)
};

// Throws StudyFileError for any problem (unknown kind, method or key; missing key; empty or
// non-positive steps; a bad [scene]).
StudyDefinition parse_study(std::string_view toml_text, std::string_view source_name,
                             std::string_view default_name);
StudyDefinition load_study(const std::filesystem::path& path);

// The fixed-seed ray set: origins uniform on the sphere of radius 3 x the box half-diagonal
// around the box centre, each aimed at a uniform point of the box.  Same rays on every platform
// (own conversion of mt19937_64 output, no std distributions).
std::vector<Ray> study_rays(const Box& box, long count, std::uint64_t seed);

struct ErrorRow {
  SegmentRule rule;
  double step = 0;
  double max_error = 0, mean_error = 0, samples_per_ray = 0;
};

// One row of the grid refinement: "reference" (the continuous integral through the trilinear
// grid) or a rule, on one resolution.
struct GridErrorRow {
  std::string method;
  int resolution = 0;
  double cell = 0;  // cell size (world units)
  double max_error = 0, mean_error = 0;
};

struct GridOrderRow {
  std::string method;
  double expected = 0, observed = 0;
  bool pass = false;
  OrderEstimate fit{};  // observed = fit.order, with its spread
};

struct OrderRow {
  SegmentRule rule;
  double expected = 0, observed = 0;
  bool pass = false;
  OrderEstimate fit{};
};

// One row of a hard-cases study: one method on one case.
struct CaseRow {
  std::string case_name, method;
  bool reference = false;
  double value = 0;
  double error = 0;   // |value - reference at reference_tol|
  double bound = 0;   // reference: its error_estimate; discrete: max_error, or NaN (none stated)
  bool finite = false;
  long samples = 0;   // discrete: field samples; reference: field evaluations
  bool pass = false;
};

struct CaseSummary {
  std::string name;
  double truth = 0, truth_estimate = 0;  // the reference at reference_tol and its error_estimate
  long nan_count = 0;                    // non-finite values among the case's rows (and truth)
  bool pass = true;
};

struct StudyResult {
  std::vector<ErrorRow> errors;  // method-major, steps in file order
  std::vector<OrderRow> orders;
  std::vector<GridErrorRow> grid_errors;  // convergence with [grid_refinement]
  std::vector<GridOrderRow> grid_orders;
  std::vector<CaseRow> cases;            // hard_cases: case-major, methods in file order
  std::vector<CaseSummary> case_summary;  // hard_cases: one per case
  long rays = 0;
  bool pass = true;
};

// Least-squares slope of log(error) against log(step) (Eigen).  NaN if fewer than two points
// or an error is not positive.
double observed_order(const std::vector<double>& steps, const std::vector<double>& errors);

// Runs the study (either kind; hard_cases goes to run_hard_cases) with parallel_for_index over rays (respects any ThreadLimit alive); the result
// does not depend on the number of threads.  progress: a Progress bar on stderr.
StudyResult run_convergence(const StudyDefinition& study, bool quick, bool progress);

// hard_cases: per case the truth (reference at reference_tol), then every (case, method) in
// parallel, each into its own slot.  quick runs the same cases (they are cheap).  A case passes
// when every row is finite and, for reference rows, error <= error_estimate + truth's estimate
// and error_estimate <= tol, and, for discrete rows with max_error, error <= max_error.
StudyResult run_hard_cases(const StudyDefinition& study, bool progress);

struct StudyFiles {
  std::string errors_csv, orders_csv, orders_md, orders_tex;
  std::string grid_errors_csv, grid_orders_csv, grid_orders_md, grid_orders_tex;  // if refined
};
StudyFiles study_tables(const StudyDefinition& study, const StudyResult& result);

struct HardCaseFiles {
  std::string cases_csv, cases_md, cases_tex;
};
HardCaseFiles hard_case_tables(const StudyDefinition& study, const StudyResult& result);

// The full parameters recorded in meta.json.
nlohmann::json study_parameters(const StudyDefinition& study, bool quick, int threads);

// Writes errors.csv, orders.csv, orders.md, orders.tex and meta.json (hard_cases: cases.csv,
// cases.md, cases.tex and meta.json) into `dir` (created if missing), each atomically.
void write_study(const std::filesystem::path& dir, const StudyDefinition& study,
                 const StudyResult& result, const nlohmann::json& parameters, double seconds);
// The tables alone (no meta.json), and the hard cases' per-case summary as meta.json has it.
void write_study_tables(const std::filesystem::path& dir, const StudyDefinition& study,
                        const StudyResult& result);
nlohmann::json case_summary_json(const StudyResult& result);

}  // namespace vrv
