#pragma once
// --max-memory for the commands that allocate in proportion to their input (vrv export: the grid
// and rays.npy; vrv render: the image), in vrv study's vocabulary (studies/engine/memory_budget.h):
// a limit in GiB, by default three quarters of physical memory, and a refusal before anything is
// allocated that names the input responsible and the estimate.
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace vrv::cli {

// The limit in bytes for --max-memory GIB (not given: default_memory_limit()); std::invalid_argument
// naming --max-memory for a value that is not a positive finite number (0 too: it is not a way to
// ask for the default).
double memory_limit_bytes(std::optional<double> max_memory_gib);

// --max-memory for the commands whose one large allocation is the scene's volume (ray, verify,
// plan, demo, gate, scene): the volume file is refused from its header above it (a volume without a
// limit was read until std::bad_alloc, naming no file).
CLI::Option* add_volume_memory_option(CLI::App& cmd, std::optional<double>& max_memory_gib);

// "12.0 GiB" as vrv study says it, "3.0 MiB" below a tenth of a GiB (a small limit reads as such).
std::string memory_text(double bytes);

// std::invalid_argument "<who>: the <command> needs about <bytes> (<detail>), more than the limit
// of <limit> (raise it with --max-memory GIB)" when bytes > limit.
void check_memory(double bytes, double limit, const std::string& who, const std::string& command,
                  const std::string& detail);

}  // namespace vrv::cli
