#include "lib/volume_export.h"

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <type_traits>

#include <fmt/format.h>
#include <nifti1.h>

#include "lib/option_error.h"

namespace vrv {
namespace {

constexpr int kMaxResolution = 2048;

ExportedNodes on_box_nodes(const Scene& scene, std::array<int, 3> n) {
  ExportedNodes v;
  v.n = n;
  v.origin = scene.box.min;
  for (int a = 0; a < 3; ++a) v.spacing[a] = scene.box.extent()[a] / (n[a] - 1);
  v.values.resize(static_cast<std::size_t>(n[0]) * n[1] * n[2]);
  visit_field(scene, [&](const auto& field) {
    std::size_t m = 0;
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i) v.values[m++] = field.value(v.position(i, j, k));
  });
  return v;
}

ExportedNodes grid_nodes(const GridField& g) {
  ExportedNodes v;
  v.n = g.resolution();
  v.origin = g.node_position(0, 0, 0);
  // The grid's own spacing: one node step along each axis (the extent when there is one node).
  for (int a = 0; a < 3; ++a) {
    std::array<int, 3> one{0, 0, 0};
    one[a] = 1;
    v.spacing[a] = v.n[a] > 1 ? g.node_position(one[0], one[1], one[2])[a] - v.origin[a]
                              : g.box().extent()[a];
  }
  v.values.reserve(static_cast<std::size_t>(v.n[0]) * v.n[1] * v.n[2]);
  for (int k = 0; k < v.n[2]; ++k)
    for (int j = 0; j < v.n[1]; ++j)
      for (int i = 0; i < v.n[0]; ++i) v.values.push_back(g.node(i, j, k));
  return v;
}

template <class T>
void append_raw(std::string& out, const std::vector<double>& values) {
  const std::size_t at = out.size();
  out.resize(at + values.size() * sizeof(T));
  for (std::size_t m = 0; m < values.size(); ++m) {
    const T x = static_cast<T>(values[m]);
    std::memcpy(out.data() + at + m * sizeof(T), &x, sizeof(T));
  }
}

std::string vec(const Vec3& p) { return fmt::format("({:.17g},{:.17g},{:.17g})", p[0], p[1], p[2]); }

}  // namespace

ExportedNodes sample_volume(const Scene& scene, std::optional<std::array<int, 3>> resolution) {
  if (resolution) {
    for (int r : *resolution)
      if (r < 2 || r > kMaxResolution)
        throw OptionError(Option::resolution, fmt::format("every axis needs 2 to {} nodes (nodes on the box faces), got {}",
                                                          kMaxResolution, r));
    return on_box_nodes(scene, *resolution);
  }
  if (const auto* g = std::get_if<GridField>(&scene.field)) return grid_nodes(*g);
  for (int r : scene.dims)
    if (r < 2 || r > kMaxResolution)
      throw std::invalid_argument(fmt::format(
          "volume.dims: exporting an analytic field needs 2 to {} nodes per axis, got {} (give --resolution)",
          kMaxResolution, r));
  return on_box_nodes(scene, scene.dims);
}

std::string nrrd_type_name(SampleType t) { return t == SampleType::float32 ? "float" : "double"; }
std::string vtk_type_name(SampleType t) { return t == SampleType::float32 ? "Float32" : "Float64"; }

std::string raw_bytes(const ExportedNodes& v, SampleType t) {
  std::string out;
  if (t == SampleType::float32) append_raw<float>(out, v.values);
  else append_raw<double>(out, v.values);
  return out;
}

std::string nrrd_header(const ExportedNodes& v, SampleType t, const std::string& data_file) {
  std::string h = "NRRD0004\n";
  h += "# vrv export: the scene's field at grid nodes; node (i,j,k) at space origin + i,j,k space directions\n";
  h += fmt::format("type: {}\n", nrrd_type_name(t));
  h += "dimension: 3\n";
  h += "space dimension: 3\n";
  h += fmt::format("sizes: {} {} {}\n", v.n[0], v.n[1], v.n[2]);
  h += fmt::format("space directions: {} {} {}\n", vec({v.spacing[0], 0, 0}), vec({0, v.spacing[1], 0}),
                   vec({0, 0, v.spacing[2]}));
  h += "kinds: domain domain domain\n";
  h += "endian: little\n";
  h += "encoding: raw\n";
  h += fmt::format("space origin: {}\n", vec(v.origin));
  if (!data_file.empty()) h += fmt::format("data file: {}\n", data_file);
  return h + "\n";
}

std::string nrrd_file(const ExportedNodes& v, SampleType t) { return nrrd_header(v, t) + raw_bytes(v, t); }

std::string vti_file(const ExportedNodes& v, SampleType t, VtiEncoding encoding) {
  const std::string extent = fmt::format("0 {} 0 {} 0 {}", v.n[0] - 1, v.n[1] - 1, v.n[2] - 1);
  std::string x = "<?xml version=\"1.0\"?>\n";
  x += "<!-- vrv export: the scene's field at grid nodes; point (i,j,k) at Origin + (i,j,k) * Spacing -->\n";
  x += "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
  x += fmt::format("  <ImageData WholeExtent=\"{}\" Origin=\"{:.17g} {:.17g} {:.17g}\" Spacing=\"{:.17g} {:.17g} {:.17g}\">\n",
                   extent, v.origin[0], v.origin[1], v.origin[2], v.spacing[0], v.spacing[1], v.spacing[2]);
  x += fmt::format("    <Piece Extent=\"{}\">\n", extent);
  x += "      <PointData Scalars=\"field\">\n";
  const std::string type = vtk_type_name(t);
  if (encoding == VtiEncoding::ascii) {
    x += fmt::format("        <DataArray type=\"{}\" Name=\"field\" NumberOfComponents=\"1\" format=\"ascii\">\n", type);
    for (std::size_t m = 0; m < v.values.size(); ++m) {
      // fmt's "{}" is the shortest text that reads back to the same value of the stored type.
      x += t == SampleType::float32 ? fmt::format("{}", static_cast<float>(v.values[m]))
                                    : fmt::format("{}", v.values[m]);
      x += (m + 1) % 6 == 0 || m + 1 == v.values.size() ? '\n' : ' ';
    }
    x += "        </DataArray>\n";
  } else {
    x += fmt::format("        <DataArray type=\"{}\" Name=\"field\" NumberOfComponents=\"1\" format=\"appended\" offset=\"0\"/>\n", type);
  }
  x += "      </PointData>\n";
  x += "      <CellData>\n      </CellData>\n";
  x += "    </Piece>\n";
  x += "  </ImageData>\n";
  if (encoding == VtiEncoding::raw_appended) {
    const std::string data = raw_bytes(v, t);
    const std::uint64_t bytes = data.size();
    x += "  <AppendedData encoding=\"raw\">\n   _";
    x.append(reinterpret_cast<const char*>(&bytes), sizeof bytes);  // little-endian host (npy.cpp asserts it)
    x += data;
    x += "\n  </AppendedData>\n";
  }
  return x + "</VTKFile>\n";
}

std::string metaimage_file(const ExportedNodes& v, SampleType t) {
  std::string h = "ObjectType = Image\n";
  h += "NDims = 3\n";
  h += "BinaryData = True\n";
  h += "BinaryDataByteOrderMSB = False\n";
  h += "CompressedData = False\n";
  h += "TransformMatrix = 1 0 0 0 1 0 0 0 1\n";
  h += fmt::format("Offset = {:.17g} {:.17g} {:.17g}\n", v.origin[0], v.origin[1], v.origin[2]);
  h += "CenterOfRotation = 0 0 0\n";
  h += fmt::format("ElementSpacing = {:.17g} {:.17g} {:.17g}\n", v.spacing[0], v.spacing[1], v.spacing[2]);
  h += fmt::format("DimSize = {} {} {}\n", v.n[0], v.n[1], v.n[2]);
  h += fmt::format("ElementType = {}\n", t == SampleType::float32 ? "MET_FLOAT" : "MET_DOUBLE");
  h += "ElementDataFile = LOCAL\n";
  return h + raw_bytes(v, t);
}

std::string nifti_file(const ExportedNodes& v, SampleType t) {
  // niftilib's own header struct (348 bytes, the standard's layout), then the 4-byte extension
  // flag (none) and the samples at vox_offset 352.
  static_assert(sizeof(nifti_1_header) == 348);
  nifti_1_header h{};
  h.sizeof_hdr = 348;
  h.dim[0] = 3;
  for (int a = 0; a < 3; ++a) h.dim[a + 1] = static_cast<short>(v.n[a]);
  for (int a = 4; a < 8; ++a) h.dim[a] = 1;
  h.datatype = t == SampleType::float32 ? NIFTI_TYPE_FLOAT32 : NIFTI_TYPE_FLOAT64;
  h.bitpix = t == SampleType::float32 ? 32 : 64;
  h.pixdim[0] = 1;  // qfac
  for (int a = 0; a < 3; ++a) h.pixdim[a + 1] = static_cast<float>(v.spacing[a]);
  h.vox_offset = 352;
  h.scl_slope = 1;
  h.xyzt_units = NIFTI_UNITS_UNKNOWN;  // vrv's world units, whatever the scene's are
  std::snprintf(h.descrip, sizeof h.descrip, "vrv export: the scene's field at grid nodes");
  // The same placement twice: qform (identity rotation) and sform (diagonal), both float32.
  h.qform_code = h.sform_code = NIFTI_XFORM_SCANNER_ANAT;
  h.qoffset_x = static_cast<float>(v.origin[0]);
  h.qoffset_y = static_cast<float>(v.origin[1]);
  h.qoffset_z = static_cast<float>(v.origin[2]);
  float* rows[3] = {h.srow_x, h.srow_y, h.srow_z};
  for (int a = 0; a < 3; ++a) {
    rows[a][a] = static_cast<float>(v.spacing[a]);
    rows[a][3] = static_cast<float>(v.origin[a]);
  }
  std::memcpy(h.magic, "n+1", 4);
  std::string out(reinterpret_cast<const char*>(&h), sizeof h);  // little-endian host (npy.cpp asserts it)
  out.append(4, '\0');
  return out + raw_bytes(v, t);
}

}  // namespace vrv
