#include "lib/rays_file.h"

#include <algorithm>
#include <cctype>
#include <set>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

namespace vrv {
namespace {

constexpr std::size_t kMaxQuoted = 40;  // longest key or token quoted in an error
// Deepest array or object nesting read: nlohmann's parser is iterative, but copying and printing
// a value recurse once per level, so a 70,000-deep id overflowed the stack (issue 22).
constexpr int kMaxDepth = 100;
constexpr std::size_t kMaxLineBytes = std::size_t{1} << 20;

std::string cut(const std::string& s) {
  return s.size() <= kMaxQuoted ? s : s.substr(0, kMaxQuoted) + "...";
}

bool word_char(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.';
}

// The token around byte `at` (1-based, as nlohmann reports it) of `text`, and its 1-based column.
std::pair<std::string, std::size_t> token_at(const std::string& text, std::size_t at) {
  std::size_t begin = std::min(at, text.size());
  if (begin > 0) --begin;
  while (begin > 0 && word_char(text[begin - 1])) --begin;
  std::size_t end = begin;
  while (end < text.size() && word_char(text[end])) ++end;
  return {text.substr(begin, end - begin), begin + 1};
}

bool is_non_finite_word(std::string t) {
  if (!t.empty() && (t[0] == '-' || t[0] == '+')) t.erase(0, 1);
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return std::tolower(c); });
  return t == "nan" || t == "inf" || t == "infinity";
}

// nlohmann's reason without its "[json.exception...] parse error at line 1, column C: " prefix.
std::string syntax_reason(const std::string& what) {
  const std::size_t dash = what.find(" - ");
  return dash == std::string::npos ? what : what.substr(dash + 3);
}

std::string parse_failure(const std::string& text, const nlohmann::json::exception& e) {
  const std::string what = e.what();
  if (const auto* p = dynamic_cast<const nlohmann::json::parse_error*>(&e)) {
    if (what.find("unexpected end of input") != std::string::npos)
      return "truncated: the line ends before its JSON object is complete";
    const auto [token, column] = token_at(text, p->byte);
    if (is_non_finite_word(token))
      return fmt::format("column {}: {} is not a JSON number (NaN and infinities cannot be given)",
                         column, cut(token));
    return fmt::format("column {}: invalid JSON: {}", p->byte, syntax_reason(what));
  }
  if (e.id == 406) {  // out_of_range: "number overflow parsing '1e999'"
    const std::size_t q = what.find('\'');
    const std::string number = q == std::string::npos ? std::string("a number")
                                                       : what.substr(q + 1, what.rfind('\'') - q - 1);
    return fmt::format("{} is beyond the range of a double", cut(number));
  }
  return syntax_reason(what);
}

Vec3 vector_field(const nlohmann::json& object, const char* key) {
  const auto it = object.find(key);
  if (it == object.end()) throw std::invalid_argument(fmt::format("{}: missing", key));
  if (!it->is_array() || it->size() != 3)
    throw std::invalid_argument(fmt::format("{}: expected an array of three numbers", key));
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    if (!(*it)[i].is_number())
      throw std::invalid_argument(fmt::format("{}[{}]: not a number", key, i));
    v[i] = (*it)[i].get<double>();
  }
  return v;
}

// Checks made while parsing, before the value exists: nesting deeper than kMaxDepth, and a key
// repeated in an object (nlohmann keeps the last value silently; the id passes through whole).
class LineChecks {
 public:
  bool operator()(int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using E = nlohmann::json::parse_event_t;
    if ((event == E::object_start || event == E::array_start) && depth >= kMaxDepth)
      throw std::invalid_argument(fmt::format("nested more than {} arrays or objects deep", kMaxDepth));
    if (event == E::object_start) keys_.emplace_back();
    if (event == E::object_end) keys_.pop_back();
    if (event == E::key && !keys_.back().insert(parsed.get<std::string>()).second)
      throw std::invalid_argument(fmt::format("key '{}' given twice", cut(parsed.get<std::string>())));
    return true;
  }

 private:
  std::vector<std::set<std::string>> keys_;  // of each object being read, outermost first
};

RayLine parse_line(const std::string& text) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text, LineChecks());
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument(parse_failure(text, e));
  }
  if (!j.is_object())
    throw std::invalid_argument(fmt::format(
        "expected a JSON object {{\"origin\": [x, y, z], \"direction\": [x, y, z]}}, got {}",
        j.type_name()));
  for (const auto& [key, value] : j.items())
    if (key != "origin" && key != "direction" && key != "id")
      throw std::invalid_argument(
          fmt::format("unknown key '{}' (origin, direction and id are read)", cut(key)));
  const Vec3 origin = vector_field(j, "origin");
  const Vec3 direction = vector_field(j, "direction");
  RayLine r;
  try {
    r.ray = make_ray(origin, direction);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(fmt::format("direction: {}", e.what()));
  }
  if (j.contains("id")) r.id = j["id"];
  return r;
}

// std::getline with a bound on the line: `--rays /dev/zero` (no line break, ever) read one endless
// line into memory.  False at the end of the input; std::invalid_argument for a longer line.
bool read_line(std::istream& in, std::string& text) {
  text.clear();
  std::streambuf* buffer = in.rdbuf();
  for (int c = buffer->sbumpc(); c != std::char_traits<char>::eof(); c = buffer->sbumpc()) {
    if (c == '\n') return true;
    if (text.size() == kMaxLineBytes)
      throw std::invalid_argument(fmt::format("longer than {} bytes (1 MiB), the longest line read", kMaxLineBytes));
    text.push_back(static_cast<char>(c));
  }
  in.setstate(std::ios::eofbit);
  return !text.empty();
}

}  // namespace

std::vector<RayLine> read_rays(std::istream& in, const std::string& name) {
  std::vector<RayLine> rays;
  std::string text;
  for (long number = 1;; ++number) {
    try {
      if (!read_line(in, text)) break;
      if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
      RayLine r = parse_line(text);
      r.line = number;
      rays.push_back(std::move(r));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(fmt::format("{}:{}: {}", name, number, e.what()));
    }
  }
  if (in.bad()) throw std::invalid_argument(fmt::format("{}: read error", name));
  return rays;
}

RayLineCount count_ray_lines(std::istream& in, long stop_after) {
  RayLineCount count;
  bool line_has_text = false;
  std::streambuf* buffer = in.rdbuf();
  for (int c = buffer->sbumpc(); c != std::char_traits<char>::eof(); c = buffer->sbumpc()) {
    ++count.bytes;
    if (c == '\n') {
      if (line_has_text && ++count.lines > stop_after) return count;
      line_has_text = false;
    } else if (c != ' ' && c != '\t' && c != '\r') {
      line_has_text = true;
    }
  }
  if (line_has_text) ++count.lines;  // a last line without its line break
  return count;
}

}  // namespace vrv
