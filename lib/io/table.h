#pragma once
// A small tidy table for study results, written three ways from the same rows:
//  - CSV: a header row, one row per record, doubles at full precision ({:.17g}, so they read back
//    bit for bit), strings quoted per RFC 4180 when needed, "\n" line ends;
//  - Markdown: aligned pipes, numbers right-aligned and formatted per column;
//  - LaTeX: a booktabs tabular (\toprule, \midrule, \bottomrule), strings escaped, numbers in math
//    mode with exponents as \times 10^{...}, optionally in a table float with caption and label.
// A table never shows NaN: add_row rejects a NaN or infinite double, naming the column, unless the
// column was declared with allow_missing, in which case the value is missing (empty in CSV, "n/a" in
// Markdown and LaTeX).  To record a missing value on purpose, pass a quiet NaN in such a column.
#include <cstddef>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace vrv {

struct LatexStyle {
  // Raw LaTeX (not escaped, so math is allowed).  With a caption or a label the tabular is wrapped
  // in \begin{table}[htbp] \centering \caption{...} \label{...} ... \end{table}.
  std::string caption;
  std::string label;
  // Raw LaTeX headers replacing the (escaped) column names, e.g. {"dt", "$\\Delta t$"}.
  std::map<std::string, std::string> headers;
};

class Table {
 public:
  // A cell holds text, an integer or a real.  Integer literals become long; cast std::size_t
  // explicitly (static_cast<long>), the variant refuses narrowing conversions.
  using Cell = std::variant<std::string, long, double>;

  // Column names: non-empty and distinct, else std::invalid_argument.
  explicit Table(std::vector<std::string> columns);

  // Declares that non-finite doubles in `column` mean "no value" instead of an error.
  void allow_missing(const std::string& column);
  // Format (fmt syntax, e.g. "{:.4f}", "{:.3e}") for the doubles of `column` in Markdown and LaTeX;
  // default "{:.6g}".  Integers are always written whole; CSV always has full precision.
  // Throws std::invalid_argument for an unknown column or a format a double cannot take.
  void set_format(const std::string& column, std::string format);

  // Throws std::invalid_argument on a wrong cell count, or on a NaN/infinite double (naming the
  // column) in a column not declared with allow_missing.
  void add_row(std::vector<Cell> row);

  const std::vector<std::string>& columns() const { return columns_; }
  std::size_t size() const { return rows_.size(); }  // number of rows

  std::string to_csv() const;
  std::string to_markdown() const;
  std::string to_latex(const LatexStyle& style = {}) const;

 private:
  std::size_t index_of(const std::string& column) const;  // throws std::invalid_argument
  bool is_numeric_column(std::size_t c) const;            // no text cells: right-aligned
  std::string display(std::size_t c, const Cell& cell) const;  // Markdown/LaTeX text; "" if missing

  std::vector<std::string> columns_;
  std::vector<bool> allow_missing_;
  std::vector<std::string> formats_;
  std::vector<std::vector<Cell>> rows_;
};

}  // namespace vrv
