// The vrv command line: one subcommand per job; errors are one line on stderr, exit code 2.
#include <cstring>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "studies/cli/commands.h"

namespace {

// CLI11 would read "--origin -3,0.5,0" as the option "-3,0.5,0"; users type negative
// vectors that way, so the value is glued on ("--origin=-3,0.5,0") before parsing.
std::vector<std::string> glue_negative_values(int argc, char** argv) {
  std::vector<std::string> args(argv, argv + argc);
  std::vector<std::string> out;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    const bool next_is_negative_number =
        i + 1 < args.size() && args[i + 1].size() > 1 && args[i + 1][0] == '-' &&
        (std::isdigit(static_cast<unsigned char>(args[i + 1][1])) || args[i + 1][1] == '.');
    if (a.starts_with("--") && a.find('=') == std::string::npos && next_is_negative_number) {
      out.push_back(a + "=" + args[i + 1]);
      ++i;
    } else {
      out.push_back(a);
    }
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"vrv: how wrong is a volume raycaster, why, and what accuracy costs"};
  app.require_subcommand(1);
  // In the order a newcomer needs them: what vrv shows, one ray, one image, the studies.
  vrv::cli::add_demo_command(app);
  vrv::cli::add_ray_command(app);
  vrv::cli::add_render_command(app);
  vrv::cli::add_study_command(app);
  vrv::cli::add_export_command(app);
  vrv::cli::add_verify_command(app);
  vrv::cli::add_gate_command(app);
  std::vector<std::string> args = glue_negative_values(argc, argv);
  std::vector<char*> ptrs;
  for (auto& a : args) ptrs.push_back(a.data());
  try {
    app.parse(static_cast<int>(ptrs.size()), ptrs.data());
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::cerr << "vrv: error: " << e.what() << '\n';
    return 2;
  }
  return 0;
}
