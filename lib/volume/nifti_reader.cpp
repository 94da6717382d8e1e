#include "lib/volume/nifti_reader.h"

#include <bit>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nifti2_io.h>

#include "lib/io/stderr_capture.h"

namespace vrv {
namespace {

struct ImageDeleter {
  void operator()(nifti_image* n) const { nifti_image_free(n); }
};

ScalarType nifti_scalar_type(const std::filesystem::path& file, int datatype) {
  switch (datatype) {
    case DT_UINT8: return ScalarType::u8;
    case DT_INT8: return ScalarType::i8;
    case DT_UINT16: return ScalarType::u16;
    case DT_INT16: return ScalarType::i16;
    case DT_UINT32: return ScalarType::u32;
    case DT_INT32: return ScalarType::i32;
    case DT_FLOAT32: return ScalarType::f32;
    case DT_FLOAT64: return ScalarType::f64;
    default:
      volume_fail(file, "datatype",
                  fmt::format("{} not supported (uint8 to int32, float32, float64; one component)",
                              nifti_datatype_string(datatype)));
  }
}

void refuse_extra_dims(const nifti_image& nim, const std::filesystem::path& file) {
  static constexpr const char* meaning[] = {"", "", "", "", "time series", "components", "", ""};
  for (int d = 4; d <= 7; ++d)
    if (nim.dim[0] >= d && nim.dim[d] > 1)
      volume_fail(file, fmt::format("dim[{}]", d),
                  fmt::format("{}-D ({} of {}) not supported (a 3-D scalar volume only)", nim.dim[0],
                              d == 4 || d == 5 ? meaning[d] : "extra axis", nim.dim[d]));
}

void set_geometry(Volume& v, const nifti_image& nim, const std::filesystem::path& file) {
  // niftilib computes qto_xyz from the quaternion with qfac, and sets it to the method-1
  // diagonal when qform_code is 0.
  const nifti_dmat44& m = nim.sform_code > 0 ? nim.sto_xyz : nim.qto_xyz;
  Eigen::Matrix3d steps;
  for (int w = 0; w < 3; ++w) {
    for (int a = 0; a < 3; ++a) steps(w, a) = m.m[w][a];
    v.origin[w] = m.m[w][3];
  }
  if (!v.origin.allFinite()) volume_fail(file, nim.sform_code > 0 ? "sform" : "qform", "non-finite offset");
  set_axis_aligned(v, steps, file, nim.sform_code > 0 ? "sform" : "qform");
}

// The data through niftilib's znzlib (plain or gzip), not nifti_image_load: that replaces NaN
// and infinite floats by 0 without a word, and a NaN must reach the scene's refusal (nibabel
// keeps them too).  Byte order as the header's.
VolumeSamples read_data(const nifti_image& nim, std::size_t count, ScalarType type, const std::filesystem::path& file) {
  znzFile f = znzopen(nim.iname, "rb", nifti_is_gzfile(nim.iname));
  if (znz_isnull(f)) volume_fail(file, "(data)", fmt::format("cannot open {}", nim.iname));
  const auto read = [&](unsigned char* out, std::size_t bytes) {
    const bool ok = znzseek(f, static_cast<znz_off_t>(nim.iname_offset), SEEK_SET) >= 0 &&  // gzseek: the offset
                    znzread(out, 1, bytes, f) == bytes;
    znzclose(f);
    if (!ok) volume_fail(file, "(data)", fmt::format("cannot read {} bytes of data from offset {} (truncated or damaged)",
                                                     bytes, nim.iname_offset));
  };
  return read_samples(type, count, nim.byteorder == 2, read);  // MSB_FIRST (defined for niftilib's own sources only)
}

// What niftilib printed, as one line: its "** ERROR: " prefixes dropped, lines joined by "; ".
std::string niftilib_said(const std::string& text) {
  std::string out;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    start = end + 1;
    if (line.starts_with("** ERROR: ")) line.erase(0, 10);
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    out += (out.empty() ? "" : "; ") + line;
  }
  return out;
}

}  // namespace

Volume read_nifti(const std::filesystem::path& file, const VolumeReadOptions& options) {
  nifti_set_debug_level(0);
  // niftilib prints some errors ("** ERROR: ...: bad datatype") whatever the debug level: they
  // become the reason in our one line instead of a second line on stderr.
  StderrCapture capture;
  std::unique_ptr<nifti_image, ImageDeleter> nim(nifti_image_read(file.c_str(), 0));
  const std::string said = niftilib_said(capture.release());
  if (!nim)
    volume_fail(file, "(header)",
                "not a readable NIfTI or ANALYZE header" + (said.empty() ? std::string() : " (niftilib: " + said + ")"));
  refuse_extra_dims(*nim, file);
  Volume v;
  const ScalarType type = nifti_scalar_type(file, nim->datatype);
  v.dims = checked_dims(file, "dim", {nim->nx, nim->ny, nim->nz});
  set_geometry(v, *nim, file);
  check_budget(file, "dim", v, type, 0, options);
  if (std::isfinite(nim->scl_slope) && nim->scl_slope != 0) {
    v.slope = nim->scl_slope;
    v.intercept = std::isfinite(nim->scl_inter) ? nim->scl_inter : 0.0;
  }
  v.has_rescale = true;

  // A single file's data cannot start inside its header (vox_offset below 352, e.g. 0, which
  // nibabel's own test files have): niftilib would read the header as data, nibabel starts after
  // it, as the standard's minimum says.
  const std::int64_t header_end = nim->nifti_type == NIFTI_FTYPE_NIFTI1_1 ? 352
                                  : nim->nifti_type == NIFTI_FTYPE_NIFTI2_1 ? 544 : 0;
  if (nim->iname_offset < header_end) nim->iname_offset = header_end;
  const std::size_t count = static_cast<std::size_t>(v.dims[0]) * v.dims[1] * v.dims[2];
  const std::int64_t bytes = static_cast<std::int64_t>(count * scalar_bytes(type));
  if (nim->iname && !nifti_is_gzfile(nim->iname)) {
    // A truncated file is named as such (niftilib only says that reading failed).
    const std::int64_t size = nifti_get_filesize(nim->iname);
    if (size < nim->iname_offset + bytes)
      volume_fail(file, "(data)", fmt::format("truncated: {} bytes of data from offset {} need {} bytes, "
                                              "the file has {}", bytes, nim->iname_offset,
                                              nim->iname_offset + bytes, size));
  }
  v.samples = read_data(*nim, count, type, file);
  v.files.push_back(file);
  if (nim->iname && nim->fname && std::string(nim->iname) != nim->fname) v.files.push_back(nim->iname);
  return v;
}

}  // namespace vrv
