#include "lib/scene_hash.h"

#include <cstddef>
#include <string_view>
#include <type_traits>
#include <vector>

#include <boost/uuid/detail/sha1.hpp>
#include <fmt/format.h>

namespace vrv {
namespace {

class Hasher {
 public:
  void text(std::string_view s) { sha_.process_bytes(s.data(), s.size()); }
  void number(double x) { text(fmt::format("{:a};", x)); }
  void vec(const Vec3& v) {
    for (int a = 0; a < 3; ++a) number(v[a]);
  }
  std::string hex() {
    boost::uuids::detail::sha1::digest_type d;
    sha_.get_digest(d);
    std::string out;
    for (unsigned word : d) out += fmt::format("{:08x}", word);
    return out;
  }

 private:
  boost::uuids::detail::sha1 sha_;
};

void hash_curve(Hasher& h, const PiecewiseLinear& curve) {
  h.text(fmt::format("curve {}:", curve.points().size()));
  for (const auto& p : curve.points()) {
    h.number(p.v);
    h.number(p.y);
  }
}

void hash_scene(Hasher& h, const Scene& s) {
  h.text("vrv scene 1;box:");
  h.vec(s.box.min);
  h.vec(s.box.max);
  h.text(fmt::format("dims:{},{},{};", s.dims[0], s.dims[1], s.dims[2]));
  std::visit(
      [&](const auto& f) {
        using F = std::decay_t<decltype(f)>;
        if constexpr (!std::is_same_v<F, GridField>) {
          static_assert(requires { F::kind; f.parameters(); },
                        "an analytic field declares its kind and parameters() (analytic/marschner_lobb.h)");
          h.text(F::kind);
          h.text(":");
          for (double p : f.parameters()) h.number(p);
        } else {
          const auto n = f.resolution();
          h.text(fmt::format("grid:{},{},{};{};{};", n[0], n[1], n[2], static_cast<int>(f.layout()),
                             static_cast<int>(f.interpolation())));
          h.vec(f.box().min);
          h.vec(f.box().max);
          if (s.field_files.empty()) {
            // Node order (i fastest) is storage order: one kind dispatch for the whole grid.
            const GridNodes& nodes = f.nodes();
            nodes.visit([&](auto node_at) {
              for (std::size_t m = 0; m < nodes.size(); ++m) h.number(node_at(m));
            });
          } else {
            // A volume's nodes as what makes them: the stored samples in grid order and the table
            // or mapping that turns them into values (SHA-1 over the values' doubles took ~2.5 s
            // for a 35 M-sample uint8 scan; its stored bytes are an eighth of that).  Only volume
            // scenes hash this way; every other hash is unchanged.  This machine's byte order.
            const GridNodes& nodes = f.nodes();
            h.text(fmt::format("stored {}:", static_cast<int>(nodes.kind())));
            h.text(nodes.stored_bytes());
            h.text(nodes.table_bytes());
            const SampleMap& m = nodes.map();
            h.text(fmt::format("map {} {} {};", m.rescale, m.window, nodes.table_bytes().empty()));
            for (double x : {m.slope, m.intercept, m.lo, m.hi}) h.number(x);
          }
        }
      },
      s.field);
  h.text(fmt::format("transfer:{};", static_cast<int>(s.transfer.convention())));
  h.number(s.transfer.unit_length());
  hash_curve(h, s.transfer.first());
  hash_curve(h, s.transfer.second());
  h.text("background:");
  h.number(s.background);
  // Only when there are files, so that every other scene's hash is as before.
  if (!s.field_files.empty()) h.text("field files:" + s.field_files);
  // Only for RGB scenes, likewise: each channel's emission (the extinction is every channel's).
  if (s.color)
    for (int c = 0; c < 3; ++c) {
      h.text(fmt::format("channel {}:", c));
      hash_curve(h, s.color->transfer[c].convention() == Convention::emission_extinction ? s.color->transfer[c].first()
                                                                                         : s.color->transfer[c].second());
      h.number(s.color->background[c]);
    }
  // Only for shaded scenes, likewise: every number and choice of the shading factor.
  if (s.shading) {
    const Shading& sh = *s.shading;
    h.text(fmt::format("shading:{} {} {};", shading_model_name(sh.model), normal_sign_name(sh.normal), sh.two_sided));
    for (double x : {sh.ambient, sh.diffuse, sh.specular, sh.shininess}) h.number(x);
    if (sh.light) h.vec(*sh.light);
    else h.text("headlight");
  }
}

}  // namespace

std::string camera_description(const Camera& c) {
  // fmt's "{}" is the shortest text that reads back to the same double: exact and readable.
  return fmt::format("{} eye [{}, {}, {}] target [{}, {}, {}] up [{}, {}, {}] fov {} extent {} angle {} {}x{}",
                     to_string(c.projection), c.eye[0], c.eye[1], c.eye[2], c.target[0], c.target[1],
                     c.target[2], c.up[0], c.up[1], c.up[2], c.fov_degrees, c.extent, c.angle_degrees,
                     c.width, c.height);
}

std::string scene_hash(const Scene& scene) {
  Hasher h;
  hash_scene(h, scene);
  return h.hex();
}

std::string scene_hash(const Scene& scene, const Camera& camera) {
  Hasher h;
  hash_scene(h, scene);
  h.text("camera:");
  h.text(camera_description(camera));
  return h.hex();
}

}  // namespace vrv
