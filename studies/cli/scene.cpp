// vrv scene --print [FILE]: the scene as TOML, checked as every command checks it, the embedded
// default when no file is given.  What `vrv export` writes as scene.toml reads back the same way.
#include <iostream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "lib/scene_file.h"
#include "studies/cli/commands.h"
#include "studies/cli/memory_limit.h"

namespace vrv::cli {

void add_scene_command(CLI::App& app) {
  auto file = std::make_shared<std::string>();
  auto print = std::make_shared<bool>(false);
  auto max_memory_gib = std::make_shared<std::optional<double>>();
  CLI::App* cmd = app.add_subcommand("scene", "Print a scene as TOML (the embedded default without FILE)");
  cmd->footer("stdout: the scene's TOML, every number to the digits that read back to the same value.");
  cmd->add_flag("--print", *print, "Print the scene (the only action, and the default)");
  cmd->add_option("FILE", *file, "Scene file (TOML); the embedded default when omitted");
  add_volume_memory_option(*cmd, *max_memory_gib);
  cmd->callback([file, print, max_memory_gib] {
    const double limit = memory_limit_bytes(*max_memory_gib);
    const std::string text = file->empty() ? std::string(default_scene_toml()) : read_scene_text(*file);
    const std::string out = scene_toml(text, file->empty() ? "<default scene>" : *file, limit);
    std::cout << out << std::flush;
    if (!std::cout) throw std::runtime_error("stdout: write error");
  });
}

}  // namespace vrv::cli
