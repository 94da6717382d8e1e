#include "studies/cli/memory_limit.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "studies/engine/memory_budget.h"

namespace vrv::cli {

double memory_limit_bytes(double max_memory_gib) {
  if (max_memory_gib < 0 || !std::isfinite(max_memory_gib))
    throw std::invalid_argument(fmt::format("--max-memory: must be a positive number of GiB, got {}", max_memory_gib));
  return max_memory_gib > 0 ? max_memory_gib * double(1 << 30) : default_memory_limit();
}

std::string memory_text(double bytes) {
  return bytes >= 0.1 * double(1 << 30) ? gibibytes(bytes) : fmt::format("{:.1f} MiB", bytes / (1 << 20));
}

void check_memory(double bytes, double limit, const std::string& who, const std::string& command,
                  const std::string& detail) {
  if (bytes <= limit) return;
  throw std::invalid_argument(fmt::format("{}: the {} needs about {} ({}), more than the limit of {} (raise it with "
                                          "--max-memory GIB)",
                                          who, command, memory_text(bytes), detail, memory_text(limit)));
}

}  // namespace vrv::cli
