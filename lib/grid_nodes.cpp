#include "lib/grid_nodes.h"

#include <type_traits>
#include <utility>

namespace vrv {
namespace {

template <class T>
constexpr GridNodes::Kind node_kind_of() {
  if constexpr (std::is_same_v<T, double>) return GridNodes::Kind::f64;
  else if constexpr (sizeof(T) == 1) return GridNodes::Kind::code8;
  else if constexpr (sizeof(T) == 2) return GridNodes::Kind::code16;
  else if constexpr (std::is_same_v<T, std::uint32_t>) return GridNodes::Kind::u32;
  else if constexpr (std::is_same_v<T, std::int32_t>) return GridNodes::Kind::i32;
  else return GridNodes::Kind::f32;
}

// The value of every bit pattern of an 8- or 16-bit type T, indexed as the unsigned type reads it.
template <class T>
std::vector<double> code_table(const std::function<double(double)>& value_of_stored) {
  using Code = std::make_unsigned_t<T>;
  std::vector<double> table(std::size_t{1} << (8 * sizeof(T)));
  for (std::size_t c = 0; c < table.size(); ++c)
    table[c] = value_of_stored(static_cast<double>(static_cast<T>(static_cast<Code>(c))));
  return table;
}

}  // namespace

GridNodes::GridNodes(std::vector<double> values) {
  point_at(std::make_shared<const VolumeSamples>(std::move(values)), nullptr);
}

GridNodes::GridNodes(VolumeSamples samples, const SampleMap& map) : map_(map) {
  std::shared_ptr<std::vector<double>> table;
  std::visit(
      [&](auto& v) {
        using T = typename std::decay_t<decltype(v)>::value_type;
        if constexpr (std::is_same_v<T, double>) {
          for (double& x : v) x = map(x);
        } else if constexpr (sizeof(T) <= 2) {
          table = std::make_shared<std::vector<double>>(code_table<T>(map));
        }
      },
      samples);
  point_at(std::make_shared<const VolumeSamples>(std::move(samples)), std::move(table));
}

void GridNodes::point_at(std::shared_ptr<const VolumeSamples> samples,
                         std::shared_ptr<const std::vector<double>> table) {
  samples_ = std::move(samples);
  table_owner_ = std::move(table);
  std::visit(
      [&](const auto& v) {
        using T = typename std::decay_t<decltype(v)>::value_type;
        kind_ = node_kind_of<T>();
        size_ = v.size();
        data_ = v.data();
      },
      *samples_);
  table_ = table_owner_ ? table_owner_->data() : nullptr;
}

std::size_t grid_nodes_bytes(ScalarType t, std::size_t count) {
  const std::size_t width = scalar_bytes(t);
  return count * width + (width <= 2 ? (std::size_t{1} << (8 * width)) * sizeof(double) : 0);
}

std::size_t GridNodes::bytes() const { return grid_nodes_bytes(static_cast<ScalarType>(samples_->index()), size_); }

std::string_view GridNodes::stored_bytes() const {
  return {static_cast<const char*>(data_), size_ * scalar_bytes(static_cast<ScalarType>(samples_->index()))};
}

std::string_view GridNodes::table_bytes() const {
  if (!table_owner_) return {};
  return {reinterpret_cast<const char*>(table_owner_->data()), table_owner_->size() * sizeof(double)};
}

GridNodes GridNodes::mapped(const std::function<double(double)>& fn) const {
  if (table_owner_) {
    // The samples stay shared: only the table is new.
    auto table = std::make_shared<std::vector<double>>(*table_owner_);
    for (double& t : *table) t = fn(t);
    GridNodes out = *this;
    out.point_at(samples_, std::move(table));
    return out;
  }
  std::vector<double> values(size_);
  visit([&](auto fetch) {
    for (std::size_t n = 0; n < size_; ++n) values[n] = fn(fetch(n));
  });
  return GridNodes(std::move(values));
}

}  // namespace vrv
