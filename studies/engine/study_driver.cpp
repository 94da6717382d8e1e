#include "studies/engine/study_driver.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "lib/io/table.h"

namespace vrv {
namespace {
// Function-local so registration from other translation units' static objects is order-safe.
struct Registered {
  StudyParse parse = nullptr;
  StudyGrids grids = nullptr;
};
std::map<std::string, Registered, std::less<>>& registry() {
  static std::map<std::string, Registered, std::less<>> kinds;
  return kinds;
}
}  // namespace

RegisterStudyKind::RegisterStudyKind(std::string kind, StudyParse parse, StudyGrids grids) {
  registry().emplace(std::move(kind), Registered{parse, grids});
}

std::string_view check_kind_name(CheckKind kind) {
  switch (kind) {
    case CheckKind::derived: return "derived";
    case CheckKind::regression: return "regression";
    case CheckKind::identity: return "identity";
    case CheckKind::finite: return "finite";
    case CheckKind::unlabelled: break;
  }
  return "unlabelled";
}

StudyParse find_study_kind(std::string_view kind) {
  const auto it = registry().find(kind);
  return it == registry().end() ? nullptr : it->second.parse;
}

StudyGrids find_study_grids(std::string_view kind) {
  const auto it = registry().find(kind);
  return it == registry().end() ? nullptr : it->second.grids;
}

std::vector<std::string> study_kinds() {
  std::vector<std::string> out;
  for (const auto& [kind, registered] : registry()) out.push_back(kind);
  return out;
}

StudyCheck order_check(std::string name, const OrderEstimate& fit, double expected, const OrderTolerance& tolerance) {
  const double bound = order_tolerance(fit, tolerance);
  std::string detail =
      fit.points < 3
          ? fmt::format("observed {:.4f}, expected {:g}: {} steps give the fit no spread to derive a "
                        "tolerance from (needs 3)", fit.order, expected, fit.points)
          : fmt::format("observed {:.4f}, expected {:g}, SE {:.2g} over {} steps: |observed - expected| <= "
                        "max({:g} x {:.2f} x SE, {:g})", fit.order, expected, fit.standard_error, fit.points,
                        tolerance.margin, fit.bias_factor, tolerance.floor);
  return {std::move(name), std::abs(fit.order - expected), bound, order_matches(fit, expected, tolerance),
          std::move(detail), CheckKind::derived};
}

CheckTables check_tables(const std::string& study_name, const std::vector<StudyCheck>& checks) {
  Table t({"check", "value", "bound", "pass", "kind", "detail"});
  t.allow_missing("value");
  t.allow_missing("bound");
  t.set_format("value", "{:.4g}");
  t.set_format("bound", "{:.4g}");
  long failed = 0;
  for (const StudyCheck& c : checks) {
    t.add_row({c.name, c.value, c.bound, std::string(c.pass ? "true" : "false"), std::string(check_kind_name(c.kind)),
               c.detail});
    failed += c.pass ? 0 : 1;
  }
  LatexStyle style;
  style.caption = fmt::format("Checks of the {} study: {} of {} pass.", study_name,
                              static_cast<long>(checks.size()) - failed, checks.size());
  style.label = "tab:" + study_name + "-checks";
  return {t.to_csv(), t.to_markdown(), t.to_latex(style)};
}

}  // namespace vrv
