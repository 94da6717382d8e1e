#pragma once
// The orthonormal frame a perspective or orthographic camera builds its rays from (defined in
// lib/camera.cpp, which uses it for Camera::ray): forward = target - eye, right = forward x up,
// up = right x forward, each normalised.
#include "lib/camera.h"

namespace vrv {

struct CameraFrame {
  Vec3 forward, right, up;
};
CameraFrame camera_frame(const Camera& camera);

}  // namespace vrv
