#include "lib/io/error_line.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

namespace vrv {

std::string cut_for_message(std::string_view s, std::size_t max) {
  if (s.size() <= max) return std::string(s);
  std::size_t keep = max;
  while (keep > 0 && (static_cast<unsigned char>(s[keep]) & 0xC0) == 0x80) --keep;  // continuation
  return fmt::format("{}... ({} bytes)", s.substr(0, keep), s.size());
}

std::string error_line(std::string_view source, std::string_view key, std::string_view reason) {
  // Reasons quote values and list allowed keys: they get more room than names.
  return one_line(fmt::format("{}: {}: {}", cut_for_message(source), cut_for_message(key),
                              cut_for_message(reason, 4 * kMaxErrorPart)));
}

std::string one_line(std::string s) {
  std::replace_if(s.begin(), s.end(), [](char c) { return c == '\n' || c == '\r' || c == '\t'; }, ' ');
  while (!s.empty() && s.back() == ' ') s.pop_back();
  // Other control bytes (a file's ESC sequences quoted in a reason) would act on the terminal
  // that shows the message: they are written as \xNN.
  const auto control = [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; };
  if (std::none_of(s.begin(), s.end(), control)) return s;
  std::string out;
  for (char c : s) out += control(c) ? fmt::format("\\x{:02x}", static_cast<unsigned char>(c)) : std::string(1, c);
  return out;
}

void throw_file_error(const std::filesystem::path& file, std::string_view reason) {
  throw std::runtime_error(one_line(fmt::format("{}: {}", file.string(), reason)));
}

}  // namespace vrv
