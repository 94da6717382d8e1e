#include "lib/volume_export.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "lib/scene_file.h"
#include "lib/volume/volume_file.h"

namespace vrv {
namespace {

Scene ml_scene() {
  Scene s = default_scene();
  s.dims = {7, 5, 4};
  s.box.min = Vec3(-1, -0.5, 0);
  s.box.max = Vec3(2, 1, 0.75);
  return s;
}

Scene grid_scene(GridLayout layout) {
  Scene s = ml_scene();
  s.field = make_grid(s.box, MarschnerLobb{}, {6, 5, 3}, layout, Interpolation::trilinear);
  return s;
}

std::map<std::string, std::string> nrrd_fields(const std::string& file, std::size_t& data_at) {
  std::map<std::string, std::string> f;
  std::istringstream in(file);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "NRRD0004");
  while (std::getline(in, line) && !line.empty()) {
    if (line[0] == '#') continue;
    const auto colon = line.find(": ");
    f[line.substr(0, colon)] = line.substr(colon + 2);
  }
  data_at = static_cast<std::size_t>(in.tellg());
  return f;
}

template <class T>
T read_at(const std::string& bytes, std::size_t at) {
  T x;
  std::memcpy(&x, bytes.data() + at, sizeof x);
  return x;
}

TEST(VolumeExport, AnalyticFieldOnDimsNodesOnTheBoxFaces) {
  const Scene s = ml_scene();
  const ExportedNodes v = sample_volume(s, std::nullopt);
  EXPECT_EQ(v.n, (std::array<int, 3>{7, 5, 4}));
  EXPECT_EQ(v.position(0, 0, 0), s.box.min);
  EXPECT_NEAR((v.position(6, 4, 3) - s.box.max).norm(), 0, 1e-15);
  const MarschnerLobb ml;
  for (int k = 0; k < 4; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 7; ++i) EXPECT_EQ(v.at(i, j, k), ml.value(v.position(i, j, k)));
}

TEST(VolumeExport, GridFieldKeepsItsOwnNodesBitForBit) {
  for (GridLayout layout : {GridLayout::node, GridLayout::cell}) {
    const Scene s = grid_scene(layout);
    const auto& g = std::get<GridField>(s.field);
    const ExportedNodes v = sample_volume(s, std::nullopt);
    EXPECT_EQ(v.n, g.resolution());
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 5; ++j)
        for (int i = 0; i < 6; ++i) {
          EXPECT_EQ(v.at(i, j, k), g.node(i, j, k));
          EXPECT_NEAR((v.position(i, j, k) - g.node_position(i, j, k)).norm(), 0, 1e-15);
        }
  }
  // Resampled: the grid's interpolant at new nodes on the box faces.
  const Scene s = grid_scene(GridLayout::node);
  const ExportedNodes r = sample_volume(s, std::array<int, 3>{3, 9, 2});
  EXPECT_EQ(r.at(2, 8, 1), std::get<GridField>(s.field).value(r.position(2, 8, 1)));
  EXPECT_THROW(sample_volume(s, std::array<int, 3>{1, 9, 2}), std::invalid_argument);
}

TEST(VolumeExport, AttachedNrrdHeaderAndValuesReadBack) {
  const ExportedNodes v = sample_volume(ml_scene(), std::nullopt);
  for (SampleType t : {SampleType::float32, SampleType::float64}) {
    const std::string file = nrrd_file(v, t);
    std::size_t at = 0;
    auto f = nrrd_fields(file, at);
    EXPECT_EQ(f["type"], t == SampleType::float32 ? "float" : "double");
    EXPECT_EQ(f["sizes"], "7 5 4");
    EXPECT_EQ(f["encoding"], "raw");
    EXPECT_EQ(f["endian"], "little");
    double ox, oy, oz;
    ASSERT_EQ(std::sscanf(f["space origin"].c_str(), "(%lf,%lf,%lf)", &ox, &oy, &oz), 3);
    EXPECT_EQ(Vec3(ox, oy, oz), v.origin);
    double hx, a, b;
    ASSERT_EQ(std::sscanf(f["space directions"].c_str(), "(%lf,%lf,%lf)", &hx, &a, &b), 3);
    EXPECT_EQ(hx, v.spacing[0]);  // 17 digits: exact
    const std::size_t w = t == SampleType::float32 ? 4 : 8;
    ASSERT_EQ(file.size() - at, v.values.size() * w);
    for (std::size_t m = 0; m < v.values.size(); ++m) {
      if (t == SampleType::float32) EXPECT_EQ(read_at<float>(file, at + 4 * m), static_cast<float>(v.values[m]));
      else EXPECT_EQ(read_at<double>(file, at + 8 * m), v.values[m]);
    }
  }
}

TEST(VolumeExport, DetachedNrrdNamesItsDataFile) {
  const ExportedNodes v = sample_volume(ml_scene(), std::nullopt);
  const std::string h = nrrd_header(v, SampleType::float64, "field_f64.raw");
  std::size_t at = 0;
  EXPECT_EQ(nrrd_fields(h, at)["data file"], "field_f64.raw");
  EXPECT_EQ(at, h.size());
  EXPECT_EQ(raw_bytes(v, SampleType::float64).size(), v.values.size() * 8);
}

std::string attribute(const std::string& xml, const std::string& name) {
  const auto at = xml.find(name + "=\"");
  const auto from = at + name.size() + 2;
  return xml.substr(from, xml.find('"', from) - from);
}

TEST(VolumeExport, VtiAsciiAndRawAppendedReadBack) {
  const ExportedNodes v = sample_volume(ml_scene(), std::nullopt);
  for (SampleType t : {SampleType::float32, SampleType::float64}) {
    const std::string ascii = vti_file(v, t, VtiEncoding::ascii);
    EXPECT_EQ(attribute(ascii, "WholeExtent"), "0 6 0 4 0 3");
    std::istringstream sp(attribute(ascii, "Spacing")), og(attribute(ascii, "Origin"));
    Vec3 spacing, origin;
    sp >> spacing[0] >> spacing[1] >> spacing[2];
    og >> origin[0] >> origin[1] >> origin[2];
    EXPECT_EQ(spacing, v.spacing);
    EXPECT_EQ(origin, v.origin);
    EXPECT_EQ(attribute(ascii.substr(ascii.find("<DataArray")), "type"), t == SampleType::float32 ? "Float32" : "Float64");
    const auto begin = ascii.find('>', ascii.find("<DataArray")) + 1;
    std::istringstream numbers(ascii.substr(begin, ascii.find("</DataArray>") - begin));
    for (std::size_t m = 0; m < v.values.size(); ++m) {
      double x = 0;
      ASSERT_TRUE(numbers >> x);
      if (t == SampleType::float32) EXPECT_EQ(static_cast<float>(x), static_cast<float>(v.values[m]));
      else EXPECT_EQ(x, v.values[m]);
    }
    double extra;
    EXPECT_FALSE(numbers >> extra);

    const std::string raw = vti_file(v, t, VtiEncoding::raw_appended);
    const std::size_t at = raw.find('_', raw.find("<AppendedData")) + 1;
    const std::size_t w = t == SampleType::float32 ? 4 : 8;
    ASSERT_EQ(read_at<std::uint64_t>(raw, at), v.values.size() * w);
    for (std::size_t m = 0; m < v.values.size(); ++m) {
      if (t == SampleType::float32) EXPECT_EQ(read_at<float>(raw, at + 8 + 4 * m), static_cast<float>(v.values[m]));
      else EXPECT_EQ(read_at<double>(raw, at + 8 + 8 * m), v.values[m]);
    }
  }
}

// MetaImage and NIfTI files read back through vrv's own readers (MetaImage by hand, NIfTI through
// niftilib): the same nodes, values and placement (NIfTI-1's float32 spacing and origin rounded).
TEST(VolumeExport, MetaImageAndNiftiReadBack) {
  const ExportedNodes v = sample_volume(ml_scene(), std::nullopt);
  const auto dir = std::filesystem::temp_directory_path() / "vrv_volume_export_formats";
  std::filesystem::create_directories(dir);
  for (SampleType t : {SampleType::float32, SampleType::float64}) {
    for (const auto& [name, bytes] : {std::pair{std::string("field.mha"), metaimage_file(v, t)},
                                      std::pair{std::string("field.nii"), nifti_file(v, t)}}) {
      SCOPED_TRACE(name + (t == SampleType::float32 ? " float32" : " float64"));
      const auto path = dir / name;
      std::ofstream(path, std::ios::binary) << bytes;
      const Volume back = read_volume(path);
      EXPECT_EQ(back.dims, v.n);
      EXPECT_EQ(back.axis, (std::array<int, 3>{0, 1, 2}));
      EXPECT_EQ(back.sign, (std::array<int, 3>{1, 1, 1}));
      const bool nifti = name == "field.nii";
      for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(back.spacing[a], nifti ? double(float(v.spacing[a])) : v.spacing[a]);
        EXPECT_EQ(back.origin[a], nifti ? double(float(v.origin[a])) : v.origin[a]);
      }
      const auto values = std::visit([](const auto& x) { return std::vector<double>(x.begin(), x.end()); }, back.samples);
      ASSERT_EQ(values.size(), v.values.size());
      for (std::size_t m = 0; m < values.size(); ++m)
        EXPECT_EQ(values[m], t == SampleType::float32 ? double(float(v.values[m])) : v.values[m]) << m;
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace vrv
