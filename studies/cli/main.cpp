// The vrv command line: one subcommand per job; errors are one line on stderr, exit code 2
// (other codes: studies/cli_support.h and README, "Exit codes").
#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "lib/io/error_line.h"
#include "lib/util/ranks.h"
#include "studies/cli/cli_support.h"
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

// CLI11's own wording (and exit codes 104, 106, 109, ...) never reaches the user: every parse
// error becomes one "vrv: error: ..." line naming the option, with exit code 2.
std::string parse_error_line(const CLI::App& app, const CLI::ParseError& e) {
  const std::string what = vrv::one_line(e.what());
  // By type: CLI11 names some errors after the subcommand (ExtrasError(name, args)).
  if (dynamic_cast<const CLI::ExtrasError*>(&e)) {
    const std::string prefix = "not expected: ";
    const auto at = what.find(prefix);
    const std::string args = at == std::string::npos ? what : what.substr(at + prefix.size());
    return fmt::format("unknown option or argument {} (vrv --help, vrv COMMAND --help)", args);
  }
  if (dynamic_cast<const CLI::RequiredError*>(&e) && what.starts_with("A subcommand")) {
    const auto& extras = app.remaining();
    if (!extras.empty() && !extras.front().starts_with("-"))
      return fmt::format("unknown command '{}' (ray, render, study or demo; vrv --help)", extras.front());
    return "a command is required: ray, render, study or demo (vrv --help)";
  }
  if (dynamic_cast<const CLI::ConversionError*>(&e)) {
    // "Could not convert: --width = 1e9": say what the option takes.
    const std::string prefix = "Could not convert: ";
    const auto eq = what.find(" = ");
    if (what.starts_with(prefix) && eq != std::string::npos) {
      const std::string option = what.substr(prefix.size(), eq - prefix.size());
      std::string type = "value";
      for (const CLI::App* sub : app.get_subcommands())
        for (const CLI::Option* o : sub->get_options())
          if (o->check_name(option)) type = o->get_type_name();
      if (type == "INT") type = "integer";
      if (type == "FLOAT") type = "number";
      return fmt::format("{}: '{}' is not a valid {}", option, what.substr(eq + 3), type);
    }
  }
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&e)) {
    // "--origin: 1 required TEXT missing"
    const auto colon = what.find(": ");
    if (colon != std::string::npos && what.ends_with(" missing"))
      return fmt::format("{}: a value is required", what.substr(0, colon));
    // "--origin: At Most 1 required but received 2": the option was given twice.
    if (colon != std::string::npos && what.find("At Most 1 required but received") != std::string::npos)
      return fmt::format("{}: given more than once (give it once)", what.substr(0, colon));
    return fmt::format("{} (vrv COMMAND --help)", what);
  }
  return what;
}

// Results go to standard output (std::cout writes through C stdio, as fmt::print does): a write
// error there (a full disk, /dev/full) loses them, so every exit path flushes and checks it, and a
// failure is one line and kExitWriteFailed instead of a success.
int checked_exit(int code) {
  std::cout.flush();
  const bool flushed = std::fflush(stdout) == 0;
  const int error = errno;
  if (flushed && !std::ferror(stdout) && std::cout.good()) return code;
  std::cerr << "vrv: error: standard output: "
            << (flushed ? "a write failed" : std::strerror(error)) << "; the results printed are incomplete\n";
  return vrv::cli::kExitWriteFailed;
}

// An error's line on stderr and its exit code; under MPI every rank ends (lib/util/ranks.h).
int fail(int code, const std::string& line) {
  if (vrv::rank_count() > 1) {
    std::cout.flush();
    vrv::end_ranks(code, line);
  }
  if (!line.empty()) std::cerr << line << '\n';
  return code;
}

// The commands that spread their work over MPI ranks; the others would run whole on every rank,
// each writing the same outputs (docs/distributed.md).
constexpr std::array<std::string_view, 4> kDistributedCommands = {"render", "verify", "gate", "study"};

void check_distributable(const std::vector<std::string>& args) {
  if (vrv::rank_count() <= 1) return;
  if (args.size() >= 2 && std::ranges::find(kDistributedCommands, args[1]) != kDistributedCommands.end()) return;
  throw std::invalid_argument(fmt::format(
      "mpirun: {} ranks: only vrv {} are spread over MPI ranks so far; run {} as one process (docs/distributed.md)",
      vrv::rank_count(), fmt::join(kDistributedCommands, ", vrv "), args.size() < 2 ? "vrv" : "vrv " + args[1]));
}

int run(CLI::App& app, const std::vector<std::string>& args, std::vector<char*>& ptrs) {
  try {
    check_distributable(args);
    app.parse(static_cast<int>(ptrs.size()), ptrs.data());
  } catch (const CLI::Success& e) {
    return app.exit(e);  // --help
  } catch (const CLI::ParseError& e) {
    return fail(vrv::cli::kExitBadInput, "vrv: error: " + parse_error_line(app, e));
  } catch (const vrv::cli::CommandFailed& e) {
    // An outcome (a check failed, --tol missed, NaN pixels) that every MPI rank reaches in step
    // with the same results: each ends normally with the code, which mpirun passes on.
    if (*e.what()) std::cerr << vrv::one_line(e.what()) << '\n';
    return e.code();
  } catch (const std::exception& e) {
    return fail(vrv::cli::kExitBadInput, "vrv: error: " + vrv::one_line(e.what()));
  }
  return vrv::cli::kExitPass;
}

}  // namespace

int main(int argc, char** argv) {
  const vrv::RankSession ranks(&argc, &argv);
  CLI::App app{"vrv: how wrong is a volume raycaster, why, and what accuracy costs"};
  app.require_subcommand(1);
  // In the order a newcomer needs them: what vrv shows, one ray, one image, the studies.
  vrv::cli::add_demo_command(app);
  vrv::cli::add_ray_command(app);
  vrv::cli::add_render_command(app);
  vrv::cli::add_study_command(app);
  vrv::cli::add_plan_command(app);
  vrv::cli::add_export_command(app);
  vrv::cli::add_verify_command(app);
  vrv::cli::add_gate_command(app);
  vrv::cli::add_scene_command(app);
  std::vector<std::string> args = glue_negative_values(argc, argv);
  std::vector<char*> ptrs;
  for (auto& a : args) ptrs.push_back(a.data());
  return checked_exit(run(app, args, ptrs));
}
