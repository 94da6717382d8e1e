#include "lib/volume/nrrd_reader.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <fstream>
#include <string_view>
#include <memory>
#include <string>
#include <vector>
#include <bit>

#include <fmt/format.h>
#include <teem/nrrd.h>

namespace vrv {
namespace {

struct NrrdDeleter {
  void operator()(Nrrd* n) const { nrrdNuke(n); }
};

// Teem's error stack as one line (its messages span several lines and say where in Teem).
std::string teem_error() {
  char* raw = biffGetDone(NRRD);
  std::string s = raw ? raw : "unknown Teem error";
  std::free(raw);
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

ScalarType nrrd_scalar_type(const std::filesystem::path& file, int type) {
  switch (type) {
    case nrrdTypeUChar: return ScalarType::u8;
    case nrrdTypeChar: return ScalarType::i8;
    case nrrdTypeUShort: return ScalarType::u16;
    case nrrdTypeShort: return ScalarType::i16;
    case nrrdTypeUInt: return ScalarType::u32;
    case nrrdTypeInt: return ScalarType::i32;
    case nrrdTypeFloat: return ScalarType::f32;
    case nrrdTypeDouble: return ScalarType::f64;
    default:
      volume_fail(file, "type", fmt::format("{} not supported (uint8 to int32, float, double)",
                                            airEnumStr(nrrdType, type)));
  }
}

// The I/O state of a header pass, and the data file Teem keeps open for it.
struct IoDeleter {
  void operator()(NrrdIoState* n) const {
    if (n->dataFile) airFclose(n->dataFile);
    nrrdIoStateNix(n);
  }
};
struct Loaded {
  std::unique_ptr<Nrrd, NrrdDeleter> nrrd;
  std::unique_ptr<NrrdIoState, IoDeleter> nio;
};

// The nrrd's header (no data; Teem then keeps a single data file open where its data start) or
// its data too; Teem's own message when it refuses.  With `data_files`, the detached data files
// the header names (for the scene hash).
Loaded load(const std::filesystem::path& file, bool skip_data, std::vector<std::filesystem::path>* data_files = nullptr) {
  std::unique_ptr<Nrrd, NrrdDeleter> nrrd(nrrdNew());
  std::unique_ptr<NrrdIoState, IoDeleter> nio(nrrdIoStateNew());
  nrrdIoStateSet(nio.get(), nrrdIoStateSkipData, skip_data ? AIR_TRUE : AIR_FALSE);
  nrrdIoStateSet(nio.get(), nrrdIoStateKeepNrrdDataFileOpen, skip_data ? AIR_TRUE : AIR_FALSE);
  if (nrrdLoad(nrrd.get(), file.c_str(), nio.get())) {
    // Data in the header's own file: nrrdLoad closed that file on its way out, but the pointer
    // it kept for us is still set (closing it again was a double free, found by fuzz_nrrd_reader).
    if (!nio->dataFNArr || nio->dataFNArr->len == 0) nio->dataFile = nullptr;
    volume_fail(file, skip_data ? "(header)" : "(data)", teem_error());
  }
  if (data_files) {
    if (nio->dataFNFormat)
      volume_fail(file, "data file", "a numbered pattern of data files is not supported (name them, or LIST)");
    const std::filesystem::path dir = file.parent_path();
    for (unsigned i = 0; nio->dataFNArr && i < nio->dataFNArr->len; ++i) {
      const std::filesystem::path name = nio->dataFN[i];
      data_files->push_back(name.is_absolute() ? name : dir / name);
    }
  }
  return {std::move(nrrd), std::move(nio)};
}

// Where the data of a single-file raw or gzip NRRD are.  Teem reads data into a buffer of its
// own, and the samples were then a second copy of the scan; its header pass leaves the one data
// file open after the line skips (and, for raw data, the byte skip), so the data are read from
// there straight into the samples, as the other readers read theirs.  Nothing for what only Teem
// decodes (ascii, hex, bzip2), several data files, per-file skips, or a byte skip inside a gzip
// stream: those still go through Teem and one copy.
std::optional<StoredSamples> nrrd_direct_data(const std::filesystem::path& file,
                                              const std::vector<std::filesystem::path>& data_files,
                                              const NrrdIoState& nio) {
  const bool raw = nio.encoding == nrrdEncodingRaw, gzip = nio.encoding == nrrdEncodingGzip;
  if (!(raw || gzip) || !nio.dataFile || data_files.size() > 1 || nio.dataFSkip) return std::nullopt;
  if (gzip && nio.byteSkip != 0) return std::nullopt;
  const long at = std::ftell(nio.dataFile);
  if (at < 0) return std::nullopt;
  StoredSamples d{data_files.empty() ? file : data_files.front(), static_cast<std::uint64_t>(at), 0, gzip};
  const std::uint64_t size = file_size_of(d.path);
  d.available = size > d.offset ? size - d.offset : 0;
  return d;
}

void set_geometry(Volume& v, const Nrrd& n, const std::filesystem::path& file) {
  Eigen::Matrix3d steps = Eigen::Matrix3d::Zero();
  if (n.spaceDim == 3) {
    for (int a = 0; a < 3; ++a)
      for (int w = 0; w < 3; ++w) steps(w, a) = n.axis[a].spaceDirection[w];
    for (int w = 0; w < 3; ++w) v.origin[w] = std::isfinite(n.spaceOrigin[w]) ? n.spaceOrigin[w] : 0.0;
    set_axis_aligned(v, steps, file, "space directions");
  } else if (n.spaceDim == 0) {
    for (int a = 0; a < 3; ++a) {
      const double s = n.axis[a].spacing;
      steps(a, a) = std::isfinite(s) ? s : 1.0;
    }
    // No space: no origin either ("axis mins" bound a range whose relation to the first sample
    // depends on the centering), so the first sample sits at 0.
    set_axis_aligned(v, steps, file, "spacings");
  } else {
    volume_fail(file, "space", fmt::format("{}-dimensional space not supported (3 or none)", n.spaceDim));
  }
}

}  // namespace

Volume read_nrrd(const std::filesystem::path& file, const VolumeReadOptions& options) {
  nrrdStateVerboseIO = 0;
  // NRRD only: nrrdLoad would otherwise try its other formats (PNM, PNG, VTK, text), whose
  // failure paths leak in Teem 1.12 (found by fuzz_nrrd_reader).
  {
    std::ifstream in(file, std::ios::binary);
    char magic[7] = {};
    if (!in.read(magic, sizeof magic) || std::string_view(magic, sizeof magic) != "NRRD000")
      volume_fail(file, "(header)", "not a NRRD file (no NRRD000x magic on its first line)");
  }
  std::vector<std::filesystem::path> data_files;
  const Loaded loaded = load(file, true, &data_files);
  const Nrrd* header = loaded.nrrd.get();
  if (header->dim != 3) {
    std::string kinds;
    for (unsigned a = 0; a < header->dim && a < NRRD_DIM_MAX; ++a)
      if (header->axis[a].kind != nrrdKindUnknown && !nrrdKindIsDomain(header->axis[a].kind))
        kinds += fmt::format(" axis {} is {} (multi-component)", a, airEnumStr(nrrdKind, header->axis[a].kind));
    volume_fail(file, "dimension",
                fmt::format("{} axes not supported (a 3-D scalar volume only; several components or "
                            "a time series are refused){}", header->dim, kinds));
  }
  Volume v;
  const ScalarType type = nrrd_scalar_type(file, header->type);
  v.dims = checked_dims(file, "sizes",
                        {static_cast<std::int64_t>(header->axis[0].size), static_cast<std::int64_t>(header->axis[1].size),
                         static_cast<std::int64_t>(header->axis[2].size)});
  set_geometry(v, *header, file);
  const std::size_t count = static_cast<std::size_t>(v.dims[0]) * v.dims[1] * v.dims[2];
  const std::optional<StoredSamples> place = nrrd_direct_data(file, data_files, *loaded.nio);
  check_budget(file, "sizes", v, type, place ? 0 : count * scalar_bytes(type), options);
  if (place) {
    v.samples = read_stored_samples(*place, type, count, loaded.nio->endian == airEndianBig, file, "(data)");
  } else {
    const Loaded full = load(file, false);
    if (!full.nrrd->data) volume_fail(file, "(data)", "no data");
    // Teem has swapped the data to this machine's byte order.
    v.samples = samples_from_bytes(type, static_cast<const unsigned char*>(full.nrrd->data), count,
                                   std::endian::native == std::endian::big);
  }
  v.files.push_back(file);
  v.files.insert(v.files.end(), data_files.begin(), data_files.end());
  return v;
}

}  // namespace vrv
