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
  std::string line = fmt::format("{}: {}: {}", cut_for_message(source), cut_for_message(key),
                                 cut_for_message(reason, 4 * kMaxErrorPart));
  std::replace_if(line.begin(), line.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  return line;
}

std::string one_line(std::string s) {
  std::replace_if(s.begin(), s.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

void throw_file_error(const std::filesystem::path& file, std::string_view reason) {
  throw std::runtime_error(one_line(fmt::format("{}: {}", file.string(), reason)));
}

}  // namespace vrv
