#include "studies/engine/memory_budget.h"

#include <unistd.h>

#include <algorithm>

#include <fmt/format.h>

namespace vrv {
namespace {

constexpr double kBytesPerNode = sizeof(double);

// Positive integers of an array, or nothing if any element is something else.
std::vector<std::int64_t> integers(const toml::array& a) {
  std::vector<std::int64_t> out;
  for (const auto& e : a) {
    const auto* i = e.as_integer();
    if (!i || i->get() <= 0) return {};
    out.push_back(i->get());
  }
  return out;
}

void add_grid(StudyMemory& m, std::array<std::int64_t, 3> r) {
  const double nodes = static_cast<double>(r[0]) * static_cast<double>(r[1]) * static_cast<double>(r[2]);
  m.bytes += nodes * kBytesPerNode;
  ++m.grids;
  const double largest = static_cast<double>(m.largest[0]) * static_cast<double>(m.largest[1]) *
                         static_cast<double>(m.largest[2]);
  if (nodes > largest) m.largest = r;
}

void walk(const toml::node& n, StudyMemory& m) {
  if (const auto* a = n.as_array()) {
    for (const auto& e : *a) walk(e, m);
    return;
  }
  const auto* t = n.as_table();
  if (!t) return;
  for (const auto& [key, value] : *t) {
    const auto* a = value.as_array();
    if (a && key.str() == "resolution") {
      const auto r = integers(*a);
      if (r.size() == 3) add_grid(m, {r[0], r[1], r[2]});
    } else if (a && (key.str() == "resolutions" || key.str() == "quick_resolutions")) {
      const auto r = integers(*a);  // built one at a time: the largest counts
      if (!r.empty()) {
        const std::int64_t n3 = *std::max_element(r.begin(), r.end());
        add_grid(m, {n3, n3, n3});
      }
    } else {
      walk(value, m);
    }
  }
}

}  // namespace

StudyMemory estimate_study_memory(const toml::table& doc) {
  StudyMemory m;
  walk(doc, m);
  return m;
}

double default_memory_limit() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? 0.75 * static_cast<double>(pages) * static_cast<double>(page) : 4.0 * (1 << 30);
}

std::string gibibytes(double bytes) { return fmt::format("{:.1f} GiB", bytes / (1 << 30)); }

std::string describe(const StudyMemory& m) {
  return fmt::format("about {} ({} grid{}, the largest {}x{}x{})", gibibytes(m.bytes), m.grids,
                     m.grids == 1 ? "" : "s", m.largest[0], m.largest[1], m.largest[2]);
}

}  // namespace vrv
