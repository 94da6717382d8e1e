#include "lib/verify/verify_output.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "lib/io/atomic_file.h"
#include "lib/io/image_io.h"
#include "lib/io/image_module.h"
#include "lib/io/numbered_error_map.h"
#include "lib/io/output_paths.h"
#include "lib/io/run_metadata.h"

namespace vrv {
namespace {

namespace fs = std::filesystem;

std::string safe(std::string s) {
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
  return s;
}

// File stem of an image name, prefixed by its rank among the images (names may repeat stems).
std::string image_stem(const VerifyReport& rep, std::size_t channel_index) {
  const std::size_t per_image = [&] {
    std::size_t n = 0;
    while (n < rep.channels.size() && rep.channels[n].image == rep.channels.front().image) ++n;
    return std::max<std::size_t>(n, 1);
  }();
  const ChannelReport& c = rep.channels[channel_index];
  return fmt::format("{}_{}_{}", channel_index / per_image, safe(fs::path(c.image).stem().string()), safe(c.channel));
}

}  // namespace

VerifyTables verify_tables(const VerifyReport& rep) {
  VerifyTables t{Table({"image", "channel", "step", "region", "pixels", "max", "mean", "rms", "p99",
                        "fraction_over", "mean_signed", "nan_count", "quantisation_rms", "at_floor"}),
                 Table({"channel", "kind", "order", "std_error", "points", "verdict", "reason"}),
                 Table({"series", "step", "error"}),
                 Table({"rank", "placement", "rule", "opacity", "color", "table", "rms", "max", "model"}),
                 Table({"fault", "evidence"}), Table({"pattern", "behaves_like", "implied_order", "evidence"})};
  for (const char* c : {"max", "mean", "rms", "p99", "mean_signed", "quantisation_rms"}) t.errors.set_format(c, "{:.3e}");
  t.errors.set_format("fraction_over", "{:.4f}");
  for (const ChannelReport& c : rep.channels)
    for (const RegionStats& r : c.regions)
      t.errors.add_row({c.image, c.channel, c.step, std::string(region_name(r.region)), r.pixels, r.stats.max, r.stats.mean, r.stats.rms,
                        r.stats.p99, r.stats.fraction_over, r.stats.mean_signed, c.nan_count, c.floor_rms,
                        std::string(c.at_floor ? "yes" : "no")});
  t.orders.allow_missing("order");
  t.orders.allow_missing("std_error");
  t.orders.set_format("order", "{:.3f}");
  t.orders.set_format("std_error", "{:.3f}");
  t.points.allow_missing("error");
  for (const OrderReport& o : rep.orders) {
    t.orders.add_row({o.channel, std::string(order_kind_name(o.kind)), o.fit.order, o.fit.standard_error, static_cast<long>(o.fit.points),
                      std::string(verdict_name(o.judgement.verdict)), o.judgement.reason});
    const std::string series = fmt::format("{} {}", o.channel, o.kind == OrderKind::self ? "successive differences" : "against the reference");
    for (std::size_t k = 0; k < o.steps.size(); ++k)
      if (o.errors[k] > 0) t.points.add_row({series, o.steps[k], o.errors[k]});
  }
  // A shaded scene's diagnosis has a gradient column; an unshaded one's table is as before.
  const bool shaded = std::any_of(rep.diagnosis.begin(), rep.diagnosis.end(), [](const Candidate& c) { return !c.gradient.empty(); });
  if (shaded) t.diagnosis = Table({"rank", "placement", "rule", "opacity", "color", "table", "gradient", "rms", "max", "model"});
  t.diagnosis.allow_missing("rms");
  t.diagnosis.set_format("rms", "{:.3e}");
  t.diagnosis.set_format("max", "{:.3e}");
  long rank = 1;
  for (const Candidate& c : rep.diagnosis)
    shaded ? t.diagnosis.add_row({rank++, c.placement, c.rule, c.opacity, c.color, c.table, c.gradient, c.rms, c.max, c.name})
           : t.diagnosis.add_row({rank++, c.placement, c.rule, c.opacity, c.color, c.table, c.rms, c.max, c.name});
  for (const Fault& f : rep.faults) t.faults.add_row({f.name(), f.evidence});
  for (const Fault& f : rep.conventions) t.conventions.add_row({f.name(), f.behaviour, f.implied_order, f.evidence});
  return t;
}

void write_table_files(const fs::path& dir, const std::string& name, const Table& table,
                       std::string_view empty_markdown) {
  write_file_atomically(dir / (name + ".csv"), table.to_csv());
  write_file_atomically(dir / (name + ".md"),
                        table.size() == 0 && !empty_markdown.empty() ? std::string(empty_markdown) : table.to_markdown());
  write_file_atomically(dir / (name + ".tex"), table.to_latex());
  write_file_atomically(dir / (name + ".json"), table.to_json());
}

void check_verify_out(const fs::path& dir, const std::vector<fs::path>& inputs) {
  if (fs::exists(dir) && !fs::is_directory(dir))
    throw std::invalid_argument(fmt::format("--out: {} exists and is not a directory", dir.string()));
  check_inputs_outside(dir, inputs, "--out");
}

void write_verify_outputs(const fs::path& dir, const VerifyReport& rep,
                          const std::vector<std::pair<std::string, Table>>& extra,
                          const nlohmann::json& parameters, double seconds) {
  // The images below need the image module: loaded (or refused) before the first file is
  // written, so a missing module leaves no half-written directory.
  image_module::functions();
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir, ec))
    throw std::runtime_error(fmt::format("{}: cannot create the output directory", dir.string()));
  const VerifyTables t = verify_tables(rep);
  write_table_files(dir, "errors", t.errors);
  write_table_files(dir, "orders", t.orders);
  write_file_atomically(dir / "points.csv", t.points.to_csv());
  write_table_files(dir, "diagnosis", t.diagnosis);
  // No fault named: the Markdown says so rather than showing a header over nothing (the CSV and
  // JSON keep their empty table, which is what a program reading them expects).
  write_table_files(dir, "faults", t.faults, "none: no fault named\n");
  write_table_files(dir, "conventions", t.conventions, "none: no convention named (no expected order, or none matched)\n");
  for (const auto& [name, table] : extra) write_table_files(dir, name, table);

  Image ref(rep.width, rep.height, 0, rep.reference_channels);
  std::copy(rep.reference_image.begin(), rep.reference_image.end(), ref.pixels.begin());
  write_exr(ref, dir / "reference.exr");
  for (std::size_t i = 0; i < rep.channels.size(); ++i) {
    Image err(rep.width, rep.height);
    std::copy(rep.channels[i].error.begin(), rep.channels[i].error.end(), err.pixels.begin());
    const std::string stem = image_stem(rep, i) + "_error";
    write_exr(err, dir / (stem + ".exr"));
    write_numbered_error_map_png(err, dir / (stem + ".png"), rep.channels[i].all().max);
  }
  const nlohmann::json plots = {
      {"plots",
       {{{"name", "error_vs_step"}, {"csv", "points.csv"}, {"style", "lines"}, {"x", "step"}, {"y", "error"},
         {"group", "series"}, {"xscale", "log"}, {"yscale", "log"}, {"fit", true},
         {"xlabel", "sample distance h"}, {"ylabel", fmt::format("error ({} over the image)", metric_name(rep.order_metric))},
         {"title", fmt::format("verify: {}", verdict_name(rep.verdict.verdict))}}}}};
  write_file_atomically(dir / "plots.json", plots.dump(2) + "\n");
  nlohmann::json meta = run_metadata(parameters, seconds);
  meta["pass"] = rep.pass;
  meta["summary"] = nlohmann::json::parse(to_json(rep).dump());
  write_file_atomically(dir / "meta.json", meta.dump(2) + "\n");
}

}  // namespace vrv
