#include "lib/verify/verify_report.h"

#include <cmath>

#include "lib/util/enum_names.h"

namespace vrv {
namespace {

constexpr NameTable<Region, 5> kRegionNames{{{Region::outside, "outside"},
                                             {Region::interior, "interior"},
                                             {Region::silhouette, "silhouette"},
                                             {Region::tf_jump, "tf_jump"},
                                             {Region::all, "all"}}};
static_assert(names_complete(kRegionNames));

constexpr NameTable<OrderKind, 2> kOrderKindNames{{{OrderKind::reference, "reference"}, {OrderKind::self, "self"}}};
static_assert(names_complete(kOrderKindNames));

constexpr NameTable<FaultKind, 10> kFaultNames{{{FaultKind::quantisation, "quantisation"},
                                               {FaultKind::half_step_offset, "half-step offset"},
                                               {FaultKind::constant_floor, "constant floor"},
                                               {FaultKind::first_order_border_band, "first-order border band"},
                                               {FaultKind::jitter, "jitter"},
                                               {FaultKind::error_at_tf_jumps, "error at transfer-function jumps"},
                                               {FaultKind::missing_opacity_correction, "missing opacity correction"},
                                               {FaultKind::swapped_channels, "swapped channels"},
                                               {FaultKind::gradient_floor, "gradient floor"},
                                               {FaultKind::fitted, "fitted fault"}}};
static_assert(names_complete(kFaultNames));

nlohmann::ordered_json number(double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nullptr; }

nlohmann::ordered_json to_json(const ErrorStats& s) {
  return {{"count", s.count}, {"max", number(s.max)}, {"mean", number(s.mean)}, {"rms", number(s.rms)},
          {"p99", number(s.p99)}, {"fraction_over", number(s.fraction_over)},
          {"mean_signed", number(s.mean_signed)}};
}

nlohmann::ordered_json to_json(const OrderEstimate& f) {
  return {{"order", number(f.order)}, {"std_error", number(f.standard_error)}, {"points", f.points}};
}

nlohmann::ordered_json to_json(const ReferenceInfo& r) {
  nlohmann::ordered_json missed = nlohmann::ordered_json::array();
  for (auto [x, y] : r.missed_pixels) missed.push_back({x, y});
  return {{"tol", r.tol}, {"max_error_estimate", number(r.max_error_estimate)},
          {"missed", r.missed}, {"missed_pixels", missed}, {"from_cache", r.from_cache},
          {"cache_file", r.cache_file}, {"hit_pixels", r.hit_pixels},
          {"silhouette_pixels", r.silhouette_pixels}, {"tf_jump_pixels", r.jump_pixels}};
}

nlohmann::ordered_json to_json(const ChannelReport& c) {
  nlohmann::ordered_json regions;
  for (const RegionStats& s : c.regions) regions[std::string(region_name(s.region))] = to_json(s.stats);
  return {{"image", c.image}, {"channel", c.channel}, {"step", c.step}, {"alpha", c.alpha},
          {"nan_count", c.nan_count}, {"quantum", c.quantum}, {"floor_rms", c.floor_rms},
          {"at_floor", c.at_floor}, {"regions", regions}};
}

nlohmann::ordered_json to_json(const OrderReport& o) {
  nlohmann::ordered_json e = to_json(o.fit);
  e["channel"] = o.channel;
  e["kind"] = order_kind_name(o.kind);
  e["verdict"] = verdict_name(o.judgement.verdict);
  e["reason"] = o.judgement.reason;
  e["steps"] = o.steps;
  nlohmann::ordered_json errs = nlohmann::ordered_json::array();
  for (double v : o.errors) errs.push_back(number(v));
  e["errors"] = errs;
  return e;
}

nlohmann::ordered_json to_json(const Candidate& c) {
  nlohmann::ordered_json j = {{"name", c.name}, {"placement", c.placement}, {"rule", c.rule}, {"opacity", c.opacity},
                              {"color", c.color}, {"table", c.table}};
  if (!c.gradient.empty()) j["gradient"] = c.gradient;  // shaded scenes only: an unshaded report as before
  j["rms"] = number(c.rms);
  j["max"] = number(c.max);
  j["pixels"] = c.pixels;
  return j;
}

nlohmann::ordered_json to_json(const FaultFit& f) {
  return {{"id", f.id}, {"name", f.name}, {"parameter", f.parameter}, {"value", number(f.value)},
          {"explained", number(f.explained)}, {"confirmed", number(f.confirmed)}, {"pixels", f.pixels},
          {"confirm_pixels", f.confirm_pixels}, {"description", f.description}};
}

template <class T>
nlohmann::ordered_json array_of(const std::vector<T>& items) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const T& item : items) out.push_back(to_json(item));
  return out;
}

}  // namespace

std::string_view region_name(Region region) { return name_of(kRegionNames, region); }
std::string_view order_kind_name(OrderKind kind) { return name_of(kOrderKindNames, kind); }
std::string_view fault_name(FaultKind kind) { return name_of(kFaultNames, kind); }

const RegionStats* ChannelReport::region(Region which) const {
  for (const RegionStats& s : regions)
    if (s.region == which) return &s;
  return nullptr;
}

nlohmann::ordered_json to_json(const VerifyReport& rep) {
  nlohmann::ordered_json j;
  j["pass"] = rep.pass;
  j["verdict"] = verdict_name(rep.verdict.verdict);
  j["verdict_channel"] = rep.verdict_channel;
  j["verdict_reason"] = rep.verdict.reason;
  j["failures"] = rep.failures;
  j["expected_order"] = rep.expected_order ? nlohmann::ordered_json(*rep.expected_order) : nullptr;
  j["threshold"] = rep.threshold;
  j["order_metric"] = metric_name(rep.order_metric);
  j["width"] = rep.width;
  j["height"] = rep.height;
  j["reference"] = to_json(rep.reference);
  j["images"] = array_of(rep.channels);
  j["orders"] = array_of(rep.orders);
  if (rep.diagnosis_channel) j["diagnosis_channel"] = *rep.diagnosis_channel;  // RGB only: grey JSON as before
  j["diagnosis"] = array_of(rep.diagnosis);
  nlohmann::ordered_json faults = nlohmann::ordered_json::array();
  for (const Fault& f : rep.faults)
    faults.push_back({{"name", fault_name(f.kind)}, {"behaves_like", f.behaviour}, {"evidence", f.evidence}});
  j["faults"] = faults;
  j["fault_fits"] = array_of(rep.fault_fits);
  nlohmann::ordered_json conventions = nlohmann::ordered_json::array();
  for (const Fault& f : rep.conventions)
    conventions.push_back({{"name", fault_name(f.kind)}, {"behaves_like", f.behaviour},
                           {"implied_order", number(f.implied_order)}, {"evidence", f.evidence}});
  j["conventions"] = conventions;
  if (rep.mode) {  // projections only: an emission-absorption report's JSON is as before
    j["mode"] = *rep.mode;
    j["notes"] = rep.notes;
  }
  return j;
}

}  // namespace vrv
