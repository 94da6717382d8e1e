#pragma once
// What a projection computes along a ray, instead of the emission-absorption integral.
//   xray            int f(s) ds over the clipped ray (no absorption, no normalisation by length)
//   xray_classified int tau(f(s)) ds: the transfer function's extinction of the field (the
//                   optical depth; for an opacity/colour transfer function tau = -ln(1 - a) / L)
//   mip             max f(s) over the clipped ray, and where it is first reached
//   mip_classified  max tau(f(s)): the maximum of the extinction of the field, which is not the
//                   extinction of the maximum (tau need not be monotone)
#include <optional>
#include <string>
#include <string_view>

#include "lib/transfer_function.h"

namespace vrv {

enum class ProjectionMode { xray, xray_classified, mip, mip_classified };

// Names: "xray", "xray_classified", "mip", "mip_classified" (one table, lib/util/enum_names.h).
std::optional<ProjectionMode> parse_projection_mode(std::string_view name);
std::string_view projection_mode_name(ProjectionMode m);
// "xray, xray_classified, mip, mip_classified": for error messages.
std::string projection_mode_list();

bool is_mip(ProjectionMode m);
bool is_classified(ProjectionMode m);

// The classified quantity of a field value: the transfer function's extinction tau(v)
// (right-continuous at a jump).
inline double classified_value(const TransferFunction& tf, double v) { return tf.extinction(v); }

}  // namespace vrv
