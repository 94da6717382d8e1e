#pragma once
// Study kind "convergence", the verification method of Etiene et al. (TVCG 2014): the observed
// order of each discrete method, the least-squares slope of log(mean error) against log(step),
// must match the expected order within a tolerance; optionally also under grid refinement.  The
// run is deterministic (any thread count gives the same bits).  See
// studies/convergence/convergence.toml and docs/studies.md.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "lib/discrete_raycast.h"
#include "lib/study_file.h"
#include "lib/order_estimate.h"
#include "lib/scene.h"
#include "studies/engine/checkpoint.h"
#include "studies/engine/reference_audit.h"
#include "studies/engine/study_driver.h"

namespace vrv {

struct StudyMethod {
  SegmentRule rule = SegmentRule::riemann;
  double expected_order = 1;
};

struct StudyDefinition {
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
  double reference_tol = 1e-13;  // the tolerance of the reference each error is against
  // Convergence under grid refinement ([grid_refinement], optional): the analytic field sampled
  // on node grids of these resolutions (cubic, trilinear), each method's error against the
  // analytic reference with the step tied to the cell (steps_per_cell x cell size).
  std::vector<int> grid_resolutions, quick_grid_resolutions;
  double grid_expected_order = 2;  // trilinear reconstruction
  double grid_steps_per_cell = 0.5;
};

// Throws StudyFileError for any problem (unknown method or key; missing key; empty or
// non-positive steps; a bad [scene]).
StudyDefinition read_convergence_study(const StudyInput& in);
StudyDefinition parse_study(std::string_view toml_text, std::string_view source_name,
                             std::string_view default_name);
StudyDefinition load_study(const std::filesystem::path& path);

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

struct StudyResult {
  std::vector<ErrorRow> errors;  // method-major, steps in file order
  std::vector<OrderRow> orders;
  std::vector<GridErrorRow> grid_errors;  // convergence with [grid_refinement]
  std::vector<GridOrderRow> grid_orders;
  long rays = 0;
  bool pass = true;
};

// Runs the study with parallel_for_index over rays (respects any ThreadLimit alive); the result
// does not depend on the number of threads.  progress: a Progress bar on stderr.  The
// reference's truths are counted in `audit`.
StudyResult run_convergence(const StudyDefinition& study, bool quick, ReferenceAudit& audit, bool progress,
                            const StudyCheckpoint& checkpoint = {});

// Field evaluations of the run (full or `quick`), estimated from the definition alone.
StudyWork convergence_work(const StudyDefinition& study, bool quick);

struct StudyFiles {
  std::string errors_csv, orders_csv, orders_md, orders_tex;
  std::string grid_errors_csv, grid_orders_csv, grid_orders_md, grid_orders_tex;  // if refined
};
StudyFiles study_tables(const StudyDefinition& study, const StudyResult& result);

// The full parameters recorded in meta.json.
nlohmann::json study_parameters(const StudyDefinition& study, bool quick, int threads);

// Writes errors.csv, orders.csv, orders.md and orders.tex (and the grid_* tables when refined)
// into `dir`, each atomically.
void write_study_tables(const std::filesystem::path& dir, const StudyDefinition& study,
                        const StudyResult& result);

}  // namespace vrv
