#pragma once
// Benchmark support: a console reporter that also keeps one counter of every benchmark over its
// repetitions (or its min/max/median aggregates when only those are displayed), for the ratio
// summaries the programs print at the end.  On a shared machine other jobs only ever slow a run
// down, so best() is the best repetition (lowest time or highest rate); median() is the check.
#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

namespace vrv::bench {

class CounterRecorder : public benchmark::ConsoleReporter {
 public:
  enum class Better { lower, higher };
  // key_with_args: key runs by "function/args" rather than the function name alone.
  CounterRecorder(std::string counter, Better better, bool key_with_args)
      : counter_(std::move(counter)), better_(better), key_with_args_(key_with_args) {}

  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& r : runs) {
      if (r.error_occurred) continue;
      const auto it = r.counters.find(counter_);
      if (it == r.counters.end()) continue;
      const std::string key =
          key_with_args_ ? r.run_name.function_name + "/" + r.run_name.args : r.run_name.function_name;
      if (r.run_type == Run::RT_Iteration) values_[key].push_back(it->second.value);
      else aggregates_[key][r.aggregate_name] = it->second.value;
    }
  }
  bool has(const std::string& key) const { return values_.count(key) || aggregates_.count(key); }
  double best(const std::string& key) const {
    const bool lower = better_ == Better::lower;
    if (const auto it = values_.find(key); it != values_.end())
      return lower ? *std::min_element(it->second.begin(), it->second.end())
                   : *std::max_element(it->second.begin(), it->second.end());
    return aggregate(key, lower ? "min" : "max");
  }
  double median(const std::string& key) const {
    if (const auto it = values_.find(key); it != values_.end()) {
      std::vector<double> v = it->second;
      std::sort(v.begin(), v.end());
      const std::size_t m = v.size() / 2;
      return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
    }
    return aggregate(key, "median");
  }

 private:
  double aggregate(const std::string& key, const std::string& name) const {
    const auto it = aggregates_.find(key);
    if (it == aggregates_.end()) return NAN;
    const auto a = it->second.find(name);
    return a == it->second.end() ? NAN : a->second;
  }
  std::string counter_;
  Better better_;
  bool key_with_args_;
  std::map<std::string, std::vector<double>> values_;
  std::map<std::string, std::map<std::string, double>> aggregates_;
};

}  // namespace vrv::bench
