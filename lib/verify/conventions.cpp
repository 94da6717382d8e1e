#include "lib/verify/conventions.h"

#include <algorithm>
#include <cmath>

namespace vrv {

bool consistent_with_expected_order(const Fault& fault, const VerifyOptions& opt) {
  return opt.expected_order && std::isfinite(fault.implied_order) &&
         fault.implied_order >= *opt.expected_order - opt.order_tolerance;
}

void separate_conventions(VerifyReport& rep, const VerifyOptions& opt) {
  rep.expected_order = opt.expected_order;
  const auto convention = [&](const Fault& f) { return consistent_with_expected_order(f, opt); };
  std::copy_if(rep.faults.begin(), rep.faults.end(), std::back_inserter(rep.conventions), convention);
  std::erase_if(rep.faults, convention);
}

}  // namespace vrv
