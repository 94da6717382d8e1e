#pragma once
// A switch of the reference's emission weight (lib/shading_weight.h) along a ray.

namespace vrv {

// A switch of the weight at t: known to within dt (where the field's proxy of the switch function
// crosses 0); `jump` where S is discontinuous there (a two-sided normal's flip), so that a
// misplaced switch costs the jump over dt, not a kink's second-order change.
struct WeightSwitch {
  double t = 0;
  double dt = 0;
  bool jump = false;
  // False for a stretch [t, t + dt] where a jump's function comes within its proxy's error of 0
  // without a located crossing: the function may cross there (twice) or not; charged, not cut.
  bool cut = true;
};

}  // namespace vrv
