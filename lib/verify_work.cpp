#include "lib/verify_work.h"

#include <stdexcept>

#include <fmt/format.h>

#include "lib/option_error.h"
#include "lib/work_estimate.h"

namespace vrv {

void check_verification_work(const Scene& scene, const VerifyOptions& options, int width, int height,
                             const std::vector<double>& steps, double renders, double max_work,
                             const std::string& who) {
  if (!(max_work > 0)) throw OptionError(Option::max_work, fmt::format("must be positive, got {}", max_work));
  const VerificationWork parts = verification_work(scene, options, width, height, steps);
  const double work = parts.total() + renders;
  if (work <= max_work) return;
  throw std::invalid_argument(fmt::format(
      "{}: about {:.3g} field evaluations (the reference on {} x {} pixels at --tol {:g}: {:.3g}{}{}), above the work "
      "limit of {:.3g}; use smaller images, a looser tolerance, {}or allow it with --max-work {}",
      who, work, width, height, options.reference_tol, parts.reference,
      parts.diagnosis > 0 ? fmt::format("; the diagnosis: {:.3g}", parts.diagnosis) : std::string(),
      renders > 0 ? fmt::format("; the renders: {:.3g}", renders) : std::string(), max_work,
      parts.diagnosis > 0 ? "--no-diagnosis, " : "", work_limit_allowing(work)));
}

}  // namespace vrv
