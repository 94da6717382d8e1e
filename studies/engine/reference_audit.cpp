#include "studies/engine/reference_audit.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <sstream>

#include <fmt/format.h>

#include "lib/io/atomic_file.h"
#include "lib/util/ranks.h"

namespace vrv {
namespace fs = std::filesystem;
namespace {

// Not a checkpoint's name (those end in .txt, checkpoint.cpp).
constexpr std::string_view kSnapshotFile = "reference_audit.snapshot";

// A whole word as a long (>= 0) or a double; nullopt otherwise.
std::optional<long> count_of(const std::string& word) {
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(word.c_str(), &end, 10);
  if (word.empty() || *end != '\0' || errno != 0 || v < 0) return std::nullopt;
  return v;
}

std::optional<double> number_of(const std::string& word) {
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  if (word.empty() || *end != '\0') return std::nullopt;
  return v;
}

}  // namespace

void ReferenceAuditCounts::add(bool tolerance_met, double error_estimate) {
  add(ReferenceAuditCounts{1, tolerance_met ? 0 : 1, error_estimate});
}

void ReferenceAuditCounts::add(const ReferenceAuditCounts& more) {
  rays += more.rays;
  missed += more.missed;
  if (std::isnan(more.largest_estimate) || more.largest_estimate > largest_estimate)
    largest_estimate = more.largest_estimate;
}

void ReferenceAudit::record(bool tolerance_met, double error_estimate) {
  record(ReferenceAuditCounts{1, tolerance_met ? 0 : 1, error_estimate});
}

void ReferenceAudit::record(const ReferenceAuditCounts& counts) {
  if (!counts_on_this_rank()) return;  // a truth every MPI rank computes counts once, on rank 0
  const std::lock_guard lock(mutex_);
  counts_.add(counts);
}

ReferenceAuditCounts ReferenceAudit::counts() const {
  const std::lock_guard lock(mutex_);
  return counts_;
}

ReferenceAuditCounts ReferenceAudit::counts_over_ranks() const {
  const ReferenceAuditCounts mine = counts();
  return {sum_over_ranks(mine.rays), sum_over_ranks(mine.missed), max_over_ranks(mine.largest_estimate)};
}

void ReferenceAudit::store_snapshot(const fs::path& dir) {
  const std::lock_guard lock(snapshot_mutex_);
  write_file_atomically(dir / kSnapshotFile, reference_audit_snapshot(counts()));
}

ReferenceResult audited_reference(ReferenceAudit& audit, const Scene& scene, const Ray& ray,
                                  const ReferenceOptions& options) {
  ReferenceResult r = integrate_reference(scene, ray, options);
  audit.record(r);
  return r;
}

std::string reference_audit_snapshot(const ReferenceAuditCounts& counts) {
  return fmt::format("rays {}\nmissed {}\nlargest_estimate {:a}\nend\n", counts.rays, counts.missed,
                     counts.largest_estimate);
}

std::optional<ReferenceAuditCounts> parse_reference_audit_snapshot(std::string_view text) {
  std::istringstream in{std::string(text)};
  std::string k1, rays, k2, missed, k3, estimate, end, extra;
  if (!(in >> k1 >> rays >> k2 >> missed >> k3 >> estimate >> end) || (in >> extra)) return std::nullopt;
  if (k1 != "rays" || k2 != "missed" || k3 != "largest_estimate" || end != "end") return std::nullopt;
  const auto r = count_of(rays), m = count_of(missed);
  const auto e = number_of(estimate);
  if (!r || !m || !e || *m > *r) return std::nullopt;
  return ReferenceAuditCounts{*r, *m, *e};
}

void ReferenceAudit::start(Checkpoints& checkpoints, bool resume) {
  ReferenceAuditCounts start;
  const fs::path file = checkpoints.dir() / kSnapshotFile;
  std::error_code ec;
  if (resume && fs::exists(file, ec)) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    const auto counts = parse_reference_audit_snapshot(text.str());
    if (!counts)
      throw StudyResumeError(fmt::format("{}: --resume: not a reference audit snapshot; run without --resume",
                                         file.string()));
    start = *counts;
  } else if (resume && checkpoints.found_stored()) {
    throw StudyResumeError(fmt::format("{}: --resume: the checkpoints have no reference audit snapshot "
                                       "(an older vrv's), so their misses are unknown; run without --resume",
                                       checkpoints.dir().string()));
  }
  {
    const std::lock_guard lock(mutex_);
    counts_ = start;
  }
  checkpoints.before_store([this](const fs::path& dir) { store_snapshot(dir); });
}

StudyCheck reference_audit_check(const ReferenceAuditCounts& counts) {
  StudyCheck c;
  c.name = "reference_within_tolerance";
  c.value = static_cast<double>(counts.missed);
  c.bound = 0;
  c.pass = counts.missed == 0;
  c.kind = CheckKind::derived;
  // The detail is the same for a resumed run (--resume computes only part of the truths, and its
  // tables must match an uninterrupted run's byte for byte): the counts go to meta.json.
  c.detail = "reference truths that missed their tolerance (work cap, estimate above tol or not finite)";
  return c;
}

}  // namespace vrv
