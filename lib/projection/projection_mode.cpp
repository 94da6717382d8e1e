#include "lib/projection/projection_mode.h"

#include "lib/util/enum_names.h"

namespace vrv {
namespace {

constexpr NameTable<ProjectionMode, 4> kModes{{
    {ProjectionMode::xray, "xray"},
    {ProjectionMode::xray_classified, "xray_classified"},
    {ProjectionMode::mip, "mip"},
    {ProjectionMode::mip_classified, "mip_classified"},
}};
static_assert(names_complete(kModes));

}  // namespace

std::optional<ProjectionMode> parse_projection_mode(std::string_view name) { return parse_name(kModes, name); }
std::string_view projection_mode_name(ProjectionMode m) { return name_of(kModes, m); }

std::string projection_mode_list() { return name_list(kModes); }

bool is_mip(ProjectionMode m) { return m == ProjectionMode::mip || m == ProjectionMode::mip_classified; }
bool is_classified(ProjectionMode m) {
  return m == ProjectionMode::xray_classified || m == ProjectionMode::mip_classified;
}

}  // namespace vrv
