#pragma once
// Cameras: which ray goes through which pixel.
//
// Image convention: pixel (x, y) with x to the right and y downwards, row 0 at the top, and
// rays through pixel centres.  The camera frame is right-handed: forward = target - eye,
// right = forward x up, and the true up = right x forward, so a camera at -z looking at the
// origin with up = +y sees +y at the top of the image and +x on the left.
//
// The fan is the 2D set-up of the sampling papers (e.g. eye at (-9, 0), 120 rays over 30
// degrees with equal angular spacing): `width` rays from the eye in the plane z = eye.z,
// ray i at the angle
//   angle - fov/2 + fov * (i + 0.5) / width      (degrees, 0 = +x, 90 = +y),
// i.e. the fov is cut into `width` equal wedges and each ray runs down the middle of its
// wedge, exactly as pixel centres do; the spacing between neighbouring rays is fov / width,
// and the outermost rays lie half a spacing inside the fan's edges.
#include <stdexcept>
#include <string>
#include <string_view>

#include "lib/geometry.h"
#include "lib/util/enum_names.h"

namespace vrv {

enum class Projection { orthographic, perspective, fan };
// Their names in scene files ([camera] projection) and in to_string.
inline constexpr NameTable<Projection, 3> kProjectionNames{{{Projection::orthographic, "orthographic"},
                                                            {Projection::perspective, "perspective"},
                                                            {Projection::fan, "fan"}}};

struct Camera {
  Projection projection = Projection::perspective;
  Vec3 eye{0, 0, -4}, target{0, 0, 0}, up{0, 1, 0};  // target and up: not used by the fan
  double fov_degrees = 40;  // perspective: vertical field of view; fan: total angle of the fan
  double extent = 2.5;      // orthographic: height of the view in world units
  int width = 256, height = 256;  // fan: width = number of rays, height = 1
  double angle_degrees = 0;  // fan: direction of the central ray in the x-y plane (0 = +x)

  // The ray through the centre of pixel (x, y); unit direction.  For the fan, ray x of
  // `width` (y must be 0).  Expects a validated camera.
  Ray ray(int x, int y) const;
  // The ray through the image point (px, py) in pixel units, pixel (x, y) covering [x, x + 1) x
  // [y, y + 1): ray(x, y) is ray_at(x + 0.5, y + 0.5), bit for bit.  For renderers whose rays miss
  // the pixel centres (lib/verify/fault_fit.h).  Fan: py is not used.
  Ray ray_at(double px, double py) const;
};

inline constexpr int kMaxImageSide = 16384;

// What validate() throws: what() is "camera.<field>: <reason>"; field() and reason() apart,
// so that a scene file can report it against its own key.
class CameraError : public std::invalid_argument {
 public:
  CameraError(std::string field, std::string reason);
  const std::string& field() const { return field_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string field_, reason_;
};

// Throws CameraError (a std::invalid_argument naming the field) unless: every number is finite;
// 1 <= width, height <= kMaxImageSide; the fan has height 1; perspective and orthographic
// cameras have eye != target and up not parallel to the view direction; a perspective
// fov is in (0, 180); a fan's fov is in (0, 360]; an orthographic extent is > 0.
void validate(const Camera& camera);

// The camera `vrv render` uses when a scene has none: perspective, 40 degree vertical fov,
// 256 x 256, looking at the box centre along +z from 2.5 box diagonals away (eye at
// centre - (0, 0, 2.5 |max - min|)), up = +y.
Camera default_camera(const Box& box);

std::string_view to_string(Projection p);

}  // namespace vrv
