// vrv export: everything another renderer needs to draw the scene's integral — the field on a
// grid (NRRD, VTK image data; float32 and float64), the transfer function (CSV table and the
// renderers' opacity/colour convention as JSON), the camera (JSON) and every pixel's ray (.npy).
// See docs/export.md.
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "lib/io/atomic_file.h"
#include "lib/camera_export.h"
#include "lib/scene_file.h"
#include "lib/transfer_export.h"
#include "lib/volume_export.h"
#include "lib/scene_hash.h"
#include "lib/shading.h"
#include "lib/vrv.h"
#include "studies/cli/cli_support.h"
#include "studies/cli/commands.h"
#include "studies/cli/memory_limit.h"
#include "studies/cli/published_folder.h"
#include "studies/engine/interrupt.h"

namespace vrv::cli {
namespace {

namespace fs = std::filesystem;

struct ExportOptions {
  std::string scene;
  std::string out;
  std::string resolution;
  // Given only where they act, so that none is accepted and ignored (run_export refuses that).
  std::optional<double> unit_distance;  // emission/extinction scenes: the table's L, by default 1
  int table_points = 64;
  std::optional<std::string> nrrd;  // with nrrd in --formats: attached (the default) or detached
  std::optional<std::string> vti;   // with vti in --formats: raw (the default) or ascii
  std::string formats = "nrrd,vti";  // any of nrrd, vti, metaimage, nifti
  std::optional<double> max_memory_gib;  // not given: default_memory_limit(), as vrv study

  double unit() const { return unit_distance.value_or(1.0); }
  bool ascii_vti() const { return vti == "ascii"; }
  bool detached_nrrd() const { return nrrd == "detached"; }
};

struct OutputFile {
  std::string name;  // relative to the output directory
  std::string contents;
};

std::array<int, 3> parse_resolution(const std::string& text) {
  const Vec3 v = parse_vec3(text, "--resolution");
  std::array<int, 3> n{};
  for (int a = 0; a < 3; ++a) {
    if (v[a] != std::floor(v[a]) || v[a] < 2 || v[a] > 2048)
      throw std::invalid_argument(
          fmt::format("--resolution: expected three whole numbers of nodes in [2, 2048], got '{}'", text));
    n[a] = static_cast<int>(v[a]);
  }
  return n;
}

const std::vector<std::string> kFormats{"nrrd", "vti", "metaimage", "nifti"};

// --formats as a set, in kFormats' order; refused in one line naming the value.
std::vector<std::string> export_formats(const std::string& text) {
  std::vector<std::string> given;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    if (std::find(kFormats.begin(), kFormats.end(), item) == kFormats.end())
      throw std::invalid_argument(
          fmt::format("--formats: unknown value '{}' (a comma-separated list of nrrd, vti, metaimage, nifti)", item));
    given.push_back(item);
  }
  if (given.empty()) throw std::invalid_argument("--formats: empty (give at least one of nrrd, vti, metaimage, nifti)");
  std::vector<std::string> formats;
  for (const auto& f : kFormats)
    if (std::find(given.begin(), given.end(), f) != given.end()) formats.push_back(f);
  return formats;
}

std::vector<OutputFile> field_files(const ExportedNodes& v, const ExportOptions& opt) {
  std::vector<OutputFile> files;
  const VtiEncoding vti = opt.ascii_vti() ? VtiEncoding::ascii : VtiEncoding::raw_appended;
  const auto formats = export_formats(opt.formats);
  const auto wanted = [&](const char* f) { return std::find(formats.begin(), formats.end(), f) != formats.end(); };
  for (const auto& [type, tag] : {std::pair{SampleType::float32, "f32"}, std::pair{SampleType::float64, "f64"}}) {
    const std::string stem = fmt::format("field_{}", tag);
    if (wanted("nrrd") && !opt.detached_nrrd()) {
      files.push_back({stem + ".nrrd", nrrd_file(v, type)});
    } else if (wanted("nrrd")) {
      files.push_back({stem + ".nhdr", nrrd_header(v, type, stem + ".raw")});
      files.push_back({stem + ".raw", raw_bytes(v, type)});
    }
    if (wanted("vti")) files.push_back({stem + ".vti", vti_file(v, type, vti)});
    if (wanted("metaimage")) files.push_back({stem + ".mha", metaimage_file(v, type)});
    if (wanted("nifti")) files.push_back({stem + ".nii", nifti_file(v, type)});
  }
  return files;
}

// What the export wrote, as a scene (scene.toml): a verification against it measures the
// renderer, not the export.  The field: the scene's own grid when it has one (unchanged), else a
// node-layout trilinear grid at the exported nodes sampling the analytic field; the transfer
// function: an opacity/colour scene's own, else the exported table's points with its unit
// distance.  A grid resampled at --resolution is no scene vrv can state (a grid's source is
// analytic): then no scene file, and `why` says so.
struct ExportedScene {
  std::string toml;  // empty: none
  std::string source;  // what the grid's nodes are, for export.json
  std::string why;     // why there is no scene file
};

ExportedScene exported_scene(const Scene& scene, const ExportedNodes& v, const ExportOptions& opt) {
  const std::string name = opt.scene.empty() ? "<default scene>" : opt.scene;
  const std::string text = opt.scene.empty() ? std::string(default_scene_toml()) : read_scene_text(opt.scene);
  const bool grid = std::holds_alternative<GridField>(scene.field);
  const std::string nodes = fmt::format("{} x {} x {}", v.n[0], v.n[1], v.n[2]);
  ExportedScene e;
  if (grid && !opt.resolution.empty()) {
    e.source = fmt::format("the scene's grid resampled through its interpolation at {} nodes on the box "
                           "faces (--resolution)", nodes);
    e.why = "a grid resampled from a grid is not a scene vrv can state (a grid's source is an analytic "
            "field): export without --resolution, or from the analytic scene";
    return e;
  }
  e.source = grid ? fmt::format("the scene's grid: its {} nodes, bit for bit", nodes)
                  : fmt::format("the scene's analytic field sampled at {} nodes on the box faces ({}); "
                                "scene.toml states it as a grid of these nodes",
                                nodes, opt.resolution.empty() ? "volume.dims" : "--resolution");
  std::optional<OpacityColourPoints> transfer;
  if (scene.transfer.convention() != Convention::opacity_color) {
    OpacityColourPoints t;
    t.unit_length = opt.unit();
    if (scene.color) {
      const auto rows = tabulate_color_transfer(*scene.color, opt.unit(), opt.table_points);
      for (std::size_t i = 0; i < rows[0].size(); ++i) {
        t.opacity.push_back({rows[0][i].value, rows[0][i].opacity});
        t.color.push_back({rows[0][i].value, rows[0][i].color, rows[1][i].color, rows[2][i].color});
      }
    } else {
      for (const TransferRow& r : tabulate_transfer(scene.transfer, opt.unit(), opt.table_points)) {
        t.opacity.push_back({r.value, r.opacity});
        t.color.push_back({r.value, r.color});
      }
    }
    transfer = t;
  }
  e.toml = exported_scene_toml(text, name, grid ? std::nullopt : std::optional(v.n), transfer);
  // The claim checked: the scene read back has the exported nodes, bit for bit.
  const Scene back = parse_scene(e.toml, "scene.toml");
  if (sample_volume(back, std::nullopt).values != v.values)
    throw std::logic_error("export: scene.toml's grid does not reproduce the exported nodes");
  return e;
}

// A shaded scene's [shading] for a renderer (docs/shading.md): what multiplies the emission.
nlohmann::ordered_json shading_manifest(const Shading& s) {
  nlohmann::ordered_json j;
  j["model"] = shading_model_name(s.model);
  j["ambient"] = s.ambient;
  j["diffuse"] = s.diffuse;
  j["specular"] = s.specular;
  j["shininess"] = s.shininess;
  if (s.light) {
    const Vec3 l = s.light->normalized();
    j["light"] = {l[0], l[1], l[2]};
  } else {
    j["light"] = "headlight";
  }
  j["normal"] = normal_sign_name(s.normal);
  j["two_sided"] = s.two_sided;
  j["formula"] = s.model == ShadingModel::blinn_phong
                     ? "S = ambient + diffuse max(0, n.l) + specular max(0, n.h)^shininess, h = (l + v) / |l + v|"
                     : "S = ambient + diffuse max(0, n.l) + specular max(0, r.v)^shininess, r = 2 (n.l) n - l";
  j["applies_to"] = "the emission (a renderer's colour) is multiplied by S; extinction (opacity) is not; n = the "
                    "normalised gradient (negative_gradient: its negative), turned toward the eye when two_sided; "
                    "v toward the eye; l toward the light (the eye's direction for the headlight); S = ambient where "
                    "the gradient vanishes";
  return j;
}

nlohmann::ordered_json manifest(const Scene& scene, const Camera& camera, const ExportedNodes& v,
                                const ExportOptions& opt, const std::vector<OutputFile>& files,
                                const ExportedScene& exported) {
  nlohmann::ordered_json j;
  j["scene"] = opt.scene.empty() ? "(embedded default)" : opt.scene;
  j["scene_hash"] = scene_hash(scene);
  j["scene_camera_hash"] = scene_hash(scene, camera);
  j["box"] = {{"min", {scene.box.min[0], scene.box.min[1], scene.box.min[2]}},
              {"max", {scene.box.max[0], scene.box.max[1], scene.box.max[2]}}};
  j["grid"] = {{"nodes", v.n},
               {"origin", {v.origin[0], v.origin[1], v.origin[2]}},
               {"spacing", {v.spacing[0], v.spacing[1], v.spacing[2]}},
               {"order", "x fastest, then y, then z"},
               {"source", exported.source}};
  if (exported.toml.empty()) {
    j["scene_file"] = nullptr;
    j["scene_file_missing"] = exported.why;
  } else {
    j["scene_file"] = "scene.toml";
    j["scene_file_hash"] = scene_hash(parse_scene(exported.toml, "scene.toml"));
  }
  j["background"] = scene.color ? nlohmann::ordered_json(scene.color->background) : nlohmann::ordered_json(scene.background);
  j["integral"] = "I = integral of g(f(s)) exp(-integral_entry^s tau(f(u)) du) ds + background exp(-integral tau), over the ray clipped to the box";
  if (scene.shading) j["shading"] = shading_manifest(*scene.shading);  // shaded scenes only: others as before
  auto names = nlohmann::ordered_json::array();
  for (const auto& f : files) names.push_back(f.name);
  j["files"] = names;
  return j;
}

// The export's peak memory, estimated before anything is sampled: per node, the samples (8 bytes),
// the field files held until written (f32 and f64: 12 bytes per format; ASCII VTI about 32 more)
// and scene.toml's grid read back to check it (16 bytes); per pixel, rays.npy (48 bytes).
// Measured: 128^3 nodes (2.1 M) peak at 121 MB resident, 48 bytes a node with the camera.
struct ExportMemory {
  double nodes = 0, pixels = 0, node_bytes = 0, ray_bytes = 0;
  double total() const { return node_bytes + ray_bytes; }
};

ExportMemory export_memory(const std::array<int, 3>& n, const Camera& camera, bool ascii_vti, std::size_t formats) {
  ExportMemory m;
  m.nodes = double(n[0]) * n[1] * n[2];
  m.pixels = double(camera.width) * camera.height;
  m.node_bytes = m.nodes * (24 + 12 * static_cast<double>(formats) + (ascii_vti ? 32 : 0));
  m.ray_bytes = m.pixels * 48;
  return m;
}

// Refused before anything is allocated, in vrv study's words (--max-memory GIB), naming the input
// responsible for most of it: --resolution (or the scene's grid or volume.dims) or the camera.
void check_export_memory(const ExportOptions& opt, const Scene& scene, const Camera& camera,
                         const std::array<int, 3>& n) {
  const double limit = memory_limit_bytes(opt.max_memory_gib);
  const ExportMemory m = export_memory(n, camera, opt.ascii_vti(), export_formats(opt.formats).size());
  const std::string scene_name = opt.scene.empty() ? "<default scene>" : opt.scene;
  const std::string who = m.ray_bytes > m.node_bytes ? scene_name + ": camera"
                          : !opt.resolution.empty()  ? std::string("--resolution")
                          : std::holds_alternative<GridField>(scene.field) ? scene_name + ": field.resolution"
                                                                           : scene_name + ": volume.dims";
  check_memory(m.total(), limit, who, "export",
               fmt::format("{}x{}x{} nodes: {}; rays.npy for {} x {} pixels: {}", n[0], n[1], n[2],
                           memory_text(m.node_bytes), camera.width, camera.height, memory_text(m.ray_bytes)));
}

// The nodes the export samples (sample_volume's choice), known before sampling.
std::array<int, 3> export_nodes(const Scene& scene, const std::optional<std::array<int, 3>>& resolution) {
  if (resolution) return *resolution;
  if (const auto* g = std::get_if<GridField>(&scene.field)) return g->resolution();
  return scene.dims;
}

// The exported table's opacities per --unit-distance, checked before anything is sampled: one that
// rounds to 1 cannot be stated in a scene (nor drawn: opaque), and one that underflows to 0 where
// the extinction is positive makes the renderer draw nothing there.  Named as the option that
// chose the distance.
void check_unit_distance(const Scene& scene, const ExportOptions& opt) {
  if (scene.transfer.convention() == Convention::opacity_color) return;  // the scene's own unit_length
  const auto check = [&](const TransferRow& r) {
    const auto refuse = [&](std::string_view what, std::string_view remedy) {
      throw std::invalid_argument(fmt::format("--unit-distance: {:g}: at value {:g} (extinction {:g}) the opacity per "
                                              "this distance {}; choose a {} one",
                                              opt.unit(), r.value, r.extinction, what, remedy));
    };
    if (r.opacity >= 1) refuse("rounds to 1, which a scene cannot state", "shorter");
    if (r.opacity == 0 && r.extinction > 0) refuse("underflows to 0 where the extinction is positive", "longer");
  };
  if (scene.color) {
    // Held: a range-for over [0] of the temporary would read the rows after it is destroyed.
    const auto rows = tabulate_color_transfer(*scene.color, opt.unit(), opt.table_points);
    for (const TransferRow& r : rows[0]) check(r);
  } else {
    for (const TransferRow& r : tabulate_transfer(scene.transfer, opt.unit(), opt.table_points)) check(r);
  }
}

// --nrrd and --vti: a known value, and only with their format in --formats.
void check_layout_options(const ExportOptions& opt) {
  const auto formats = export_formats(opt.formats);  // refused before anything is read
  const auto check = [&](const char* flag, const char* format, const std::optional<std::string>& value,
                         const char* values, std::initializer_list<const char*> known) {
    if (!value) return;
    if (std::none_of(known.begin(), known.end(), [&](const char* k) { return *value == k; }))
      throw std::invalid_argument(fmt::format("{}: unknown value '{}' ({})", flag, *value, values));
    if (std::find(formats.begin(), formats.end(), format) == formats.end())
      throw std::invalid_argument(fmt::format("{}: {}: --formats '{}' writes no {} file", flag, *value, opt.formats, format));
  };
  check("--nrrd", "nrrd", opt.nrrd, "attached or detached", {"attached", "detached"});
  check("--vti", "vti", opt.vti, "raw or ascii", {"raw", "ascii"});
}

// The folder is created if its parent exists (a typo in a long path is not a new tree of folders).
void check_parent_exists(const fs::path& dir) {
  std::error_code ec;
  fs::path p = dir.lexically_normal();
  if (!p.has_filename()) p = p.parent_path();  // "o/"
  const fs::path parent = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, ec))
    throw std::invalid_argument(fmt::format("--out: {}: the parent directory {} does not exist", dir.string(), parent.string()));
}

void run_export(const ExportOptions& opt) {
  if (opt.out.empty()) throw std::invalid_argument("--out: an output directory is required");
  check_layout_options(opt);
  if (opt.unit_distance && !(*opt.unit_distance > 0 && std::isfinite(*opt.unit_distance)))
    throw std::invalid_argument(fmt::format("--unit-distance: must be positive and finite, got {}", *opt.unit_distance));
  if (opt.table_points < 1 || opt.table_points > 1 << 20)
    throw std::invalid_argument(fmt::format("--table-points: must be in [1, 1048576], got {}", opt.table_points));
  const InterruptGuard interrupts;  // SIGINT leaves --out as it was (published_folder.h)
  const Scene scene = load_scene_or_default(opt.scene, memory_limit_bytes(opt.max_memory_gib));
  if (opt.unit_distance && scene.transfer.convention() == Convention::opacity_color)
    throw std::invalid_argument(fmt::format("--unit-distance: {} gives its opacity per unit_length = {:g}, which the "
                                            "export keeps (the option is for emission/extinction scenes)",
                                            opt.scene.empty() ? "the default scene" : opt.scene,
                                            scene.transfer.unit_length()));
  check_unit_distance(scene, opt);
  const Camera camera = scene_camera(scene);  // as vrv render has it
  std::optional<std::array<int, 3>> resolution;
  if (!opt.resolution.empty()) resolution = parse_resolution(opt.resolution);
  check_export_memory(opt, scene, camera, export_nodes(scene, resolution));
  // The folder is checked and locked before the work; the files go to its staging folder and
  // appear together: export.json never describes another export's field.
  check_parent_exists(opt.out);
  PublishedFolder out(opt.out, "export.json", "--out");
  const ExportedNodes v = sample_volume(scene, resolution);

  std::vector<OutputFile> files = field_files(v, opt);
  const double unit = scene.transfer.convention() == Convention::opacity_color ? scene.transfer.unit_length()
                                                                              : opt.unit();
  files.push_back({"transfer_function.csv",
                   scene.color ? color_transfer_csv(tabulate_color_transfer(*scene.color, unit, opt.table_points))
                               : transfer_csv(tabulate_transfer(scene.transfer, unit, opt.table_points))});
  files.push_back({"transfer_function.json",
                   (scene.color ? color_transfer_json(*scene.color, opt.unit(), opt.table_points)
                                : transfer_json(scene.transfer, opt.unit(), opt.table_points))
                           .dump(2) + "\n"});
  files.push_back({"camera.json", camera_json(camera).dump(2) + "\n"});
  files.push_back({"rays.npy", rays_npy(camera)});
  const ExportedScene exported = exported_scene(scene, v, opt);
  if (!exported.toml.empty()) files.push_back({"scene.toml", exported.toml});
  files.push_back({"export.json", ""});
  files.back().contents = manifest(scene, camera, v, opt, files, exported).dump(2) + "\n";

  const fs::path dir(opt.out);
  out.write_and_publish([&](const fs::path& staging) {
    for (const auto& f : files) write_file_atomically(staging / f.name, f.contents);
  });
  nlohmann::ordered_json j;
  j["out"] = dir.string();
  j["files"] = files.size();
  j["nodes"] = v.n;
  j["scene_hash"] = scene_hash(scene);
  std::cout << j.dump() << '\n';
}

}  // namespace

void add_export_command(CLI::App& app) {
  auto opt = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export", "Write the scene for another renderer: field (NRRD, VTI), transfer function, camera, rays");
  cmd->footer(
      "Writes into DIR: field_f32/field_f64 as .nrrd (or .nhdr + .raw) and .vti (--formats: also .mha, .nii), "
      "transfer_function.csv and .json (opacity per unit distance and colour), camera.json, "
      "The folder is replaced whole (it must be new, empty or an earlier export). "
      "rays.npy (float64, height x width x 2 x 3: origin, direction), scene.toml (the scene that "
      "describes exactly what was written: verify against it) and export.json (grid, hashes, file list). Loading them into a renderer: docs/export.md.\n"
      "stdout: one JSON line.");
  cmd->add_option("--scene", opt->scene, "Scene file (TOML); the embedded default when omitted");
  cmd->add_option("--out", opt->out, "Output directory (created if its parent exists)")->required();
  cmd->add_option("--resolution", opt->resolution,
                  "nx,ny,nz nodes on the box faces (default: the grid field's own nodes, else volume.dims)");
  cmd->add_option("--unit-distance", opt->unit_distance,
                  "Unit distance L of the exported opacity, default 1 (emission/extinction scenes only: an "
                  "opacity/colour scene keeps its unit_length, and the option is refused there)");
  cmd->add_option("--table-points", opt->table_points,
                  "Rows per transfer-function segment in the table")
      ->capture_default_str();
  cmd->add_option("--nrrd", opt->nrrd, "With nrrd in --formats: attached (.nrrd, the default) | detached (.nhdr + .raw)");
  cmd->add_option("--vti", opt->vti, "With vti in --formats: raw (appended binary, the default) | ascii");
  cmd->add_option("--formats", opt->formats,
                  "Field files to write, comma-separated: nrrd, vti, metaimage (.mha), nifti (.nii, NIfTI-1: "
                  "its spacing and origin are float32)")
      ->capture_default_str();
  cmd->add_option("--max-memory", opt->max_memory_gib,
                  "GiB the export may take, estimated before anything is sampled (default: 3/4 of physical memory)");
  cmd->callback([opt] { run_export(*opt); });
}

}  // namespace vrv::cli
