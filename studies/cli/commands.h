#pragma once
// The `vrv` subcommands.  Each registers its options on the app and runs when chosen.
#include <CLI/CLI.hpp>

namespace vrv::cli {

void add_demo_command(CLI::App& app);
void add_ray_command(CLI::App& app);
void add_render_command(CLI::App& app);
void add_study_command(CLI::App& app);
void add_export_command(CLI::App& app);
void add_verify_command(CLI::App& app);
void add_gate_command(CLI::App& app);
void add_scene_command(CLI::App& app);
void add_plan_command(CLI::App& app);

}  // namespace vrv::cli
