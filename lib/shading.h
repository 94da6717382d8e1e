#pragma once
// Gradient shading of the emission: a Phong or Blinn-Phong factor
//   S = ambient + diffuse max(0, n.l) + specular max(0, n.h)^shininess      (Blinn-Phong)
//   S = ambient + diffuse max(0, n.l) + specular max(0, r.v)^shininess      (Phong, r = 2 (n.l) n - l)
// with n = +-grad f / |grad f|, v the direction toward the eye (minus the ray's direction), l the
// direction toward the light (a directional light, or the headlight l = v) and h = (l + v) / |l + v|.
// Emission is multiplied by S, extinction is not.  Where the gradient vanishes, S = ambient.
// Two-sided: n is turned to face the eye (n.v >= 0) before the terms are taken.
#include <optional>
#include <string_view>

#include "lib/geometry.h"
#include "lib/util/enum_names.h"

namespace vrv {

enum class ShadingModel { phong, blinn_phong };
// The normal's sign: "gradient" (n points toward higher values) or "negative_gradient" (toward
// lower values: outward from a bright object on a dark background, as VTK's ray caster takes it).
enum class NormalSign { gradient, negative_gradient };
// Their names in scene files ([shading] model, normal).
inline constexpr NameTable<ShadingModel, 2> kShadingModelNames{
    {{ShadingModel::phong, "phong"}, {ShadingModel::blinn_phong, "blinn_phong"}}};
inline constexpr NameTable<NormalSign, 2> kNormalSignNames{
    {{NormalSign::gradient, "gradient"}, {NormalSign::negative_gradient, "negative_gradient"}}};

std::optional<ShadingModel> parse_shading_model(std::string_view name);  // "phong", "blinn_phong"
std::string_view shading_model_name(ShadingModel m);
std::optional<NormalSign> parse_normal_sign(std::string_view name);  // "gradient", "negative_gradient"
std::string_view normal_sign_name(NormalSign s);

struct Shading {
  ShadingModel model = ShadingModel::blinn_phong;
  double ambient = 0.2;
  double diffuse = 0.7;
  double specular = 0.1;
  double shininess = 16;
  // Toward the light, unit length; none: a headlight (the light sits at the eye).
  std::optional<Vec3> light;
  NormalSign normal = NormalSign::negative_gradient;
  bool two_sided = true;

  double max_factor() const { return ambient + diffuse + specular; }
  double min_factor() const { return ambient; }
};

// Throws std::invalid_argument naming the key ("shading.ambient: ...") unless the coefficients
// are finite and >= 0 and their sum finite, shininess finite and >= 1 (max(0, x)^p is then
// continuous at its kink) with specular x shininess finite, and the light finite and non-zero
// (ShadingFactor normalises it, scaled first: any finite size is a direction).
void validate(const Shading& shading);

// S along the rays of one direction: l, v and h are fixed along a ray.  The switches of S (where a
// max(0, .) kinks, or a two-sided normal flips) are the sign changes of functions of the gradient
// that need no normalisation (switch_value); a piece of the ray between switches is one branch.
class ShadingFactor {
 public:
  ShadingFactor(const Shading& shading, const Vec3& direction);

  // Which side of each switch: fixed for a piece from the gradient at its middle, so that S on
  // the piece is one smooth function up to its ends (a node on a switch takes the piece's side).
  struct Branch {
    double sign = 1;       // n = sign grad f / |grad f|
    bool diffuse = false;  // n.l > 0
    bool specular = false; // n.h > 0 (Blinn-Phong) or r.v > 0 (Phong)
    bool zero = false;     // the gradient vanishes: S = ambient
  };
  Branch branch(const Vec3& gradient) const;
  // S on a branch; a gradient of 0 gives the ambient term alone.
  double operator()(const Vec3& gradient, const Branch& branch) const { return evaluate(gradient, branch).s; }
  // S with the rounding of its own evaluation, and what change_within needs.
  struct Value {
    double s = 0;
    double rounding = 0;
    bool diffuse = false, specular = false;  // the terms taken
    double base = 0;                         // the specular base (n.h or r.v), clamped at 0
  };
  Value evaluate(const Vec3& gradient, const Branch& branch) const;
  // A bound on |S(n') - S(n)| for every unit n' within dn of the normal that gave v, on v's
  // branch: diffuse dn, and specular |x^p - y^p| <= p max(x, y)^(p - 1) |x - y| with the base
  // moved by at most dn (4 dn for Phong's r.v), never more than the term's own range.
  double change_within(const Value& v, double dn) const;
  // S where the gradient is (its own branch).
  double operator()(const Vec3& gradient) const { return (*this)(gradient, branch(gradient)); }

  static constexpr int kSwitches = 3;
  // The k-th switch function (0: n.v for the two-sided flip, 1: n.l, 2: n.h or r.v), up to a
  // positive factor, for the normal grad f; 0 where the switch does not apply (one-sided, no
  // diffuse or specular term).
  double switch_value(int k, const Vec3& gradient) const;
  bool has_switch(int k) const;

  double max() const { return max_; }
  double min() const { return min_; }
  double shininess() const { return shading_.shininess; }
  double diffuse() const { return shading_.diffuse; }
  double specular() const { return shading_.specular; }

 private:
  // The unit normal on a branch, and the gradient's norm (0 where it vanishes or underflows).
  Vec3 normal(const Vec3& gradient, double sign, double& norm) const;

  Shading shading_;
  double sign_ = 1;  // +1 for "gradient", -1 for "negative_gradient"
  Vec3 view_;        // toward the eye
  Vec3 light_;       // toward the light
  Vec3 half_;        // (l + v) / |l + v|
  double light_dot_view_ = 1;
  double max_ = 1, min_ = 1;
};

}  // namespace vrv
