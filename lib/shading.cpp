#include "lib/shading.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "lib/util/enum_names.h"

namespace vrv {
namespace {

static_assert(names_complete(kShadingModelNames) && names_complete(kNormalSignNames));

void require_coefficient(double value, std::string_view key) {
  if (!(value >= 0) || !std::isfinite(value))
    throw std::invalid_argument(fmt::format("shading.{}: must be a finite number >= 0, got {}", key, value));
}

// x^p for x in [0, 1] and p >= 0: by squaring where p is a whole number up to 64, as most
// exponents are (std::pow was a fifth of a shaded ray's time: two calls per node); std::pow
// otherwise.  Each squaring doubles the base's relative rounding, so x^p is within about p ulps:
// a sixteenth of what evaluate() charges it (16 eps x p relative).
double power(double x, double p) {
  if (!(p >= 0 && p <= 64 && p == std::floor(p))) return std::pow(x, p);
  double result = 1, base = x;
  for (auto n = static_cast<unsigned>(p); n > 0; n >>= 1) {
    if (n & 1) result *= base;
    base *= base;
  }
  return result;
}

}  // namespace

std::optional<ShadingModel> parse_shading_model(std::string_view name) {
  return parse_name(kShadingModelNames, name);
}
std::string_view shading_model_name(ShadingModel m) { return name_of(kShadingModelNames, m); }
std::optional<NormalSign> parse_normal_sign(std::string_view name) { return parse_name(kNormalSignNames, name); }
std::string_view normal_sign_name(NormalSign s) { return name_of(kNormalSignNames, s); }

void validate(const Shading& s) {
  require_coefficient(s.ambient, "ambient");
  require_coefficient(s.diffuse, "diffuse");
  require_coefficient(s.specular, "specular");
  if (!(s.shininess >= 1) || !std::isfinite(s.shininess))
    throw std::invalid_argument(fmt::format("shading.shininess: must be a finite number >= 1, got {}", s.shininess));
  if (!std::isfinite(s.max_factor()))
    throw std::invalid_argument("shading.specular: ambient + diffuse + specular must be finite");
  if (!std::isfinite(4 * s.specular * s.shininess))
    throw std::invalid_argument(fmt::format("shading.shininess: specular x shininess must be finite, got {} x {}",
                                            s.specular, s.shininess));
  if (s.light && (!s.light->allFinite() || !(s.light->cwiseAbs().maxCoeff() > 0)))
    throw std::invalid_argument("shading.light: must be a finite, non-zero direction (toward the light)");
}

ShadingFactor::ShadingFactor(const Shading& shading, const Vec3& direction) : shading_(shading) {
  sign_ = shading.normal == NormalSign::gradient ? 1.0 : -1.0;
  view_ = -direction.normalized();
  // Scaled before normalising: a light of 1e200 (or 1e-170) is still a direction.
  light_ = shading.light ? Vec3((*shading.light / shading.light->cwiseAbs().maxCoeff()).normalized()) : view_;
  const Vec3 sum = light_ + view_;
  // Light straight behind the volume (l = -v, up to rounding): no half vector; n.h is then taken
  // as 0 (no highlight), not a direction made of rounding.
  half_ = sum.norm() > 8 * std::numeric_limits<double>::epsilon() ? Vec3(sum.normalized()) : Vec3::Zero();
  light_dot_view_ = light_.dot(view_);
  max_ = shading.max_factor();
  min_ = shading.min_factor();
}

Vec3 ShadingFactor::normal(const Vec3& gradient, double sign, double& norm) const {
  // Scaled first: a gradient of 1e-170 squares to 0, one of 1e170 to infinity.
  const double scale = gradient.cwiseAbs().maxCoeff();
  if (!(scale > 0) || !std::isfinite(scale)) {
    norm = 0;
    return Vec3::Zero();
  }
  const Vec3 g = gradient / scale;
  norm = g.norm();
  return (sign * sign_ / norm) * g;
}

ShadingFactor::Branch ShadingFactor::branch(const Vec3& gradient) const {
  Branch b;
  double norm = 0;
  Vec3 n = normal(gradient, 1, norm);
  if (!(norm > 0)) {
    b.zero = true;
    return b;
  }
  if (shading_.two_sided && n.dot(view_) < 0) b.sign = -1, n = -n;
  b.diffuse = n.dot(light_) > 0;
  b.specular = shading_.model == ShadingModel::blinn_phong
                   ? n.dot(half_) > 0
                   : 2 * n.dot(light_) * n.dot(view_) - light_dot_view_ > 0;
  return b;
}

ShadingFactor::Value ShadingFactor::evaluate(const Vec3& gradient, const Branch& b) const {
  constexpr double eps = std::numeric_limits<double>::epsilon();
  double norm = 0;
  const Vec3 n = normal(gradient, b.sign, norm);
  Value v;
  v.s = shading_.ambient;
  if (b.zero || !(norm > 0)) return v;
  // On the branch the terms are continued smoothly up to the piece's ends: n.l may be a rounding
  // below 0 at an end that lies on its switch; the specular base is clamped, x^p being undefined
  // below 0 (and continuous at 0 for p >= 1).
  const double n_l = n.dot(light_);
  if (b.diffuse) v.s += shading_.diffuse * n_l, v.diffuse = true;
  double highlight = 0;
  if (b.specular && shading_.specular > 0) {
    const bool blinn = shading_.model == ShadingModel::blinn_phong;
    v.base = std::max(blinn ? n.dot(half_) : 2 * n_l * n.dot(view_) - light_dot_view_, 0.0);
    highlight = shading_.specular * power(v.base, shading_.shininess);
    v.s += highlight;
    v.specular = true;
  }
  // A few ulps per term; the power's relative error grows with the exponent times the base's.
  v.rounding = 16 * eps * (v.s + highlight * shading_.shininess);
  return v;
}

double ShadingFactor::change_within(const Value& v, double dn) const {
  dn = std::min(dn, 2.0);  // two unit vectors are at most 2 apart
  double change = 0;
  if (v.diffuse) change += shading_.diffuse * dn;
  if (v.specular) {
    const double moved = (shading_.model == ShadingModel::blinn_phong ? 1.0 : 4.0) * dn;
    const double p = shading_.shininess;
    change += shading_.specular * std::min(1.0, p * power(std::min(1.0, v.base + moved), p - 1) * moved);
  }
  return change;
}

bool ShadingFactor::has_switch(int k) const {
  switch (k) {
    case 0: return shading_.two_sided;
    case 1: return shading_.diffuse > 0;
    default: return shading_.specular > 0;
  }
}

double ShadingFactor::switch_value(int k, const Vec3& gradient) const {
  if (!has_switch(k)) return 0;
  // Zeros of these are the switches whichever way a two-sided normal faces (q(-g) = -q(g) for the
  // linear ones, and Phong's is even in g): smooth along the ray, so a proxy finds them.
  const Vec3 g = sign_ * gradient;
  switch (k) {
    case 0: return g.dot(view_);
    case 1: return g.dot(light_);
    default:
      if (shading_.model == ShadingModel::blinn_phong) return g.dot(half_);
      return 2 * g.dot(light_) * g.dot(view_) - light_dot_view_ * g.squaredNorm();  // r.v |g|^2
  }
}

}  // namespace vrv
