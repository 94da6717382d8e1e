#pragma once
// The sampling study's files, each written atomically into the study's directory:
//   rays.csv                 one row per (strategy, rate, ray) and the continuous solution
//   errors.{csv,md,tex}      per strategy and rate: max and mean error, samples, dropped rays
//   summary.{csv,md,tex}     per strategy: errors at the curve rates and observed orders
//   images.{csv,md}          per image: errors, dropped pixels
//   reference.{exr,png}, <strategy>_r<rate>.{exr,png}, <strategy>_r<rate>_error.{exr,png}
//   plots.json               the Fig. 2 panels, per-rate errors, convergence
#include <filesystem>
#include <vector>

#include "studies/sampling/run.h"

namespace vrv::sampling_study {

void write_fan_tables(const std::filesystem::path& dir, const Study& st, std::size_t ray_count,
                      const std::vector<ContinuousRay>& truth, const std::vector<StrategyRun>& runs,
                      const std::vector<StrategyOrder>& orders);
void write_images(const std::filesystem::path& dir, const Study& st, const Camera& view,
                  const std::vector<ContinuousRay>& truth, const std::vector<StrategyRun>& images);
void write_plots(const std::filesystem::path& dir, const Study& st);

// "S.R. 4": the series name of a rate in rays.csv (the paper's legend).
std::string series_name(double rate);

}  // namespace vrv::sampling_study
