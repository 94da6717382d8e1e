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

std::mutex audit_mutex;
ReferenceAuditCounts audit;

// Not a checkpoint's name (those end in .txt, checkpoint.cpp).
constexpr std::string_view kSnapshotFile = "reference_audit.snapshot";

// Taken while a snapshot is read from the counters and written: snapshots reach the file in the
// order they were taken, so the file never goes back to fewer truths than a stored checkpoint's.
std::mutex snapshot_mutex;

void store_snapshot(const fs::path& dir) {
  const std::lock_guard lock(snapshot_mutex);
  write_file_atomically(dir / kSnapshotFile, reference_audit_snapshot(reference_audit_counts()));
}

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

void record_reference(const ReferenceResult& r) {
  if (!counts_on_this_rank()) return;  // a truth every MPI rank computes counts once, on rank 0
  const std::lock_guard lock(audit_mutex);
  ++audit.rays;
  if (!r.tolerance_met) ++audit.missed;
  if (std::isnan(r.error_estimate) || r.error_estimate > audit.largest_estimate)
    audit.largest_estimate = r.error_estimate;
}

ReferenceResult audited_reference(const Scene& scene, const Ray& ray, const ReferenceOptions& options) {
  ReferenceResult r = integrate_reference(scene, ray, options);
  record_reference(r);
  return r;
}

void reset_reference_audit() {
  const std::lock_guard lock(audit_mutex);
  audit = {};
}

ReferenceAuditCounts reference_audit_counts() {
  const std::lock_guard lock(audit_mutex);
  return audit;
}

ReferenceAuditCounts reference_audit_counts_over_ranks() {
  const ReferenceAuditCounts mine = reference_audit_counts();
  return {sum_over_ranks(mine.rays), sum_over_ranks(mine.missed), max_over_ranks(mine.largest_estimate)};
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

void start_reference_audit(Checkpoints& checkpoints, bool resume) {
  reset_reference_audit();
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
    const std::lock_guard lock(audit_mutex);
    audit = *counts;
  } else if (resume && checkpoints.found_stored()) {
    throw StudyResumeError(fmt::format("{}: --resume: the checkpoints have no reference audit snapshot "
                                       "(an older vrv's), so their misses are unknown; run without --resume",
                                       checkpoints.dir().string()));
  }
  checkpoints.before_store(store_snapshot);
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
