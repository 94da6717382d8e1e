#include "lib/gate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "lib/option_error.h"
#include "lib/util/not_a_number.h"

namespace vrv {
namespace {

double error_metric(const ErrorStats& s, Bound b) {
  switch (b) {
    case Bound::max: return s.max;
    case Bound::mean: return s.mean;
    case Bound::rms: return s.rms;
    case Bound::p99: return s.p99;
    case Bound::percent_over: return 100 * s.fraction_over;
    default: return kNaN;
  }
}

}  // namespace

std::string_view bound_verdict_name(BoundVerdict v) {
  switch (v) {
    case BoundVerdict::pass: return "pass";
    case BoundVerdict::warn: return "warn";
    case BoundVerdict::fail: return "fail";
    case BoundVerdict::hard_fail: return "hard-fail";
  }
  return "?";
}

BoundRow judge_bound(const std::string& case_name, Bound bound, const std::string& where, double measured,
                     const Limits& limits) {
  BoundRow row;
  row.case_name = case_name, row.bound = bound_name(bound), row.where = where, row.measured = measured;
  row.warn = limits.warn, row.fail = limits.fail, row.hard_fail = limits.hard_fail;
  const bool lower = is_lower_limit(bound);
  // Crossed: beyond the limit; NaN crosses every limit (an unmeasurable value never passes).
  auto crossed = [&](const std::optional<double>& l) {
    return l && (std::isnan(measured) || (lower ? measured < *l : measured > *l));
  };
  std::optional<double> decided;
  if (crossed(limits.hard_fail)) row.verdict = BoundVerdict::hard_fail, decided = limits.hard_fail;
  else if (crossed(limits.fail)) row.verdict = BoundVerdict::fail, decided = limits.fail;
  else if (crossed(limits.warn)) row.verdict = BoundVerdict::warn, decided = limits.warn;
  else decided = limits.fail ? limits.fail : limits.warn ? limits.warn : limits.hard_fail;
  row.limit = *decided;
  row.margin = lower ? measured - row.limit : row.limit - measured;
  return row;
}

std::vector<BoundRow> evaluate_bounds(const std::string& case_name, const VerifyReport& report,
                                      const BoundSet& set) {
  if (set.limits.count(Bound::percent_over) && report.threshold != set.threshold)
    throw std::invalid_argument(fmt::format("percent_over: the report counts |e| > {:g}, the bounds ask for {:g}",
                                            report.threshold, set.threshold));
  std::vector<BoundRow> rows;
  const double finest = report.channels.empty() ? kNaN
                        : std::min_element(report.channels.begin(), report.channels.end(),
                                           [](const auto& a, const auto& b) { return a.step < b.step; })->step;
  for (const auto& [bound, limits] : set.limits) {
    if (bound == Bound::min_order) {
      double lowest = std::numeric_limits<double>::infinity();
      std::string where;
      for (const OrderReport& o : report.orders)
        if (o.kind == OrderKind::reference && !(o.fit.order >= lowest)) lowest = o.fit.order, where = o.channel;
      if (report.orders.empty()) lowest = kNaN;
      rows.push_back(judge_bound(case_name, bound, fmt::format("order against the reference ({})", where),
                                 lowest, limits));
    } else if (bound == Bound::max_nan) {
      long nan = 0;
      for (const ChannelReport& c : report.channels) nan += c.nan_count;
      rows.push_back(judge_bound(case_name, bound, "all images", static_cast<double>(nan), limits));
    } else {
      // The worst channel of each image the bound reads.
      std::vector<double> steps;
      for (const ChannelReport& c : report.channels)
        if ((set.all_images || c.step == finest) && (steps.empty() || steps.back() != c.step)) steps.push_back(c.step);
      for (double step : steps) {
        const ChannelReport* worst_channel = nullptr;
        for (const ChannelReport& c : report.channels)
          if (c.step == step && (!worst_channel || !(error_metric(c.all(), bound) <= error_metric(worst_channel->all(), bound))))
            worst_channel = &c;
        rows.push_back(judge_bound(case_name, bound,
                                   fmt::format("{} ({})", worst_channel->image, worst_channel->channel),
                                   error_metric(worst_channel->all(), bound), limits));
      }
    }
  }
  return rows;
}

BoundRow study_row(const std::string& case_name, bool pass, long failed_checks) {
  BoundRow row;
  row.case_name = case_name, row.bound = "study_checks", row.where = "failed checks";
  row.measured = static_cast<double>(failed_checks), row.limit = 0, row.margin = -row.measured;
  row.fail = 0;
  row.verdict = pass ? BoundVerdict::pass : BoundVerdict::fail;
  return row;
}

Table bound_table(const std::vector<BoundRow>& rows) {
  Table t({"case", "bound", "where", "measured", "limit", "margin", "warn", "fail", "hard_fail", "verdict"});
  for (const char* c : {"measured", "margin", "warn", "fail", "hard_fail"}) t.allow_missing(c);
  for (const char* c : {"measured", "limit", "margin", "warn", "fail", "hard_fail"}) t.set_format(c, "{:.4g}");
  auto opt = [](const std::optional<double>& v) { return v ? *v : kNaN; };
  for (const BoundRow& r : rows)
    t.add_row({r.case_name, r.bound, r.where, r.measured, r.limit, r.margin, opt(r.warn), opt(r.fail),
               opt(r.hard_fail), std::string(bound_verdict_name(r.verdict))});
  return t;
}

BoundVerdict worst(const std::vector<BoundRow>& rows) {
  BoundVerdict w = BoundVerdict::pass;
  for (const BoundRow& r : rows) w = std::max(w, r.verdict);
  return w;
}

void use_bounds(const BoundSet& set, VerifyOptions& options, std::optional<double> threshold) {
  if (threshold && *threshold != set.threshold)
    throw OptionError(Option::threshold,
                      fmt::format("{} differs from the bounds file's threshold {}", *threshold, set.threshold));
  options.threshold = set.threshold;
  options.allow_nan = set.limits.count(Bound::max_nan) > 0;
}

}  // namespace vrv
