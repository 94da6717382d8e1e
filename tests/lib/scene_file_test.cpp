#include "lib/scene_file.h"
#include "lib/scene_mode.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace vrv {
namespace {

const std::string kVolume = "[volume]\nmin = [-1.0, -1.0, -1.0]\nmax = [1.0, 1.0, 1.0]\n";
const std::string kField = "[field]\nkind = \"marschner_lobb\"\n";
const std::string kTransfer =
    "[transfer]\nemission = [[0.0, 0.0], [1.0, 1.0]]\nextinction = [[0.0, 0.0], [1.0, 0.5]]\n";

std::string with_field(const std::string& field) { return kVolume + field + kTransfer; }
std::string with_transfer(const std::string& transfer) { return kVolume + kField + transfer; }
std::string with_volume(const std::string& volume) { return volume + kField + kTransfer; }

std::string grid_field(const std::string& extra) {
  return "[field]\nkind = \"grid\"\n" + extra +
         "[field.source]\nkind = \"linear_ramp\"\ngradient = [1.0, 2.0, 3.0]\noffset = 0.5\n";
}

TEST(SceneFile, DefaultSceneHasExpectedValues) {
  const Scene s = default_scene();
  EXPECT_EQ(s.box.min, Vec3(-1, -1, -1));
  EXPECT_EQ(s.box.max, Vec3(1, 1, 1));
  EXPECT_EQ(s.dims, (std::array<int, 3>{64, 64, 64}));
  const auto* ml = std::get_if<MarschnerLobb>(&s.field);
  ASSERT_NE(ml, nullptr);
  EXPECT_EQ(ml->fM, 6);
  EXPECT_EQ(ml->alpha, 0.25);
  EXPECT_EQ(s.transfer.convention(), Convention::emission_extinction);
  ASSERT_EQ(s.transfer.first().points().size(), 2u);
  EXPECT_EQ(s.transfer.first().points()[1].y, 1.0);
  EXPECT_EQ(s.transfer.second().points()[1].y, 0.5);
  EXPECT_DOUBLE_EQ(s.transfer.extinction(0.5), 0.25);
  EXPECT_EQ(s.background, 0);
  EXPECT_NE(default_scene_toml().find("fM = 6"), std::string_view::npos);
  EXPECT_NE(default_scene_toml().find("alpha = 0.25"), std::string_view::npos);
}

TEST(SceneFile, LinearRamp) {
  const Scene s = parse_scene(
      with_field("[field]\nkind = \"linear_ramp\"\ngradient = [1.0, -2.0, 0.5]\noffset = 0.25\n"),
      "ramp.toml");
  const auto* f = std::get_if<LinearRamp>(&s.field);
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(f->gradient, Vec3(1, -2, 0.5));
  EXPECT_EQ(f->offset, 0.25);
  EXPECT_EQ(s.dims, (std::array<int, 3>{64, 64, 64}));
}

TEST(SceneFile, GridNodeTakesResolutionAsDims) {
  const Scene s = parse_scene(with_field(grid_field("resolution = [5, 6, 7]\n")), "grid.toml");
  const auto* g = std::get_if<GridField>(&s.field);
  ASSERT_NE(g, nullptr);
  EXPECT_EQ(g->resolution(), (GridField::Index3{5, 6, 7}));
  EXPECT_EQ(g->layout(), GridLayout::node);
  EXPECT_EQ(g->interpolation(), Interpolation::trilinear);
  EXPECT_EQ(s.dims, (std::array<int, 3>{5, 6, 7}));
  // The corner node samples the source at the box corner: 0.5 + 1*-1 + 2*-1 + 3*-1.
  EXPECT_DOUBLE_EQ(g->node(0, 0, 0), -5.5);
}

TEST(SceneFile, GridCellNearestKeepsExplicitDims) {
  const std::string text =
      "[volume]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\ndims = [32, 16, 8]\n" +
      grid_field("resolution = [1, 4, 4]\nlayout = \"cell\"\ninterpolation = \"nearest\"\n") +
      kTransfer;
  const Scene s = parse_scene(text, "cell.toml");
  const auto* g = std::get_if<GridField>(&s.field);
  ASSERT_NE(g, nullptr);
  EXPECT_EQ(g->layout(), GridLayout::cell);
  EXPECT_EQ(g->interpolation(), Interpolation::nearest);
  EXPECT_EQ(g->resolution(), (GridField::Index3{1, 4, 4}));
  EXPECT_EQ(s.dims, (std::array<int, 3>{32, 16, 8}));
}

TEST(SceneFile, GridOfMarschnerLobb) {
  const Scene s = parse_scene(
      with_field("[field]\nkind = \"grid\"\nresolution = [3, 3, 3]\n"
                 "[field.source]\nkind = \"marschner_lobb\"\nfM = 3\nalpha = 0.5\n"),
      "g.toml");
  const auto* g = std::get_if<GridField>(&s.field);
  ASSERT_NE(g, nullptr);
  const MarschnerLobb ml{3, 0.5};
  EXPECT_DOUBLE_EQ(g->node(1, 2, 0), ml.value(g->node_position(1, 2, 0)));
}

TEST(SceneFile, OpacityColorConvention) {
  const Scene s = parse_scene(
      with_transfer("[transfer]\nopacity = [[0.0, 0.0], [1.0, 0.5]]\ncolor = [[0.0, 1.0]]\n"
                    "unit_length = 0.5\n"),
      "oc.toml");
  EXPECT_EQ(s.transfer.convention(), Convention::opacity_color);
  EXPECT_EQ(s.transfer.unit_length(), 0.5);
  EXPECT_NEAR(s.transfer.extinction(1.0), -std::log(0.5) / 0.5, 1e-15);
}

TEST(SceneFile, OpacityColorDefaultUnitLength) {
  const Scene s = parse_scene(
      with_transfer("[transfer]\nopacity = [[0, 0.25]]\ncolor = [[0, 1]]\n"), "oc.toml");
  EXPECT_EQ(s.transfer.unit_length(), 1.0);
}

TEST(SceneFile, JumpInEmission) {
  const Scene s = parse_scene(
      with_transfer("[transfer]\nemission = [[0, 0], [0.5, 0], [0.5, 1], [1, 1]]\n"
                    "extinction = [[0, 1]]\n"),
      "jump.toml");
  EXPECT_EQ(s.transfer.emission(0.25), 0);
  EXPECT_EQ(s.transfer.emission(0.5), 1);  // right-continuous
  EXPECT_EQ(s.transfer.emission(0.75), 1);
}

TEST(SceneFile, IntegersAcceptedAsFloats) {
  const Scene s = parse_scene(
      "[volume]\nmin = [-2, -1, 0]\nmax = [2, 1, 3]\n"
      "[field]\nkind = \"marschner_lobb\"\nfM = 4\nalpha = 1\n"
      "[transfer]\nemission = [[0, 0], [1, 2]]\nextinction = [[0, 1]]\n"
      "[background]\nintensity = 1\n",
      "ints.toml");
  EXPECT_EQ(s.box.min, Vec3(-2, -1, 0));
  EXPECT_EQ(s.box.max, Vec3(2, 1, 3));
  EXPECT_EQ(std::get<MarschnerLobb>(s.field).fM, 4);
  EXPECT_EQ(std::get<MarschnerLobb>(s.field).alpha, 1);
  EXPECT_EQ(s.transfer.first().points()[1].y, 2);
  EXPECT_EQ(s.background, 1);
}

std::string with_camera(const std::string& camera) { return kVolume + kField + kTransfer + camera; }

TEST(SceneFile, NoCameraByDefault) {
  EXPECT_FALSE(default_scene().camera.has_value());
  EXPECT_FALSE(parse_scene(kVolume + kField + kTransfer, "s.toml").camera.has_value());
}

TEST(SceneFile, PerspectiveCamera) {
  const Scene s = parse_scene(with_camera("[camera]\nprojection = \"perspective\"\n"
                                          "eye = [1, 2, -6]\ntarget = [0, 0.5, 0]\nup = [0, 0, 1]\n"
                                          "fov = 25.5\nwidth = 320\nheight = 200\n"),
                              "cam.toml");
  ASSERT_TRUE(s.camera.has_value());
  const Camera& c = *s.camera;
  EXPECT_EQ(c.projection, Projection::perspective);
  EXPECT_EQ(c.eye, Vec3(1, 2, -6));
  EXPECT_EQ(c.target, Vec3(0, 0.5, 0));
  EXPECT_EQ(c.up, Vec3(0, 0, 1));
  EXPECT_EQ(c.fov_degrees, 25.5);
  EXPECT_EQ(c.width, 320);
  EXPECT_EQ(c.height, 200);
}

TEST(SceneFile, CameraDefaultsToPerspective) {
  const Scene s = parse_scene(with_camera("[camera]\n"), "cam.toml");
  ASSERT_TRUE(s.camera.has_value());
  EXPECT_EQ(s.camera->projection, Projection::perspective);
  EXPECT_EQ(s.camera->eye, Camera{}.eye);
  EXPECT_EQ(s.camera->width, 256);
}

TEST(SceneFile, OrthographicCamera) {
  const Scene s = parse_scene(
      with_camera("[camera]\nprojection = \"orthographic\"\neye = [0, -5, 0]\nup = [0, 0, 1]\n"
                  "extent = 3\nwidth = 8\nheight = 4\n"),
      "cam.toml");
  ASSERT_TRUE(s.camera.has_value());
  EXPECT_EQ(s.camera->projection, Projection::orthographic);
  EXPECT_EQ(s.camera->extent, 3);
  EXPECT_EQ(s.camera->height, 4);
}

TEST(SceneFile, FanCameraOfTheSamplingPaper) {
  const Scene s = parse_scene(with_camera("[camera]\nprojection = \"fan\"\neye = [-9, 0, 0]\n"
                                          "angle = 0\nfov = 30\nrays = 120\n"),
                              "fan.toml");
  ASSERT_TRUE(s.camera.has_value());
  const Camera& c = *s.camera;
  EXPECT_EQ(c.projection, Projection::fan);
  EXPECT_EQ(c.eye, Vec3(-9, 0, 0));
  EXPECT_EQ(c.fov_degrees, 30);
  EXPECT_EQ(c.angle_degrees, 0);
  EXPECT_EQ(c.width, 120);
  EXPECT_EQ(c.height, 1);  // a fan is one row
  // width is the same as rays; height = 1 may be spelled out.
  const Scene w = parse_scene(
      with_camera("[camera]\nprojection = \"fan\"\nwidth = 7\nheight = 1\nangle = -45.5\n"), "fan.toml");
  EXPECT_EQ(w.camera->width, 7);
  EXPECT_EQ(w.camera->angle_degrees, -45.5);
}

struct BadCase {
  std::string text;
  std::string key;     // dotted path expected in the message
  std::string reason;  // a word of the reason
};

std::vector<BadCase> bad_cases() {
  const std::string vol_tail = "max = [1.0, 1.0, 1.0]\n";
  return {
      {"[volume\nmin = 1", "(syntax)", "line"},
      {kVolume + "[volume]\n" + kField + kTransfer, "(syntax)", "line"},
      {kField + kTransfer, "volume", "missing"},
      {"", "volume", "missing"},
      {with_volume("[volume]\n" + vol_tail), "volume.min", "missing"},
      {with_volume("[volume]\nmin = \"low\"\n" + vol_tail), "volume.min", "array"},
      {with_volume("[volume]\nmin = [1.0, 2.0]\n" + vol_tail), "volume.min", "3 elements"},
      {with_volume("[volume]\nmin = [-1, \"x\", -1]\n" + vol_tail), "volume.min[1]", "number"},
      {with_volume("[volume]\nmin = [nan, -1, -1]\n" + vol_tail), "volume.min[0]", "finite"},
      {with_volume("[volume]\nmin = [-1, -1, -1]\nmax = [1, 1, inf]\n"), "volume.max[2]", "finite"},
      {with_volume("[volume]\nmin = [-1, 1, -1]\n" + vol_tail), "volume.max[1]", "exceed"},
      {with_volume(kVolume + "dims = [64, 64.0, 64]\n"), "volume.dims[1]", "integer"},
      {with_volume(kVolume + "dims = [64, 64, 0]\n"), "volume.dims[2]", "positive"},
      {with_volume(kVolume + "dims = [64, 64, 9999999999]\n"), "volume.dims[2]", "large"},
      {with_volume(kVolume + "dimz = [64, 64, 64]\n"), "volume.dimz", "unknown"},
      {"[volum]\nmin = [-1, -1, -1]\n" + kVolume + kField + kTransfer, "volum", "unknown"},
      {"volume = 3\n" + kField + kTransfer, "volume", "table"},
      {kVolume + kTransfer, "field", "missing"},
      {kVolume + kField + kTransfer + "[a" + std::string(40, '.') + "]\n", "(syntax)", "deeply"},
      {kVolume + "[[field]]\nkind = \"linear_ramp\"\n" + kTransfer, "field", "table"},
      {with_field("[field]\nfM = 6\n"), "field.kind", "missing"},
      {with_field("[field]\nkind = 3\n"), "field.kind", "string"},
      {with_field("[field]\nkind = \"sphere\"\n"), "field.kind",
       "unknown field kind \"sphere\" (expected marschner_lobb, linear_ramp, grid or volume)"},
      {with_field("[field]\nkind = \"linear_ramp\"\n"), "field.gradient", "missing"},
      {with_field("[field]\nkind = \"linear_ramp\"\ngradient = [1, 0, 0]\noffset = true\n"),
       "field.offset", "number"},
      {with_field("[field]\nkind = \"marschner_lobb\"\ngradient = [1, 0, 0]\n"), "field.gradient",
       "unknown"},
      {with_field("[field]\nkind = \"marschner_lobb\"\nalpha = -0.5\n"), "field.alpha", "negative"},
      {with_field("[field]\nkind = \"grid\"\nresolution = [4, 4, 4]\n"), "field.source", "missing"},
      {with_field(grid_field("")), "field.resolution", "missing"},
      {with_field(grid_field("resolution = [1, 4, 4]\n")), "field.resolution[0]", "at least 2"},
      {with_field(grid_field("resolution = [4, 4.5, 4]\n")), "field.resolution[1]", "integer"},
      {with_field(grid_field("resolution = [4, 4, -3]\nlayout = \"cell\"\n")),
       "field.resolution[2]", "positive"},
      {with_field(grid_field("resolution = [4096, 4096, 4096]\n")), "field.resolution", "too many"},
      {with_field(grid_field("resolution = [4, 4, 4]\nlayout = \"corner\"\n")), "field.layout",
       "unknown"},
      {with_field(grid_field("resolution = [4, 4, 4]\ninterpolation = \"cubic\"\n")),
       "field.interpolation", "unknown"},
      {with_field("[field]\nkind = \"grid\"\nresolution = [4, 4, 4]\n"
                  "[field.source]\nkind = \"grid\"\n"),
       "field.source.kind", "nested"},
      {with_field("[field]\nkind = \"grid\"\nresolution = [4, 4, 4]\n"
                  "[field.source]\nkind = \"marschner_lobb\"\nfm = 6\n"),
       "field.source.fm", "unknown"},
      {kVolume + kField, "transfer", "missing"},
      {with_transfer("[transfer]\n"), "transfer", "needs"},
      {with_transfer("[transfer]\nemision = [[0, 1]]\nextinction = [[0, 1]]\n"), "transfer.emision",
       "unknown"},
      {with_transfer("[transfer]\nemission = [[0, 1]]\n"), "transfer.extinction", "missing"},
      {with_transfer("[transfer]\nopacity = [[0, 0.5]]\n"), "transfer.color", "missing"},
      {with_transfer("[transfer]\nemission = [[0, 1]]\nextinction = [[0, 1]]\nopacity = [[0, 0.5]]\n"),
       "transfer.opacity", "mixed"},
      {with_transfer("[transfer]\nemission = [[0, 1]]\nextinction = [[0, 1]]\nunit_length = 2\n"),
       "transfer.unit_length", "mixed"},
      {with_transfer("[transfer]\nemission = []\nextinction = [[0, 1]]\n"), "transfer.emission",
       "empty"},
      {with_transfer("[transfer]\nemission = [[0, 1, 2]]\nextinction = [[0, 1]]\n"),
       "transfer.emission[0]", "pair"},
      {with_transfer("[transfer]\nemission = [0, 1]\nextinction = [[0, 1]]\n"),
       "transfer.emission[0]", "pair"},
      {with_transfer("[transfer]\nemission = [[0, 1], [\"a\", 1]]\nextinction = [[0, 1]]\n"),
       "transfer.emission[1][0]", "number"},
      {with_transfer("[transfer]\nemission = [[1, 1], [0, 1]]\nextinction = [[0, 1]]\n"),
       "transfer.emission[1]", "order"},
      {with_transfer("[transfer]\nemission = [[0, 1], [0, 2], [0, 3]]\nextinction = [[0, 1]]\n"),
       "transfer.emission[2]", "twice"},
      {with_transfer("[transfer]\nemission = [[0, 1]]\nextinction = [[0, 0], [0.5, 1], [1, -0.5]]\n"),
       "transfer.extinction[2]", "negative"},
      {with_transfer("[transfer]\nemission = [[0, -1]]\nextinction = [[0, 1]]\n"),
       "transfer.emission[0]", "negative"},
      {with_transfer("[transfer]\nemission = [[0, 1]]\nextinction = [[-inf, 1]]\n"),
       "transfer.extinction[0][0]", "finite"},
      {with_transfer("[transfer]\nopacity = [[0, 0], [1, 1.0]]\ncolor = [[0, 1]]\n"),
       "transfer.opacity[1]", "below 1"},
      {with_transfer("[transfer]\nopacity = [[0, -0.1]]\ncolor = [[0, 1]]\n"),
       "transfer.opacity[0]", "negative"},
      {with_transfer("[transfer]\nopacity = [[0, 0.5]]\ncolor = [[0, -2]]\n"), "transfer.color[0]",
       "negative"},
      {with_transfer("[transfer]\nopacity = [[0, 0.5]]\ncolor = [[0, 1]]\nunit_length = 0\n"),
       "transfer.unit_length", "positive"},
      {with_transfer("[transfer]\nopacity = [[0, 0.5]]\ncolor = [[0, 1]]\nunit_length = -2\n"),
       "transfer.unit_length", "positive"},
      {kVolume + kField + kTransfer + "[background]\nintensity = -1\n", "background.intensity",
       "negative"},
      {kVolume + kField + kTransfer + "[background]\nintensity = nan\n", "background.intensity",
       "finite"},
      {kVolume + kField + kTransfer + "[background]\nintensty = 1\n", "background.intensty",
       "unknown"},
      {"background = 0.5\n" + kVolume + kField + kTransfer, "background", "table"},
      {"camera = 3\n" + kVolume + kField + kTransfer, "camera", "table"},
      {with_camera("[camera]\nprojection = \"pinhole\"\n"), "camera.projection", "unknown"},
      {with_camera("[camera]\nprojection = 1\n"), "camera.projection", "string"},
      {with_camera("[camera]\nfoo = 1\n"), "camera.foo", "unknown"},
      {with_camera("[camera]\nextent = 2\n"), "camera.extent", "does not apply"},
      {with_camera("[camera]\nrays = 12\n"), "camera.rays", "does not apply"},
      {with_camera("[camera]\nangle = 12\n"), "camera.angle", "does not apply"},
      {with_camera("[camera]\nprojection = \"orthographic\"\nfov = 30\n"), "camera.fov",
       "does not apply"},
      {with_camera("[camera]\nprojection = \"fan\"\nup = [0, 1, 0]\n"), "camera.up",
       "does not apply"},
      {with_camera("[camera]\nprojection = \"fan\"\ntarget = [0, 1, 0]\n"), "camera.target",
       "does not apply"},
      {with_camera("[camera]\neye = [0, 0]\n"), "camera.eye", "3 elements"},
      {with_camera("[camera]\neye = [0, nan, 0]\n"), "camera.eye[1]", "finite"},
      {with_camera("[camera]\neye = [0, 0, 0]\ntarget = [0, 0, 0]\n"), "camera.target", "equals"},
      {with_camera("[camera]\nup = [0, 0, 1]\n"), "camera.up", "parallel"},
      {with_camera("[camera]\nup = [0, 0, 0]\n"), "camera.up", "zero"},
      {with_camera("[camera]\nfov = 180\n"), "camera.fov", "(0, 180)"},
      {with_camera("[camera]\nfov = -5\n"), "camera.fov", "(0, 180)"},
      {with_camera("[camera]\nfov = \"wide\"\n"), "camera.fov", "number"},
      {with_camera("[camera]\nwidth = 0\n"), "camera.width", "positive"},
      {with_camera("[camera]\nheight = 20000\n"), "camera.height", "too large"},
      {with_camera("[camera]\nwidth = 2.5\n"), "camera.width", "integer"},
      {with_camera("[camera]\nprojection = \"orthographic\"\nextent = 0\n"), "camera.extent",
       "positive"},
      {with_camera("[camera]\nprojection = \"fan\"\nrays = 10\nwidth = 10\n"), "camera.rays",
       "not both"},
      {with_camera("[camera]\nprojection = \"fan\"\nrays = 0\n"), "camera.rays", "positive"},
      {with_camera("[camera]\nprojection = \"fan\"\nheight = 2\n"), "camera.height", "must be 1"},
      {with_camera("[camera]\nprojection = \"fan\"\nfov = 400\n"), "camera.fov", "360"},
      {with_camera("[camera]\nprojection = \"fan\"\nangle = inf\n"), "camera.angle", "finite"},
      // RGB points: all alike, three values, not for the shared curve, backgrounds to match.
      {with_transfer("[transfer]\nemission = [[0, 1, 2, 3], [1, 1]]\nextinction = [[0, 1]]\n"),
       "transfer.emission[1]", "[value, r, g, b] as the first point, got 2"},
      {with_transfer("[transfer]\nemission = [[0, 1, 2]]\nextinction = [[0, 1]]\n"), "transfer.emission[0]",
       "[value, y] or [value, r, g, b], got 3 numbers"},
      {with_transfer("[transfer]\nemission = [[0, 1]]\nextinction = [[0, 1, 2, 3]]\n"),
       "transfer.extinction[0]", "a pair [value, y], got 4 numbers"},
      {with_transfer("[transfer]\nopacity = [[0, 0.1, 0.2, 0.3]]\ncolor = [[0, 1]]\n"), "transfer.opacity[0]",
       "a pair [value, y], got 4 numbers"},
      {with_transfer("[transfer]\nemission = [[0, 1, -2, 3]]\nextinction = [[0, 1]]\n"),
       "transfer.emission[0][2]", "negative emission -2"},
      {with_transfer("[transfer]\nemission = [[0, 1]]\nextinction = [[0, 1]]\n[background]\ncolor = [1, 2, 3]\n"),
       "background.color", "needs an RGB transfer function"},
      {with_transfer("[transfer]\nemission = [[0, 1, 2, 3]]\nextinction = [[0, 1]]\n[background]\n"
                     "color = [1, 2, 3]\nintensity = 1\n"),
       "background.color", "not both"},
      {with_transfer("[transfer]\nemission = [[0, 1, 2, 3]]\nextinction = [[0, 1]]\n[background]\n"
                     "color = [1, -2, 3]\n"),
       "background.color[1]", "negative intensity"},
  };
}

// RGB: three-valued emission (or colour) points, one extinction (or opacity) for every channel.
TEST(SceneFile, RgbEmissionMakesThreeChannelsSharingTheExtinction) {
  const Scene s = parse_scene(with_transfer("[transfer]\nemission = [[0, 0.1, 0.2, 0.3], [1, 1, 2, 3]]\n"
                                            "extinction = [[0, 0], [1, 0.5]]\n[background]\ncolor = [0.5, 0, 1]\n"),
                              "rgb.toml");
  ASSERT_TRUE(s.color);
  EXPECT_EQ(s.channel_count(), 3);
  for (int c = 0; c < 3; ++c) {
    const Scene one = channel_scene(s, c);
    EXPECT_FALSE(one.color);
    EXPECT_DOUBLE_EQ(one.transfer.emission(1), c + 1.0);
    EXPECT_DOUBLE_EQ(one.transfer.emission(0), 0.1 * (c + 1));
    EXPECT_DOUBLE_EQ(one.transfer.extinction(1), 0.5);
    EXPECT_EQ(one.background, (std::array<double, 3>{0.5, 0, 1})[c]);
  }
  EXPECT_DOUBLE_EQ(s.transfer.emission(1), 1.0);  // `transfer` is the red channel
  EXPECT_THROW(channel_scene(s, 3), std::out_of_range);
  // One intensity is every channel's.
  const Scene grey_bg = parse_scene(with_transfer("[transfer]\nopacity = [[0, 0.5]]\ncolor = [[0, 1, 0, 0.5]]\n"
                                                  "[background]\nintensity = 0.25\n"),
                                    "rgb.toml");
  ASSERT_TRUE(grey_bg.color);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(grey_bg.color->background[c], 0.25);
  EXPECT_EQ(grey_bg.color->transfer[2].convention(), Convention::opacity_color);
  EXPECT_FALSE(parse_scene(with_transfer(kTransfer), "grey.toml").color);
}

TEST(SceneFile, GreyOnlyCallersRefuseAnRgbSceneNamingIt) {
  const Scene s = parse_scene(with_transfer("[transfer]\nemission = [[0, 1, 2, 3]]\nextinction = [[0, 1]]\n"),
                              "rgb.toml");
  try {
    require_grey(s, "rgb.toml", "vrv verify");
    ADD_FAILURE() << "an RGB scene was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("rgb.toml: transfer: the scene is RGB", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("vrv verify"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(require_grey(default_scene(), "default", "vrv verify"));
}

TEST(SceneFile, BadInputsGiveOneLineErrorsNamingKeyAndReason) {
  const auto cases = bad_cases();
  ASSERT_GE(cases.size(), 20u);
  for (const auto& c : cases) {
    SCOPED_TRACE(c.text);
    try {
      parse_scene(c.text, "bad.toml");
      ADD_FAILURE() << "no error for key " << c.key;
    } catch (const SceneFileError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind("bad.toml: " + c.key + ": ", 0), 0u) << msg;
      EXPECT_NE(msg.find(c.reason), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
  }
}

TEST(SceneFile, ManyDotsInCommentsAndStringsAreFine) {
  const std::string dots(200, '.');
  const std::string text = "# " + dots + "\n" + kVolume + "[field]\nkind = \"marschner_lobb\" # " +
                           dots + "\n" + kTransfer + "'" + dots + "'.x = 1\n";
  try {
    parse_scene(text, "dots.toml");
    FAIL();
  } catch (const SceneFileError& e) {
    // Only the unknown quoted key is wrong, not the nesting.
    EXPECT_NE(std::string(e.what()).find("unknown"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(parse_scene("# " + dots + "\n" + kVolume + kField + kTransfer, "dots.toml"));
}

TEST(SceneFile, KeyWithLineBreakStillGivesOneLine) {
  try {
    parse_scene(kVolume + kField + kTransfer + "\"bad\\nkey\" = 1\n", "a\nb.toml");
    FAIL();
  } catch (const SceneFileError& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("unknown"), std::string::npos);
  }
}

// Truncations and byte mutations of a valid file either parse or give SceneFileError.
TEST(SceneFile, MangledInputNeverEscapesAsOtherErrors) {
  const std::string base(default_scene_toml());
  std::mt19937 rng(42);
  std::vector<std::string> inputs;
  for (std::size_t n = 0; n <= base.size(); ++n) inputs.push_back(base.substr(0, n));
  const std::string alphabet = "[]{}=,.\"'#\n -+0123456789eEnaif_xyz\x80\xff";
  for (int k = 0; k < 2000; ++k) {
    std::string s = base;
    for (int m = 0; m < 3; ++m) s[rng() % s.size()] = alphabet[rng() % alphabet.size()];
    inputs.push_back(s);
  }
  inputs.push_back("a = " + std::string(100000, '['));
  inputs.push_back("a = " + std::string(100000, '{'));
  inputs.push_back(std::string("\0\0\0", 3));
  // toml++ recurses per key level; these would overflow the stack if they reached it.
  std::string deep = "a";
  for (int i = 0; i < 200000; ++i) deep += ".a";
  inputs.push_back(deep + " = 1\n");
  inputs.push_back("[" + deep + "]\n");
  inputs.push_back("\"x\" = \"\"\"\"\"\"\"\"\"\"\n" + deep + " = 1\n");
  for (const auto& s : inputs) {
    try {
      parse_scene(s, "m.toml");
    } catch (const SceneFileError& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
    }
  }
}

TEST(SceneFile, LoadSceneReadsFile) {
  const auto path = std::filesystem::temp_directory_path() / "vrv_test_scene_file.toml";
  {
    std::ofstream out(path);
    out << default_scene_toml();
  }
  const Scene s = load_scene(path);
  EXPECT_TRUE(std::holds_alternative<MarschnerLobb>(s.field));
  std::filesystem::remove(path);
}

TEST(SceneFile, LoadSceneErrorsNameTheFile) {
  const auto path = std::filesystem::temp_directory_path() / "vrv_no_such_dir" / "missing.toml";
  try {
    load_scene(path);
    FAIL();
  } catch (const SceneFileError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path.string() + ": ", 0), 0u) << e.what();
  }
  EXPECT_THROW(load_scene(std::filesystem::temp_directory_path()), SceneFileError);
}

TEST(SceneFile, LoadSceneReportsErrorsWithThePath) {
  const auto path = std::filesystem::temp_directory_path() / "vrv_test_scene_bad.toml";
  {
    std::ofstream out(path);
    out << kVolume << kField << "[transfer]\nemission = [[0, 1]]\n";
  }
  try {
    load_scene(path);
    FAIL();
  } catch (const SceneFileError& e) {
    EXPECT_EQ(std::string(e.what()), path.string() +
                                         ": transfer.extinction: missing (emission needs extinction)");
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace vrv

namespace vrv {
namespace {

// mode = "...": a projection's name, checked here; anything else is one line naming file and key.
TEST(SceneFile, ModeKeyTakesAProjectionNameAndRefusesAnyOther) {
  for (const char* m : {"xray", "xray_classified", "mip", "mip_classified"})
    EXPECT_NO_THROW(parse_scene(std::string("mode = \"") + m + "\"\n" + kVolume + kField + kTransfer, "m.toml")) << m;
  for (const char* bad : {"mode = \"MIP\"\n", "mode = \"\"\n", "mode = 3\n"}) {
    try {
      parse_scene(bad + kVolume + kField + kTransfer, "m.toml");
      FAIL() << bad;
    } catch (const SceneFileError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("m.toml: mode: ", 0), 0u) << what;
      EXPECT_EQ(what.find('\n'), std::string::npos);
    }
  }
}

TEST(SceneFile, ExportKeepsTheMode) {
  const std::string text = "mode = \"mip\"\n" + kVolume + kField + kTransfer;
  const std::string exported = exported_scene_toml(text, "m.toml", std::array<int, 3>{4, 4, 4}, std::nullopt);
  EXPECT_EQ(scene_mode(exported), ProjectionMode::mip) << exported;
  EXPECT_NO_THROW(parse_scene(exported, "exported.toml"));
}

}  // namespace
}  // namespace vrv
