#pragma once
// What `vrv verify` writes into --out DIR, the way a study writes its results:
//   errors.{csv,md,tex,json}     one row per image, channel and region: max, mean, RMS, p99, fraction over
//   orders.{csv,md,tex,json}     per channel: the order against the reference and the self-convergence
//                                order, each with its standard error, and the verdict
//   points.csv                   the (step, error) points of every fit, for the plot
//   diagnosis.{csv,md,tex,json}  vrv's models by RMS difference from the images, nearest first
//   faults.{csv,md,tex,json}     the known faults the errors match
//   conventions.{csv,md,tex,json} the placements or rules matched that the expected order allows
//   bounds.{csv,md,tex,json}     with a bounds file: one row per bound
//   reference.exr, <k>_<image>_<channel>_error.{exr,png}   the reference and signed error images
//                                (PNG: colour-mapped with a numbered colour bar)
//   plots.json                   the log-log plot of error against step (drawn by plot_study.py)
//   meta.json                    run metadata (lib/run_metadata.h), the options and the summary
// Every file is written atomically; the directory is created if missing.
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "lib/io/table.h"
#include "lib/verify.h"

namespace vrv {

struct VerifyTables {
  Table errors, orders, points, diagnosis, faults, conventions;
};
VerifyTables verify_tables(const VerifyReport& report);

// name.csv, name.md, name.tex and name.json; an empty table's Markdown is `empty_markdown` when
// that is given.
void write_table_files(const std::filesystem::path& dir, const std::string& name, const Table& table,
                       std::string_view empty_markdown = {});

// Before any work (vrv verify --out, vrv.verify(out=)): `dir` is a directory or does not exist
// yet (write_verify_outputs creates it), and holds none of `inputs` (the images, scene and bounds
// files: the reference.exr and error images written there would replace them; output_paths.h);
// std::invalid_argument "--out: ..." otherwise.
void check_verify_out(const std::filesystem::path& dir, const std::vector<std::filesystem::path>& inputs = {});

// `extra`: further tables (e.g. {"bounds", ...}); parameters go to meta.json with the summary.
void write_verify_outputs(const std::filesystem::path& dir, const VerifyReport& report,
                          const std::vector<std::pair<std::string, Table>>& extra,
                          const nlohmann::json& parameters, double seconds);

}  // namespace vrv
