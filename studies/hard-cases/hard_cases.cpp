#include "studies/hard-cases/hard_cases.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <utility>

#include <fmt/format.h>
#include <toml++/toml.h>

#include "lib/io/atomic_file.h"
#include "lib/io/table.h"
#include "lib/discrete_error_bound.h"
#include "lib/reference_integrator.h"
#include "lib/util/parallel.h"
#include "lib/util/progress.h"
#include "lib/work_estimate.h"
#include "studies/engine/reference_audit.h"

namespace vrv {
namespace {

constexpr std::size_t kMaxCases = 256;
constexpr std::size_t kMaxCaseMethods = 32;

void parse_hard_cases(const StudyReader& r, const toml::table& doc,
                      HardCasesStudy& s) {
  const toml::array* arr = r.require(doc, "case", "").as_array();
  if (!arr) r.fail("case", "expected an array of tables ([[case]])");
  if (arr->empty()) r.fail("case", "no cases");
  if (arr->size() > kMaxCases) r.fail("case", fmt::format("more than {} cases", kMaxCases));
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const std::string path = fmt::format("case[{}]", i);
    const toml::table& t = r.table(*arr->get(i), path);
    r.check_keys(t, path, {"name", "description", "scene", "origin", "direction", "method"});
    HardCase c;
    c.name = r.string(r.require(t, "name", path), path + ".name");
    if (c.name.empty()) r.fail(path + ".name", "empty");
    for (const HardCase& earlier : s.cases)
      if (earlier.name == c.name) r.fail(path + ".name", fmt::format("'{}' is listed twice", c.name));
    if (t.contains("description")) c.description = r.string(*t.get("description"), path + ".description");
    c.scene = read_study_scene(r, t, path, c.scene_toml);
    c.origin = r.vec3(t, "origin", path);
    c.direction = r.vec3(t, "direction", path);
    if (!(c.direction.cwiseAbs().maxCoeff() > 0)) r.fail(path + ".direction", "must not be zero");
    const toml::array* ma = r.require(t, "method", path).as_array();
    if (!ma) r.fail(path + ".method", "expected an array of tables ([[case.method]])");
    if (ma->empty()) r.fail(path + ".method", "no methods");
    if (ma->size() > kMaxCaseMethods)
      r.fail(path + ".method", fmt::format("more than {} methods", kMaxCaseMethods));
    for (std::size_t j = 0; j < ma->size(); ++j) {
      const std::string mpath = fmt::format("{}.method[{}]", path, j);
      HardCaseMethod m = read_study_method(r, r.table(*ma->get(j), mpath), mpath, c.scene);
      for (const HardCaseMethod& earlier : c.methods)
        if (earlier.label == m.label)
          r.fail(mpath, fmt::format("'{}' is listed twice (give a distinct label)", m.label));
      c.methods.push_back(std::move(m));
    }
    s.cases.push_back(std::move(c));
  }
}

}  // namespace

HardCasesStudy read_hard_cases_study(const StudyInput& in) {
  const StudyReader& r = in.reader;
  const toml::table& doc = in.doc;
  r.check_keys(doc, "", {"name", "kind", "description", "reference_tol", "case"});
  HardCasesStudy s;
  s.source = r.source();
  s.name = in.name;
  if (doc.contains("description")) s.description = r.string(*doc.get("description"), "description");
  s.reference_tol = read_reference_tol(r, doc, "", s.reference_tol);
  parse_hard_cases(r, doc, s);
  return s;
}

HardCasesStudy parse_hard_cases_study(std::string_view text, std::string_view source_name,
                                      std::string_view default_name) {
  return read_grey_study(text, source_name, default_name, read_hard_cases_study);
}

HardCasesStudy load_hard_cases_study(const std::filesystem::path& path) {
  return parse_hard_cases_study(read_study_text(path), path.string(), path.stem().string());
}

StudyWork hard_cases_work(const HardCasesStudy& study) {
  StudyWork work;
  for (const HardCase& hc : study.cases) {
    const Ray ray = make_ray(hc.origin, hc.direction);
    double per_ray = reference_evaluations(hc.scene, ray, study.reference_tol);  // the truth
    for (const HardCaseMethod& m : hc.methods) {
      if (m.reference) {
        per_ray += reference_evaluations(hc.scene, ray, m.tol);
        continue;
      }
      const double samples = discrete_samples(m.config, hc.scene, ray);
      const bool bounded = !m.max_error && why_no_error_bound(hc.scene, m.config).empty();
      per_ray += samples * (bounded ? 1 + kErrorBoundEvaluationsPerSegment : 1);
    }
    work.add(fmt::format("case {}", hc.name), 1, per_ray);
  }
  return work;
}

HardCasesResult run_hard_cases(const HardCasesStudy& study, ReferenceAudit& audit, bool progress,
                               const StudyCheckpoint& checkpoint) {
  const std::size_t C = study.cases.size();
  std::vector<std::pair<std::size_t, std::size_t>> jobs;  // (case, method)
  for (std::size_t c = 0; c < C; ++c)
    for (std::size_t m = 0; m < study.cases[c].methods.size(); ++m) jobs.emplace_back(c, m);
  std::vector<ReferenceResult> truth(C);
  std::vector<CaseRow> rows(jobs.size());
  Progress bar("study " + study.name, static_cast<long>(C + jobs.size()), progress);
  parallel_for_index(static_cast<long>(C), [&](long i) {
    const HardCase& hc = study.cases[static_cast<std::size_t>(i)];
    const std::vector<double> v = checkpointed(checkpoint, fmt::format("truth_{}", i), 2, [&] {
      const ReferenceResult r = audited_reference(audit, hc.scene, make_ray(hc.origin, hc.direction), {study.reference_tol});
      return std::vector<double>{r.value, r.error_estimate};
    });
    truth[static_cast<std::size_t>(i)].value = v[0];
    truth[static_cast<std::size_t>(i)].error_estimate = v[1];
    bar.advance();
  });
  parallel_for_index(static_cast<long>(jobs.size()), [&](long j) {
    const auto [c, m] = jobs[static_cast<std::size_t>(j)];
    const HardCase& hc = study.cases[c];
    const HardCaseMethod& method = hc.methods[m];
    const Ray ray = make_ray(hc.origin, hc.direction);
    CaseRow& row = rows[static_cast<std::size_t>(j)];
    row.case_name = hc.name;
    row.method = method.label;
    row.reference = method.reference;
    // One (case, method) is one checkpoint: value, bound, work.
    const std::vector<double> v = checkpointed(checkpoint, fmt::format("case_{}_{}", c, m), 3, [&] {
      if (method.reference) {
        const ReferenceResult r = integrate_reference(hc.scene, ray, {method.tol});
        return std::vector<double>{r.value, r.error_estimate, static_cast<double>(r.evaluations)};
      }
      const DiscreteResult d = discrete_raycast(hc.scene, ray, method.config);
      double bound = std::numeric_limits<double>::quiet_NaN();
      if (method.max_error) {
        bound = *method.max_error;
      } else if (const DiscreteErrorBound b = discrete_error_bound(hc.scene, ray, method.config); b.available()) {
        bound = b.bound;
      }
      return std::vector<double>{d.value, bound, static_cast<double>(d.samples)};
    });
    row.value = v[0];
    row.bound = v[1];
    row.bound_source = method.reference    ? BoundSource::reference
                       : method.max_error  ? BoundSource::stated
                       : std::isfinite(row.bound) ? BoundSource::a_priori
                                                  : BoundSource::none;
    row.samples = static_cast<long>(v[2]);
    bar.advance();
  });
  bar.finish();

  // Errors and verdicts in file order: the same bits for any thread count.
  HardCasesResult result;
  result.rays = static_cast<long>(C);
  std::size_t j = 0;
  for (std::size_t c = 0; c < C; ++c) {
    const ReferenceResult& t = truth[c];
    CaseSummary sum{study.cases[c].name, t.value, t.error_estimate, 0, true};
    const bool truth_ok = std::isfinite(t.value) && std::isfinite(t.error_estimate) &&
                          t.error_estimate <= study.reference_tol;
    if (!std::isfinite(t.value)) ++sum.nan_count;
    for (std::size_t m = 0; m < study.cases[c].methods.size(); ++m, ++j) {
      CaseRow& row = rows[j];
      const HardCaseMethod& method = study.cases[c].methods[m];
      row.finite = std::isfinite(row.value);
      row.error = std::abs(row.value - t.value);  // NaN if either is
      if (!row.finite) ++sum.nan_count;
      if (method.reference)
        // The truth is itself only within its estimate: error <= estimate + that, estimate <= tol.
        row.pass = row.finite && truth_ok && std::isfinite(row.bound) &&
                   row.error <= row.bound + t.error_estimate && row.bound <= method.tol;
      else if (row.bound_source == BoundSource::a_priori)
        row.pass = row.finite && truth_ok && row.error <= row.bound + t.error_estimate;
      else
        row.pass = row.finite && truth_ok && (!method.max_error || row.error <= *method.max_error);
      sum.pass = sum.pass && row.pass;
      result.cases.push_back(row);
    }
    sum.pass = sum.pass && truth_ok;
    result.pass = result.pass && sum.pass;
    result.case_summary.push_back(sum);
  }
  return result;
}

HardCaseFiles hard_case_tables(const HardCasesStudy& study, const HardCasesResult& result) {
  Table t({"case", "method", "value", "error", "bound", "finite", "samples", "pass"});
  for (const char* c : {"value", "error", "bound"}) t.allow_missing(c);
  t.set_format("value", "{:.12g}");
  t.set_format("error", "{:.2e}");
  t.set_format("bound", "{:.2e}");
  for (const CaseRow& r : result.cases)
    t.add_row({r.case_name, r.method, r.value, r.error, r.bound,
               std::string(r.finite ? "true" : "false"), r.samples,
               std::string(r.pass ? "true" : "false")});
  long nans = 0;
  for (const CaseSummary& c : result.case_summary) nans += c.nan_count;
  LatexStyle style;
  style.caption = fmt::format(
      "Hard cases: error against the reference at tolerance {:g}; bound: the reference's own "
      "error estimate, a stated maximum error, or the discrete rule's a-priori bound ({} cases, {} "
      "non-finite values).",
      study.reference_tol, result.case_summary.size(), nans);
  style.label = "tab:" + study.name;
  return {t.to_csv(), t.to_markdown(), t.to_latex(style)};
}

nlohmann::json hard_cases_parameters(const HardCasesStudy& study, bool quick, int threads) {
  nlohmann::ordered_json p;
  p["study"] = study.name;
  p["file"] = study.source;
  p["kind"] = "hard_cases";
  p["description"] = study.description;
  nlohmann::ordered_json cases = nlohmann::ordered_json::array();
  for (const HardCase& c : study.cases) {
    nlohmann::ordered_json methods = nlohmann::ordered_json::array();
    for (const HardCaseMethod& m : c.methods) {
      const nlohmann::ordered_json j = method_json(m);
      methods.push_back(j);
    }
    cases.push_back({{"name", c.name},
                     {"description", c.description},
                     {"scene", c.scene_toml},
                     {"origin", {c.origin[0], c.origin[1], c.origin[2]}},
                     {"direction", {c.direction[0], c.direction[1], c.direction[2]}},
                     {"methods", methods}});
  }
  p["cases"] = cases;
  p["reference_tol"] = study.reference_tol;
  p["quick"] = quick;  // recorded only; quick runs the same cases
  p["threads"] = threads;
  return nlohmann::json::parse(p.dump());
}

nlohmann::json case_summary_json(const HardCasesResult& result) {
  auto finite_or_null = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
  nlohmann::json summary = nlohmann::json::array();
  for (const CaseSummary& c : result.case_summary)
    summary.push_back({{"name", c.name},
                       {"reference", finite_or_null(c.truth)},
                       {"reference_estimate", finite_or_null(c.truth_estimate)},
                       {"nan_count", c.nan_count},
                       {"pass", c.pass}});
  return summary;
}

void write_hard_case_tables(const std::filesystem::path& dir, const HardCasesStudy& study,
                            const HardCasesResult& result) {
  const HardCaseFiles h = hard_case_tables(study, result);
  write_file_atomically(dir / "cases.csv", h.cases_csv);
  write_file_atomically(dir / "cases.md", h.cases_md);
  write_file_atomically(dir / "cases.tex", h.cases_tex);
}

}  // namespace vrv
