#pragma once
// The one line every reader reports a bad input with: "<source>: <key>: <reason>".  Line breaks
// become spaces, and each part is cut to a bound (a 10 MB table name in a file must not make a
// 10 MB message): a cut part keeps its head and says how long it was.
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace vrv {

inline constexpr std::size_t kMaxErrorPart = 200;  // bytes kept of a source, key or reason

// `s` if it has at most `max` bytes, else its head (whole UTF-8 characters) and "... (N bytes)".
std::string cut_for_message(std::string_view s, std::size_t max = kMaxErrorPart);

std::string error_line(std::string_view source, std::string_view key, std::string_view reason);

// `s` with its line breaks and tabs as spaces, no trailing spaces and other control bytes as \xNN:
// a message that stays one line and cannot act on the terminal that shows it.
std::string one_line(std::string s);

// "<file>: <reason>" as one line, thrown as std::runtime_error (the image readers and writers).
[[noreturn]] void throw_file_error(const std::filesystem::path& file, std::string_view reason);

}  // namespace vrv
