#include "studies/cli/memory_limit.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "studies/engine/memory_budget.h"

namespace vrv::cli {

double memory_limit_bytes(std::optional<double> max_memory_gib) {
  if (!max_memory_gib) return default_memory_limit();
  if (!(*max_memory_gib > 0) || !std::isfinite(*max_memory_gib))
    throw std::invalid_argument(fmt::format("--max-memory: must be a positive number of GiB, got {}", *max_memory_gib));
  return *max_memory_gib * double(1 << 30);
}

CLI::Option* add_volume_memory_option(CLI::App& cmd, std::optional<double>& max_memory_gib) {
  return cmd.add_option("--max-memory", max_memory_gib,
                        "GiB the scene's volume file may take, checked from its header before its samples are "
                        "read (default: 3/4 of physical memory)");
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
