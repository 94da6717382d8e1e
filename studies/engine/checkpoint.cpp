#include "studies/engine/checkpoint.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <sstream>

#include <fmt/format.h>

#include "lib/io/atomic_file.h"
#include "lib/util/checksum.h"
#include "lib/util/parallel.h"
#include "lib/util/ranks.h"

namespace vrv {
namespace fs = std::filesystem;
namespace {

constexpr std::string_view kIdentityFile = "identity.txt";

std::string read_all(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string fingerprint(std::string_view identity) {
  return fmt::format("{} {}\n", crc64_hex(identity), identity.size());
}

// The last line of a checkpoint, "end COUNT CRC": the count of values and the CRC-64 of the key
// and the value lines before it, so a file cut, edited or copied to another key is never used.
std::string end_line(const std::string& key, std::size_t count, std::string_view values_text) {
  return fmt::format("end {} {}\n", count, crc64_hex(key + '\n' + std::string(values_text)));
}

}  // namespace

Checkpoints::Checkpoints(const fs::path& dir, std::string_view identity, bool resume) : dir_(dir) {
  std::error_code ec;
  const std::string mine = fingerprint(identity);
  if (resume && fs::exists(dir_ / kIdentityFile, ec) && read_all(dir_ / kIdentityFile) != mine)
    throw StudyResumeError(fmt::format("{}: --resume: the study file or --quick differs from the "
                                       "interrupted run's; run without --resume",
                                       dir_.parent_path().string()));
  if (resume)
    for (const auto& e : fs::directory_iterator(dir_, ec))
      if (e.path().extension() == ".txt" && e.path().filename() != kIdentityFile) found_stored_ = true;
  ec.clear();
  fs::create_directories(dir_, ec);
  if (ec) throw std::runtime_error(fmt::format("{}: cannot create: {}", dir_.string(), ec.message()));
  write_file_atomically(dir_ / kIdentityFile, mine);
  // Test hook (tests/studies/engine/interrupt_test.sh): "N" or "N:SIGNAL" sends SIGKILL (or the
  // signal) to this process once N configurations are computed, a deterministic "midway".
  if (const char* hook = std::getenv("VRV_TEST_KILL_AFTER_CHECKPOINTS")) {
    char* end = nullptr;
    kill_after_ = std::strtol(hook, &end, 10);
    if (*end == ':') kill_signal_ = static_cast<int>(std::strtol(end + 1, nullptr, 10));
  }
}

fs::path Checkpoints::file(const std::string& key) const { return dir_ / (key + ".txt"); }

// Stored files are written whole (atomically), so one that fails its end line was changed or
// damaged: it is refused, never used.
std::optional<std::vector<double>> Checkpoints::find(const std::string& key) const {
  std::ifstream in(file(key));
  if (!in) return std::nullopt;
  const auto refuse = [&](const std::string& why) {
    return StudyResumeError(fmt::format("{}: {}: the checkpoint was changed or damaged; run without --resume",
                                        file(key).string(), why));
  };
  std::vector<double> values;
  std::string line, text;
  while (std::getline(in, line) && !line.starts_with("end")) {
    char* end = nullptr;
    values.push_back(std::strtod(line.c_str(), &end));
    if (line.empty() || *end != '\0') throw refuse(fmt::format("line {} is not a number", values.size()));
    text += line + '\n';
  }
  if (line + '\n' != end_line(key, values.size(), text) || std::getline(in, line))
    throw refuse(fmt::format("{} values and their checksum do not match its end line", values.size()));
  return values;
}

void Checkpoints::store(const std::string& key, const std::vector<double>& values) {
  std::string text;
  for (const double v : values) text += fmt::format("{:a}\n", v);  // exact; nan, inf as words
  text += end_line(key, values.size(), text);
  if (before_store_) before_store_(dir_);
  write_file_atomically(file(key), text);
}

void Checkpoints::note_non_finite(const std::string& key, const std::vector<double>& values) {
  const auto bad = std::find_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); });
  if (bad == values.end()) return;
  const std::lock_guard lock(reused_non_finite_mutex_);
  if (reused_non_finite_.empty())
    reused_non_finite_ = fmt::format("{}: value {} is {}", file(key).string(), bad - values.begin() + 1, *bad);
}

std::string Checkpoints::reused_non_finite() const {
  const std::lock_guard lock(reused_non_finite_mutex_);
  return reused_non_finite_;
}

std::vector<double> Checkpoints::get(const std::string& unprefixed, const std::function<std::vector<double>()>& compute,
                                     std::optional<std::size_t> expected) {
  const std::string key = key_prefix_ + unprefixed;
  for (const char c : key)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'))
      throw std::logic_error("checkpoint key '" + key + "' has a character other than [A-Za-z0-9_.-]");
  if (auto stored = find(key)) {
    if (expected && stored->size() != *expected)
      throw StudyResumeError(fmt::format("{}: {} values, expected {}: the checkpoint belongs to another "
                                         "computation; run without --resume",
                                         file(key).string(), stored->size(), *expected));
    ++reused_;
    note_non_finite(key, *stored);
    return *stored;
  }
  std::vector<double> values = compute();
  store(key, values);
  if (++computed_ == kill_after_ && kill_after_ > 0) ::kill(::getpid(), kill_signal_);
  return values;
}

std::vector<double> checkpointed(Checkpoints* checkpoints, const std::string& key,
                                 const std::function<std::vector<double>()>& compute,
                                 std::optional<std::size_t> expected) {
  return checkpoints ? checkpoints->get(key, compute, expected) : compute();
}

std::vector<double> checkpointed(const StudyCheckpoint& checkpoint, const std::string& key, std::size_t expected,
                                 const std::function<std::vector<double>()>& compute) {
  return checkpoint ? checkpoint(key, expected, compute) : compute();
}

std::vector<double> checkpointed_items(Checkpoints* checkpoints, const std::string& key, long n, long block,
                                       std::size_t width, const std::function<void(long, std::span<double>)>& item,
                                       const std::function<void(long)>& advance) {
  block = std::max(block, 1L);
  std::vector<double> out(static_cast<std::size_t>(n) * width);
  if (!checkpoints && width > 0 && pixels_shared_over_ranks()) {
    // Over MPI ranks (which keep no checkpoints): the blocks dealt, the items exchanged.
    long own = 0;
    deal_and_share(reinterpret_cast<std::byte*>(out.data()), n, width * sizeof(double), block, [&](long fb, long lb) {
      const long first = fb * block, last = std::min(n, lb * block);
      own += last - first;
      parallel_for_index(last - first, [&](long i) {
        item(first + i, std::span<double>(out).subspan(static_cast<std::size_t>(first + i) * width, width));
        if (advance) advance(1);
      });
    });
    if (advance && n > own) advance(n - own);
    return out;
  }
  const long blocks = (n + block - 1) / block;
  parallel_for_index(blocks, [&](long b) {
    const long first = b * block, count = std::min(block, n - first);
    bool computed = false;
    const std::size_t expected = static_cast<std::size_t>(count) * width;
    const std::vector<double> v = checkpointed(checkpoints, fmt::format("{}.{}", key, first), [&] {
      std::vector<double> values(static_cast<std::size_t>(count) * width);
      parallel_for_index(count, [&](long i) {
        item(first + i, std::span<double>(values).subspan(static_cast<std::size_t>(i) * width, width));
        if (advance) advance(1);
      });
      computed = true;
      return values;
    }, expected);
    std::copy(v.begin(), v.end(), out.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(first) * width));
    if (!computed && advance) advance(count);
  });
  return out;
}

BlockStore checkpoint_blocks(Checkpoints* checkpoints, const std::string& key) {
  if (!checkpoints) return {};
  return [checkpoints, key](long first, std::span<double> records, const std::function<void()>& compute) {
    const std::vector<double> v = checkpoints->get(fmt::format("{}.{}", key, first), [&] {
      compute();
      return std::vector<double>(records.begin(), records.end());
    }, records.size());
    std::copy(v.begin(), v.end(), records.begin());
  };
}

StudyCheckpoint checkpoint_function(Checkpoints* checkpoints) {
  if (!checkpoints) return {};
  return [checkpoints](const std::string& key, std::size_t expected,
                       const std::function<std::vector<double>()>& compute) {
    return checkpoints->get(key, compute, expected);
  };
}

}  // namespace vrv
