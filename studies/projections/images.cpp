// The projections study's images: per mode, the reference image of the scene's camera; per
// method, its error map at the coarsest step (discrete - reference), with the image's RMS and
// largest error.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>

#include <fmt/format.h>

#include "lib/image_loop.h"
#include "lib/io/table.h"
#include "lib/util/parallel.h"
#include "lib/vrv.h"
#include "lib/work_estimate.h"
#include "studies/engine/study_outputs.h"
#include "studies/projections/projections.h"

namespace vrv {
namespace {

Camera images_camera(const ProjectionsStudy& study, bool quick) {
  Camera c = study.scene.camera ? *study.scene.camera : default_camera(study.scene.box);
  c.width = c.height = quick ? study.quick_image_size : study.image_size;
  return c;
}

std::vector<Ray> pixel_rays(const Camera& camera) {
  std::vector<Ray> rays(static_cast<std::size_t>(camera.width) * camera.height);
  for (std::size_t i = 0; i < rays.size(); ++i) rays[i] = pixel_ray(camera, static_cast<long>(i));
  return rays;
}

// "mip max step (face maxima)" -> "mip_max_step_face_maxima": a file name.
std::string slug(const std::string& label) {
  std::string out;
  for (char c : label) {
    if (std::isalnum(static_cast<unsigned char>(c))) out += c;
    else if (!out.empty() && out.back() != '_') out += '_';
  }
  while (!out.empty() && out.back() == '_') out.pop_back();
  return out;
}

}  // namespace

ProjectionsImages run_projections_images(const ProjectionsStudy& study, bool quick) {
  ProjectionsImages out;
  const Camera camera = images_camera(study, quick);
  out.width = camera.width;
  out.height = camera.height;
  const std::vector<Ray> rays = pixel_rays(camera);
  const double coarsest = *std::max_element(study.steps.begin(), study.steps.end());
  std::map<ProjectionMode, std::vector<ProjectionResult>> refs;
  for (const ProjectionsMethod& m : study.methods) {
    auto [it, added] = refs.try_emplace(m.config.mode);
    if (added) {
      it->second = projection_values(study.scene, rays, m.config.mode, {study.reference_tol});
      for (const ProjectionResult& v : it->second) out.truths.add(v);
      Image image(camera.width, camera.height);
      for (std::size_t i = 0; i < rays.size(); ++i) image.pixels[i] = static_cast<float>(it->second[i].value);
      out.references.push_back({std::string(projection_mode_name(m.config.mode)), std::move(image)});
    }
    // Methods that differ only in the class of maxima their tables keep cast the same image.
    const std::string method = m.label.substr(0, m.label.find(" ("));
    if (std::any_of(out.error_maps.begin(), out.error_maps.end(), [&](const auto& e) { return e.method == method; }))
      continue;
    DiscreteProjectionConfig c = m.config;
    c.sampling.step = coarsest;
    const std::vector<DiscreteProjectionResult> values = discrete_projection_values(study.scene, rays, c);
    ProjectionsErrorMap map{method, slug(method), coarsest, 0, 0, Image(camera.width, camera.height)};
    double sum = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const double e = values[i].value - it->second[i].value;
      map.error.pixels[i] = static_cast<float>(e);
      sum += e * e;
      map.max_error = std::max(map.max_error, std::abs(e));
    }
    map.rms_error = std::sqrt(sum / static_cast<double>(rays.size()));
    out.error_maps.push_back(std::move(map));
  }
  return out;
}

void write_projections_images(const std::filesystem::path& dir, const ProjectionsImages& images) {
  std::filesystem::create_directories(dir / "images");
  for (const auto& [mode, image] : images.references) write_value_image(image, dir / "images" / (mode + "_reference"));
  Table maps({"method", "step", "rms_error", "max_error", "map_range", "file"});
  for (const char* c : {"rms_error", "max_error", "map_range"}) maps.set_format(c, "{:.3e}");
  for (const ProjectionsErrorMap& m : images.error_maps) {
    const std::string file = fmt::format("images/{}_error", m.file_stem);
    // The colours span the 99th percentile of |error|: silhouette rays shorter than half a step
    // have no sample (error = the whole value) and would wash out the rest of the map.
    const double range = abs_pixel_quantile(m.error, 0.99);
    write_error_image(m.error, dir / file, range);
    maps.add_row({m.method, m.step, m.rms_error, m.max_error, range, file + ".png"});
  }
  write_table(dir, "error_maps", maps,
              {fmt::format("Projections: image error at the coarsest step ({}x{} pixels)", images.width, images.height),
               "tab:projections-maps", {}});
}

std::vector<StudyCheck> images_checks(const ProjectionsStudy& study, const ProjectionsImages& images) {
  long bad = 0;
  for (const ProjectionsErrorMap& m : images.error_maps) bad += !(std::isfinite(m.rms_error) && std::isfinite(m.max_error));
  return {{"finite image errors", static_cast<double>(bad), 0, bad == 0,
           "error maps whose RMS or largest error is not finite", CheckKind::finite},
          {"image references within reference_tol", images.truths.largest_estimate, study.reference_tol,
           images.truths.missed == 0,
           fmt::format("largest error estimate of the images' references; {} missed", images.truths.missed),
           CheckKind::derived}};
}

void add_images_work(const ProjectionsStudy& study, bool quick, StudyWork& work) {
  const Camera camera = images_camera(study, quick);
  double per_pixel = 0;
  std::vector<ProjectionMode> modes;
  const double coarsest = *std::max_element(study.steps.begin(), study.steps.end());
  for (const ProjectionsMethod& m : study.methods) {
    if (std::find(modes.begin(), modes.end(), m.config.mode) == modes.end()) {
      modes.push_back(m.config.mode);
      per_pixel += reference_evaluations(study.scene, study.reference_tol);
    }
    DiscreteConfig c;
    c.sampling = m.config.sampling;
    c.sampling.step = coarsest;
    per_pixel += discrete_samples(c, study.scene);
  }
  work.add("images", static_cast<double>(camera.width) * camera.height, per_pixel);
}

}  // namespace vrv
