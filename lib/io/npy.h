#pragma once
// NumPy .npy files (format version 1.0): little-endian float64 ('<f8') or float32 ('<f4'),
// C order (last index fastest), as numpy.load reads them.
//
// Hand-written on purpose: the format is a 10-byte preamble and a Python-dict header
// (numpy/lib/format.py), Debian ships no C++ npy library (cnpy and libnpy are not packaged), and
// OpenImageIO, which reads every other image verify takes, does not read .npy.
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace vrv {

// The bytes of a .npy file holding `values` with the given shape (product of shape = size,
// else std::invalid_argument).  The header is padded with spaces to a multiple of 64 bytes.
std::string npy_bytes(std::span<const double> values, const std::vector<std::size_t>& shape);
std::string npy_bytes(std::span<const float> values, const std::vector<std::size_t>& shape);

struct NpyArray {
  std::string dtype;                // "<f8" or "<f4"
  std::vector<std::size_t> shape;
  std::vector<double> values;       // C order; float32 files widened exactly
};

// Reads a version 1.0 or 2.0 .npy of '<f8' or '<f4' in C order.  Throws std::runtime_error,
// one line naming the file, for anything else (bad magic, other dtype, Fortran order, a size
// that does not match the shape).
NpyArray read_npy(const std::filesystem::path& path);
// The same from bytes already in memory; `name` labels errors.
NpyArray parse_npy(std::string_view bytes, const std::string& name);

}  // namespace vrv
