#pragma once
// Gating a verification on a bounds file (lib/bounds_file.h): one row per bound with the
// measured value, the limit that decided it, the margin and the verdict.
#include <optional>
#include <string>
#include <vector>

#include "lib/bounds_file.h"
#include "lib/io/table.h"
#include "lib/verify.h"

namespace vrv {

enum class BoundVerdict { pass, warn, fail, hard_fail };
std::string_view bound_verdict_name(BoundVerdict v);  // "pass", "warn", "fail", "hard-fail"

struct BoundRow {
  std::string case_name, bound, where;  // where: "image (channel)" or "all images"
  double measured = 0;
  double limit = 0;   // the limit crossed (the most severe), or the fail limit (else warn, else
                      // hard_fail) when none is
  double margin = 0;  // limit - measured for upper limits, measured - limit for lower: < 0 crossed
  std::optional<double> warn, fail, hard_fail;
  BoundVerdict verdict = BoundVerdict::pass;
};

// The level a measured value reaches: hard_fail beyond hard_fail, fail beyond fail, warn beyond
// warn, else pass ("beyond": above for upper limits, below for lower ones; NaN is beyond all).
BoundRow judge_bound(const std::string& case_name, Bound bound, const std::string& where,
                     double measured, const Limits& limits);

// Every bound of `set` against the report: error bounds on the finest image (or every image with
// at = "all"), each on the worst channel; percent_over is 100 x the report's fraction over its
// threshold, which must be the set's (verify with VerifyOptions::threshold = set.threshold;
// std::invalid_argument otherwise); min_order on the lowest observed order
// against the reference (NaN when none could be fitted, which fails it); max_nan on the NaN count
// over all images and channels.
std::vector<BoundRow> evaluate_bounds(const std::string& case_name, const VerifyReport& report,
                                      const BoundSet& set);

// The options verifying against `set` needs: its threshold (percent_over counts against it) and,
// when it bounds NaN pixels (max_nan), NaN pixels counted instead of refused.  `threshold`, an
// explicitly chosen one (--threshold), must equal the set's: std::invalid_argument otherwise.
void use_bounds(const BoundSet& set, VerifyOptions& options, std::optional<double> threshold = std::nullopt);

// A study case: its checks pass or not (the only bound it has).
BoundRow study_row(const std::string& case_name, bool pass, long failed_checks);

Table bound_table(const std::vector<BoundRow>& rows);
// The most severe verdict of the rows (pass for none).
BoundVerdict worst(const std::vector<BoundRow>& rows);

}  // namespace vrv
