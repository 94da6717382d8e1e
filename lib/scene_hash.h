#pragma once
// Content hashes that say whether two images were rendered from the same scene and camera.
//
// The hash covers everything that changes the integral: the box, the nominal dims, the field
// (its kind and parameters; a grid field's layout, interpolation, resolution and every node
// value), the transfer function (convention, unit length, every control point), the background
// and, with a camera, every camera parameter.  Doubles enter bit for bit (hexfloat), so a
// scene file that parses to the same numbers hashes the same, whatever its formatting.
// SHA-1 (Boost's) as 40 hex digits: an identity check, not a security one.
#include <string>

#include "lib/camera.h"
#include "lib/scene.h"

namespace vrv {

std::string scene_hash(const Scene& scene);
std::string scene_hash(const Scene& scene, const Camera& camera);
// The canonical text the camera part of the hash is taken over: one line, every number in its
// shortest round-trip form, e.g. "perspective eye [0, 0, -4] target [0, 0, 0] up [0, 1, 0] fov 40 ...".
std::string camera_description(const Camera& camera);

}  // namespace vrv
