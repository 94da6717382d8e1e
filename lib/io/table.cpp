#include "lib/io/table.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace vrv {
namespace {

constexpr const char* kDefaultFormat = "{:.6g}";
constexpr const char* kMissing = "n/a";

bool is_missing(const Table::Cell& cell) {
  const double* d = std::get_if<double>(&cell);
  return d != nullptr && !std::isfinite(*d);
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char ch : s) {
    if (ch == '"') out += '"';
    out += ch;
  }
  return out + '"';
}

// Display width of UTF-8 text: code points, so that "Lee–Newman" lines up.
std::size_t width(const std::string& s) {
  return static_cast<std::size_t>(
      std::count_if(s.begin(), s.end(), [](char ch) { return (static_cast<unsigned char>(ch) & 0xC0) != 0x80; }));
}

std::string pad(const std::string& s, std::size_t w, bool right) {
  const std::string fill(w - std::min(w, width(s)), ' ');
  return right ? fill + s : s + fill;
}

std::string markdown_escape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    if (ch == '|') out += "\\|";
    else if (ch == '\n' || ch == '\r') out += ' ';
    else out += ch;
  }
  return out;
}

std::string latex_escape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    switch (ch) {
      case '_': case '%': case '&': case '#': case '$': case '{': case '}':
        out += '\\';
        out += ch;
        break;
      case '~': out += "\\textasciitilde{}"; break;
      case '^': out += "\\textasciicircum{}"; break;
      case '\\': out += "\\textbackslash{}"; break;
      case '\n': case '\r': out += ' '; break;
      default: out += ch;
    }
  }
  return out;
}

// "1.5", "-2", "1.234e-05" in math mode ("$1.234 \times 10^{-5}$", a real minus sign); anything
// else a custom format produced ("12%", "1.5 s") is escaped text.
std::string latex_number(const std::string& s) {
  std::size_t i = 0;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  std::size_t digits = 0;
  while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i, ++digits;
  if (i < s.size() && s[i] == '.') {
    ++i;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i, ++digits;
  }
  if (digits == 0) return latex_escape(s);
  const std::string mantissa = s.substr(0, i);
  if (i == s.size()) return "$" + mantissa + "$";
  if (s[i] != 'e' && s[i] != 'E') return latex_escape(s);
  ++i;
  bool negative = false;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
  const std::size_t exponent_start = i;
  while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
  if (i != s.size() || i == exponent_start) return latex_escape(s);
  std::string exponent = s.substr(exponent_start);
  exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
  if (negative && exponent != "0") exponent = "-" + exponent;
  return fmt::format("${} \\times 10^{{{}}}$", mantissa, exponent);
}

}  // namespace

Table::Table(std::vector<std::string> columns) : columns_(std::move(columns)) {
  if (columns_.empty()) throw std::invalid_argument("table: no columns");
  std::set<std::string> seen;
  for (const auto& c : columns_) {
    if (c.empty()) throw std::invalid_argument("table: empty column name");
    if (!seen.insert(c).second) throw std::invalid_argument(fmt::format("table: duplicate column '{}'", c));
  }
  allow_missing_.assign(columns_.size(), false);
  formats_.assign(columns_.size(), kDefaultFormat);
}

std::size_t Table::index_of(const std::string& column) const {
  const auto it = std::find(columns_.begin(), columns_.end(), column);
  if (it == columns_.end()) throw std::invalid_argument(fmt::format("table: no column '{}'", column));
  return static_cast<std::size_t>(it - columns_.begin());
}

void Table::allow_missing(const std::string& column) { allow_missing_[index_of(column)] = true; }

void Table::set_format(const std::string& column, std::string format) {
  const std::size_t c = index_of(column);
  try {
    // A format must take one double and show it: two different values must print differently.
    if (fmt::format(fmt::runtime(format), 1.25) == fmt::format(fmt::runtime(format), 3.75))
      throw std::invalid_argument("it ignores the value");
  } catch (const std::exception& e) {
    throw std::invalid_argument(
        fmt::format("table: column '{}': bad number format \"{}\": {}", column, format, e.what()));
  }
  formats_[c] = std::move(format);
}

void Table::add_row(std::vector<Cell> row) {
  if (row.size() != columns_.size())
    throw std::invalid_argument(fmt::format("table: row has {} cells, the table has {} columns ({})", row.size(),
                                            columns_.size(), fmt::join(columns_, ", ")));
  for (std::size_t c = 0; c < row.size(); ++c) {
    if (is_missing(row[c]) && !allow_missing_[c])
      throw std::invalid_argument(fmt::format("table: column '{}': value is {} (row {}); declare allow_missing(\"{}\") "
                                              "if it may have no value",
                                              columns_[c], std::get<double>(row[c]), rows_.size() + 1, columns_[c]));
  }
  rows_.push_back(std::move(row));
}

bool Table::is_numeric_column(std::size_t c) const {
  return std::none_of(rows_.begin(), rows_.end(),
                      [c](const auto& row) { return std::holds_alternative<std::string>(row[c]); });
}

std::string Table::display(std::size_t c, const Cell& cell) const {
  if (is_missing(cell)) return kMissing;
  if (const auto* s = std::get_if<std::string>(&cell)) return *s;
  if (const auto* i = std::get_if<long>(&cell)) return fmt::format("{}", *i);
  return fmt::format(fmt::runtime(formats_[c]), std::get<double>(cell));
}

std::string Table::to_csv() const {
  std::string out;
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    if (c) out += ',';
    out += csv_field(columns_[c]);
  }
  out += '\n';
  for (const auto& row : rows_) {
    for (std::size_t c = 0; c < row.size(); ++c) {
      if (c) out += ',';
      const Cell& cell = row[c];
      if (is_missing(cell)) continue;
      if (const auto* s = std::get_if<std::string>(&cell)) out += csv_field(*s);
      else if (const auto* i = std::get_if<long>(&cell)) out += fmt::format("{}", *i);
      else out += fmt::format("{:.17g}", std::get<double>(cell));
    }
    out += '\n';
  }
  return out;
}

std::string Table::to_markdown() const {
  const std::size_t n = columns_.size();
  std::vector<std::vector<std::string>> text;
  text.reserve(rows_.size());
  std::vector<std::size_t> widths(n, 3);  // "---" is the shortest separator
  std::vector<bool> right(n);
  for (std::size_t c = 0; c < n; ++c) {
    right[c] = is_numeric_column(c);
    widths[c] = std::max(widths[c], width(markdown_escape(columns_[c])));
  }
  for (const auto& row : rows_) {
    auto& cells = text.emplace_back();
    for (std::size_t c = 0; c < n; ++c) {
      cells.push_back(markdown_escape(display(c, row[c])));
      widths[c] = std::max(widths[c], width(cells.back()));
    }
  }
  auto line = [&](auto&& cell_text) {
    std::string out = "|";
    for (std::size_t c = 0; c < n; ++c) {
      out += ' ';
      out += cell_text(c);
      out += " |";
    }
    return out + "\n";
  };
  std::string out = line([&](std::size_t c) { return pad(markdown_escape(columns_[c]), widths[c], false); });
  out += line([&](std::size_t c) {
    const std::string dashes(widths[c] - 1, '-');
    return right[c] ? dashes + ':' : std::string(1, ':') + dashes;
  });
  for (const auto& cells : text) out += line([&](std::size_t c) { return pad(cells[c], widths[c], right[c]); });
  return out;
}

std::string Table::to_latex(const LatexStyle& style) const {
  const std::size_t n = columns_.size();
  for (const auto& [column, header] : style.headers) index_of(column);  // unknown column: throws
  const bool wrapped = !style.caption.empty() || !style.label.empty();
  const std::string indent = wrapped ? "  " : "";
  std::string spec;
  for (std::size_t c = 0; c < n; ++c) spec += is_numeric_column(c) ? 'r' : 'l';

  std::string out;
  if (wrapped) {
    out += "\\begin{table}[htbp]\n  \\centering\n";
    if (!style.caption.empty()) out += "  \\caption{" + style.caption + "}\n";
    if (!style.label.empty()) out += "  \\label{" + style.label + "}\n";
  }
  out += indent + "\\begin{tabular}{" + spec + "}\n";
  out += indent + "  \\toprule\n" + indent + "  ";
  for (std::size_t c = 0; c < n; ++c) {
    const auto it = style.headers.find(columns_[c]);
    if (c) out += " & ";
    out += it != style.headers.end() ? it->second : latex_escape(columns_[c]);
  }
  out += " \\\\\n" + indent + "  \\midrule\n";
  for (const auto& row : rows_) {
    out += indent + "  ";
    for (std::size_t c = 0; c < n; ++c) {
      const Cell& cell = row[c];
      std::string text;
      if (is_missing(cell)) text = kMissing;
      else if (const auto* s = std::get_if<std::string>(&cell)) text = latex_escape(*s);
      else text = latex_number(display(c, cell));
      if (c) out += " & ";
      out += text;
    }
    out += " \\\\\n";
  }
  out += indent + "  \\bottomrule\n" + indent + "\\end{tabular}\n";
  if (wrapped) out += "\\end{table}\n";
  return out;
}

}  // namespace vrv
