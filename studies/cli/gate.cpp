// vrv gate: runs what a bounds file names (vrv's own methods rendered at several steps, a
// renderer's images, or studies) and gates each on its bounds.  See docs/verify.md.
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include <fmt/format.h>

#include "lib/bounds_file.h"
#include "lib/discrete_channels.h"
#include "lib/io/error_line.h"
#include "lib/io/output_paths.h"
#include "lib/verify/verify_output.h"
#include "lib/util/parallel.h"
#include "lib/util/ranks.h"
#include "lib/scene_file.h"
#include "lib/scene_mode.h"
#include "lib/work_estimate.h"
#include "studies/cli/memory_limit.h"
#include "studies/cli/verify_run.h"
#include "studies/cli/cli_support.h"
#include "studies/cli/commands.h"
#include "studies/cli/discrete_flags.h"
#include "studies/engine/study_runner.h"

namespace vrv::cli {
namespace {

namespace fs = std::filesystem;

struct GateOptions {
  std::string bounds, out, case_name, cache_dir;
  bool no_cache = false, plots = false, no_diagnosis = false, quiet = false;
  bool report = false;  // --report: OUT/<case>/report.html
  int threads = 0;
  double max_work = kDefaultVerifyWorkLimit;
  std::optional<double> max_memory_gib;  // --max-memory: each case's scene volume
};

// `vrv study NAME --quick` in a child process (this executable), with gate's --max-memory when
// given, its checks read back from meta.json.  Returns the child's exit code.
int run_study_case(const GateCase& c, const fs::path& out, const std::optional<double>& max_memory_gib, long& failed) {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("gate: cannot find the vrv executable to run a study");
  const std::string exe = self.string(), dir = out.string();
  const std::string log = (out / (c.name + ".stderr.log")).string();
  std::vector<std::string> args{exe, "study", c.study, "--quick", "--quiet", "--no-plots", "--out", dir};
  if (max_memory_gib) args.insert(args.end(), {"--max-memory", fmt::format("{}", *max_memory_gib)});
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("gate: cannot start a study");
  if (pid == 0) {
    // The study's own messages and its JSON line go to a log beside its results: gate's own
    // output is its table and one line of ours.
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) dup2(fd, 2), dup2(fd, 1);
    execv(argv[0], argv.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return 127;
  const int rc = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
  failed = 0;
  std::ifstream meta(out / c.study / "meta.json");
  if (meta) {
    const auto j = nlohmann::json::parse(meta, nullptr, false);
    if (!j.is_discarded() && j.contains("checks"))
      for (const auto& check : j["checks"]) failed += !check.value("pass", false);
  }
  return rc;
}

// The render case's method at step h, as `vrv render --method ... --step h` takes it.
DiscreteOptions discrete_options(const GateRenderSpec& spec, double h) {
  DiscreteOptions d = spec.options;
  d.step = h;
  return d;
}

// The camera a render case renders with: the scene's (or the default), at the case's size.
Camera case_camera(const GateCase& c, const Scene& scene) {
  Camera camera = scene.camera ? *scene.camera : default_camera(scene.box);
  if (c.width) camera.width = *c.width;
  if (c.height) camera.height = *c.height;
  validate(camera);
  return camera;
}

// A render case above --max-work (its renders at every step and the reference) is refused before
// any case runs: 4096 x 4096 at step 1e-6 (about 1e14 samples) started at once.
void check_render_work(const GateCase& c, const Scene& scene, const BoundsFile& file, double max_work) {
  const Camera camera = case_camera(c, scene);
  double renders = 0;
  for (double h : c.steps) {
    const DiscreteConfig config = *discrete_config(discrete_options(*c.render, h), scene);
    renders += camera_work(scene, camera, 0, &config);
  }
  check_verification_work(scene, VerifyOptions{}, camera.width, camera.height, c.steps, renders, max_work,
                          fmt::format("{}: case[{}]", file.path.string(), &c - file.cases.data()));
}

std::vector<ImageWithStep> render_case(const GateCase& c, const Scene& scene) {
  const Camera camera = case_camera(c, scene);
  std::vector<ImageWithStep> images;
  for (double h : c.steps) {
    const DiscreteConfig config = *discrete_config(discrete_options(*c.render, h), scene);
    ChannelImage im(discrete_channel_image(scene, camera, config));  // as vrv render casts it
    im.pixel_type = "float";                                          // and writes it
    double largest = 0;
    for (double& x : im.pixels) x = static_cast<float>(x), largest = std::max(largest, std::abs(x));
    im.quantum = stored_quantum(im.pixel_type, largest);
    images.push_back({fmt::format("{} h={:g}", c.name, h), h, std::move(im)});
  }
  return images;
}

// The case's steps, or for an images case without them each image's provenance step (as
// `vrv verify` without --steps); one line naming the bounds file, case and image otherwise.
std::vector<double> case_steps(const GateCase& c, const std::string& bounds) {
  if (!c.steps.empty()) return c.steps;
  std::vector<double> steps;
  for (const fs::path& image : c.images) {
    std::optional<double> step;
    try {
      step = provenance_step(image.string());
    } catch (const VerifyInputError& e) {
      throw std::invalid_argument(fmt::format("{}: case {}: {}", bounds, c.name, e.what()));
    }
    if (!step)
      throw std::invalid_argument(fmt::format("{}: case {}: steps: not given, and {} has no step in its provenance "
                                              "(vrv:step metadata): give steps = [H1, H2, ...] one per image",
                                              bounds, c.name, image.string()));
    steps.push_back(*step);
  }
  return steps;
}

// A study case names a study `vrv study --list` finds: anything else (a path, "--help") would be
// passed to `vrv study` as an argument.
void check_study_name(const BoundsFile& file, const GateCase& c) {
  std::string known;
  for (const auto& [name, path] : find_studies()) {
    if (name == c.study) return;
    known += (known.empty() ? "" : ", ") + name;
  }
  throw std::invalid_argument(error_line(file.path.string(), fmt::format("case[{}].study", &c - file.cases.data()),
                                         fmt::format("'{}' is not a study vrv knows ({})", c.study, known)));
}

// Without --out the gate writes into a temporary folder (its table goes to stderr, its verdict to
// stdout), removed on every way out of run_gate, errors included.
struct TemporaryFolder {
  fs::path dir;
  ~TemporaryFolder() {
    std::error_code ec;
    if (!dir.empty()) fs::remove_all(dir, ec);
  }
};

int run_gate(const GateOptions& o) {
  check_threads(o.threads);
  const double memory_limit = memory_limit_bytes(o.max_memory_gib);  // checked even when every case is a study
  const BoundsFile file = load_bounds(o.bounds);
  std::vector<const GateCase*> cases;
  if (!o.case_name.empty()) cases.push_back(&named_case(file, o.case_name));
  else
    for (const GateCase& c : file.cases) cases.push_back(&c);
  if (cases.empty()) throw std::invalid_argument(fmt::format("--bounds: {}: no [[case]] to run", o.bounds));
  // Check every case's input before running any.
  std::vector<Scene> scenes;
  std::vector<std::vector<double>> steps;
  for (const GateCase* c : cases) {
    if (!c->study.empty()) {
      check_study_name(file, *c);
      if (rank_count() > 1)
        throw std::invalid_argument(fmt::format(
            "{}: case {}: a study case runs vrv study as a child process, outside the MPI run; run this gate "
            "as one process, or --case a render or images case, or mpirun vrv study itself (docs/distributed.md)",
            o.bounds, c->name));
      scenes.emplace_back();
      steps.emplace_back();
      continue;
    }
    scenes.push_back(load_scene_or_default(c->scene.string(), memory_limit));
    steps.push_back(case_steps(*c, o.bounds));
    const bool projection = scene_mode(scene_text_or_default(c->scene.string())).has_value();
    if (c->render && projection)
      throw std::invalid_argument(fmt::format("{}: case {}: render: the scene has a projection mode, which a render "
                                              "case does not render; give the renderer's images", o.bounds, c->name));
    // Before any case runs: a projection of a shaded scene is refused (verify_images would refuse
    // it mid-run).
    if (projection) require_unshaded(scenes.back(), c->scene.string(), "vrv gate (a projection's images)");
    if (projection) require_grey(scenes.back(), c->scene.string(), "vrv gate (a projection's images)");
    if (c->render) {
      try {
        discrete_config(discrete_options(*c->render, c->steps.front()), scenes.back());
      } catch (const OptionError& e) {  // named by the key the bounds file uses
        throw std::invalid_argument(fmt::format("{}: case {}: render: {}", o.bounds, c->name, e.message(Spelling::key)));
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(fmt::format("{}: case {}: render: {}", o.bounds, c->name, e.what()));
      }
      check_render_work(*c, scenes.back(), file, o.max_work);
    }
  }
  // Under MPI (docs/distributed.md) every rank verifies each case; rank 0 alone writes.
  const bool writer = is_output_rank();
  const fs::path out = o.out.empty() ? fs::temp_directory_path() / fmt::format("vrv-gate-{}", getpid()) : fs::path(o.out);
  TemporaryFolder temporary{o.out.empty() && writer ? out : fs::path()};
  if (writer) check_writable_dir(out, "--out");
  const fs::path cache = reference_cache_dir(o.cache_dir, o.no_cache);
  const ThreadLimit threads(o.threads);
  std::vector<BoundRow> rows;
  nlohmann::ordered_json case_json = nlohmann::ordered_json::array();
  bool pass = true;
  const PixelSharing sharing;  // every rank meets the same cases' image loops in the same order
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const GateCase& c = *cases[i];
    if (!c.study.empty()) {
      long failed = 0;
      const int rc = run_study_case(c, out, o.max_memory_gib, failed);
      if (rc == kExitBadInput || rc > kExitBadInput) {
        std::ifstream log(out / (c.name + ".stderr.log"));
        std::string first;
        std::getline(log, first);
        throw std::invalid_argument(fmt::format("{}: case {}: study {} exited with {}: {}", o.bounds, c.name,
                                                c.study, rc, first));
      }
      rows.push_back(study_row(c.name, rc == 0, failed));
      pass = pass && rc == 0;
      case_json.push_back({{"case", c.name}, {"study", c.study}, {"pass", rc == 0}});
      continue;
    }
    VerifyOptions opt;
    opt.scene_text = scene_text_or_default(c.scene.string());
    opt.expected_order = c.expected_order;
    opt.mode = scene_mode(opt.scene_text);  // projection images: the scene's mode
    opt.threshold = c.bounds.threshold;
    opt.allow_nan = c.bounds.limits.count(Bound::max_nan) > 0;
    opt.diagnose = !o.no_diagnosis;
    opt.progress = !o.quiet;
    opt.cache_dir = cache;
    std::vector<std::string> files;
    for (const auto& p : c.images) files.push_back(p.string());
    const std::vector<ImageWithStep> images = c.render ? render_case(c, scenes[i]) : read_images(files, steps[i]);
    if (!c.render)  // an images case's size is known once they are read: before its reference
      check_verification_work(scenes[i], opt, images.front().image.width, images.front().image.height, steps[i], 0,
                              o.max_work,
                              fmt::format("{}: case[{}]", o.bounds, &c - file.cases.data()));
    const nlohmann::json parameters = {{"command", "gate"}, {"bounds", o.bounds}, {"case", c.name}};
    const HtmlReportContext html{"vrv gate: case " + c.name, invoking_commands(), {}};
    const fs::path case_out = writer ? out / c.name : fs::path();  // the other ranks write nothing
    const VerifyRun run = run_verification(scenes[i], images, opt, c.bounds, c.name, case_out, parameters,
                                           o.plots && !o.out.empty(), o.report ? &html : nullptr);
    if (!run.report.pass)
      for (const std::string& f : run.report.failures) {
        BoundRow r = study_row(c.name, false, 1);
        r.bound = "verify";
        r.where = f;
        rows.push_back(r);
      }
    rows.insert(rows.end(), run.rows.begin(), run.rows.end());
    pass = pass && run.pass;
    if (!o.quiet) std::cerr << fmt::format("vrv gate: {}: {}\n", c.name, summary_text(run));
    case_json.push_back({{"case", c.name}, {"verdict", verdict_name(run.report.verdict.verdict)}, {"pass", run.pass}});
  }
  const Table table = bound_table(rows);
  if (writer) write_table_files(out, "bounds", table);
  if (!o.quiet) std::cerr << table.to_markdown();
  nlohmann::ordered_json j;
  j["bounds"] = o.bounds;
  j["out"] = o.out.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(out.string());
  j["pass"] = pass;
  j["worst"] = bound_verdict_name(worst(rows));
  j["cases"] = case_json;
  j["exit"] = pass ? kExitPass : kExitCheckFailed;
  std::cout << j.dump() << '\n';
  return pass ? kExitPass : kExitCheckFailed;
}

}  // namespace

void add_gate_command(CLI::App& app) {
  auto o = std::make_shared<GateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "gate", "Run the verifications and studies a bounds file names and gate each on its bounds");
  cmd->footer("Writes OUT/bounds.{csv,md,tex,json} (one row per bound: measured, limit, margin, verdict) "
              "and OUT/<case>/ (the verification's files). Exit: 0 pass (warnings allowed), 1 a fail or "
              "hard-fail level crossed, 2 bad input. See docs/verify.md.");
  cmd->add_option("--bounds", o->bounds, "Bounds file (TOML)")->required();
  cmd->add_option("--case", o->case_name, "Run only this case");
  add_volume_memory_option(*cmd, o->max_memory_gib);
  cmd->add_option("--out", o->out, "Output directory (default: a temporary directory, removed at the end)");
  cmd->add_option("--cache-dir", o->cache_dir, "Reference cache (default $XDG_CACHE_HOME/vrv or ~/.cache/vrv)");
  cmd->add_flag("--no-cache", o->no_cache, "Do not read or write the reference cache");
  cmd->add_flag("--no-diagnosis", o->no_diagnosis, "Skip casting vrv's own models");
  add_plot_flags(cmd, o->plots, "With --out: draw each case's log-log plot (~1 CPU s a case)");
  cmd->add_flag("--report", o->report, "With --out: write each case's verification as one HTML page, OUT/<case>/report.html")
      ->needs(cmd->get_option("--out"));
  cmd->add_option("--threads", o->threads, "Threads (default: all cores)");
  cmd->add_option("--max-work", o->max_work,
                  "Field evaluations a render case may take (its renders and the reference), estimated "
                  "before any case runs")
      ->capture_default_str();
  cmd->add_flag("--quiet", o->quiet, "No progress or summary on stderr");
  cmd->callback([o] { run_exiting([&] { return run_gate(*o); }); });
}

}  // namespace vrv::cli
