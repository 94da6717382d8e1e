#include "studies/engine/memory_budget.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "lib/scene_file.h"

namespace vrv {
namespace {

void add_grid(StudyMemory& m, NodeCounts r) {
  m.bytes += grid_bytes(r);
  ++m.grids;
  if (grid_bytes(r) > grid_bytes(m.largest)) m.largest = r;
}

// Every [field] table's grid, wherever the file holds scenes (cases, lists of them).
void walk(const toml::node& n, StudyMemory& m) {
  if (const auto* a = n.as_array()) {
    for (const auto& e : *a) walk(e, m);
    return;
  }
  const auto* t = n.as_table();
  if (!t) return;
  if (const auto nodes = field_grid_nodes(*t)) add_grid(m, *nodes);
  for (const auto& [key, value] : *t) walk(value, m);
}

}  // namespace

std::optional<NodeCounts> largest_cube(const toml::table& t, std::string_view key) {
  const toml::node* n = t.get(key);
  if (!n) return std::nullopt;
  double largest = 0;
  const auto take = [&](const toml::node& e) {
    if (const auto v = e.value<double>(); v && *v >= 1 && *v <= 1e6 && *v == std::floor(*v)) largest = std::max(largest, *v);
  };
  if (const auto* a = n->as_array()) {
    for (const auto& e : *a) take(e);
  } else {
    take(*n);
  }
  if (!(largest >= 1)) return std::nullopt;
  const auto side = static_cast<std::int64_t>(largest);
  return NodeCounts{side, side, side};
}

StudyMemory estimate_study_memory(const toml::table& doc, StudyGrids own) {
  StudyMemory m;
  walk(doc, m);
  if (own)
    for (const NodeCounts& g : own(doc)) add_grid(m, g);
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
