#pragma once
// The node values of a grid, held in the samples' own scalar type: a 512³ int16 scan costs its
// 256 MiB, not 1 GiB of doubles.
//
// Kinds: doubles (a grid sampled from a function, or given node values); 8- and 16-bit samples
// read through a table holding the value of every code (the volume's mapping applied once per
// code, so a read is one load more and gives bit for bit the double the mapping gives); 32-bit
// samples (uint32, int32, float32) mapped on each read.  Copies share the samples (immutable).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string_view>
#include <vector>

#include "lib/util/force_inline.h"
#include "lib/volume/volume.h"

namespace vrv {

// A stored sample s to its node value: x = slope s + intercept where `rescale`, else s; with a
// window, (x - lo) / (hi - lo) clamped to [0, 1].  The arithmetic every kind applies, so that a
// table entry and a per-read mapping give the same double.
struct SampleMap {
  bool rescale = false;
  double slope = 1, intercept = 0;
  bool window = false;
  double lo = 0, hi = 1;
  double operator()(double s) const {
    const double x = rescale ? slope * s + intercept : s;
    if (!window) return x;
    return std::clamp((x - lo) / (hi - lo), 0.0, 1.0);
  }
};

// What GridNodes of `count` samples of type `t` hold: the samples and, for 8/16-bit ones, the table
// of every code's value (2^8 or 2^16 doubles).
std::size_t grid_nodes_bytes(ScalarType t, std::size_t count);

class GridNodes {
 public:
  enum class Kind { f64, code8, code16, u32, i32, f32 };

  GridNodes() = default;
  explicit GridNodes(std::vector<double> values);
  // `samples` in node order, each read through `map`.  float64 samples are mapped into doubles
  // once (the same size).
  GridNodes(VolumeSamples samples, const SampleMap& map);

  Kind kind() const { return kind_; }
  std::size_t size() const { return size_; }
  // Bytes held: the samples and, for 8/16-bit ones, the table (grid_nodes_bytes).
  std::size_t bytes() const;
  double operator[](std::size_t n) const;
  // f(fetch) with fetch(n) the value of node n, fetch's type fixed per kind (the interpolation
  // loops are compiled once per kind; the dispatch is one predictable branch per call).
  template <class F>
  VRV_FORCE_INLINE decltype(auto) visit(F&& f) const;
  // What determines every node value, as bytes in this machine's order: the stored samples, and
  // the table (8/16-bit) or the mapping's numbers (32-bit).  What a scene hash covers in place of
  // the values (an eighth of their bytes for uint8 samples).
  std::string_view stored_bytes() const;
  std::string_view table_bytes() const;
  const SampleMap& map() const { return map_; }
  // fn applied to every node value: for 8/16-bit samples only the table changes.
  GridNodes mapped(const std::function<double(double)>& fn) const;

  struct Doubles {
    const double* p;
    double operator()(std::size_t n) const { return p[n]; }
  };
  template <class Code>
  struct Coded {
    const Code* p;
    const double* table;
    double operator()(std::size_t n) const { return table[p[n]]; }
  };
  template <class T>
  struct Mapped {
    const T* p;
    SampleMap map;
    double operator()(std::size_t n) const { return map(static_cast<double>(p[n])); }
  };

 private:
  void point_at(std::shared_ptr<const VolumeSamples> samples, std::shared_ptr<const std::vector<double>> table);

  std::shared_ptr<const VolumeSamples> samples_;    // doubles for Kind::f64
  std::shared_ptr<const std::vector<double>> table_owner_;  // 8/16-bit kinds: every bit pattern's value
  Kind kind_ = Kind::f64;
  std::size_t size_ = 0;
  const void* data_ = nullptr;
  const double* table_ = nullptr;
  SampleMap map_;
};

template <class F>
VRV_FORCE_INLINE decltype(auto) GridNodes::visit(F&& f) const {
  // Signed codes are read through the unsigned type of the same width (allowed aliasing); the
  // table is indexed by the bit pattern.
  switch (kind_) {
    case Kind::code8: return f(Coded<std::uint8_t>{static_cast<const std::uint8_t*>(data_), table_});
    case Kind::code16: return f(Coded<std::uint16_t>{static_cast<const std::uint16_t*>(data_), table_});
    case Kind::u32: return f(Mapped<std::uint32_t>{static_cast<const std::uint32_t*>(data_), map_});
    case Kind::i32: return f(Mapped<std::int32_t>{static_cast<const std::int32_t*>(data_), map_});
    case Kind::f32: return f(Mapped<float>{static_cast<const float*>(data_), map_});
    case Kind::f64: break;
  }
  return f(Doubles{static_cast<const double*>(data_)});
}

inline double GridNodes::operator[](std::size_t n) const {
  return visit([n](auto fetch) { return fetch(n); });
}

}  // namespace vrv
