/// A column-keyed convergence table: one row per resolution, any named error columns, their
/// convergence rates against a designated spacing column, rendered as Markdown or CSV.
///
/// The layer knows no numerics: what a column measures is its caller's business. The rates are
/// those of 004 II eq 7.3: the least-squares slope of ln e against ln h over all rows, and the
/// slope between each pair of successive rows, r_i = ln(e_i / e_{i-1}) / ln(h_i / h_{i-1}).
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace mfv {


class ConvergenceTable {
 public:
  /// Formats one value for a Markdown cell ("1.234e-03", "–" for NaN).
  using Format = std::function<std::string(double)>;

  /// `abscissa` names the spacing column (h) the rates are taken against; it is a column like
  /// any other (added with add_value) and is never rated itself.
  explicit ConvergenceTable(std::string abscissa = "h");

  /// Starts the row of a new resolution; rows stay in the order added (coarsest first, as
  /// verify runs them; the table neither sorts nor checks it).
  void add_row();
  /// Sets `column` in the current row. A new column is appended after the existing ones (the
  /// rows before it hold NaN there). Throws std::logic_error before the first add_row() and
  /// when the current row already holds a value for `column`.
  void add_value(const std::string& column, double value);
  /// add_row() followed by add_value for each pair, in order.
  void add_row(const std::vector<std::pair<std::string, double>>& values);

  std::size_t rows() const { return rows_; }
  /// Column names in insertion order, the abscissa included.
  const std::vector<std::string>& columns() const { return columns_; }
  bool has_column(const std::string& column) const;
  const std::string& abscissa() const { return abscissa_; }

  /// The value in `row` (0 = first added); NaN if that row never set the column. Throws
  /// std::invalid_argument for an unknown column (listing the known ones) and
  /// std::out_of_range for a row past the last.
  double value(std::size_t row, const std::string& column) const;
  /// Every row's value of `column` (NaN where unset). Throws std::invalid_argument for an
  /// unknown column.
  const std::vector<double>& values(const std::string& column) const;

  /// Least-squares rate of `column` against the abscissa (fitted_rate, reports/convergence.hpp); NaN if any row
  /// of `column` is NaN (set so, or never set), because a slope over the remaining rows would
  /// describe a different study (as verify/runner.cpp run_study decides). A zero or infinite
  /// error is only left out of the fit, as fitted_rate does. Throws
  /// std::invalid_argument for an unknown column, a missing abscissa column, and for the
  /// abscissa itself.
  double rate(const std::string& column) const;
  /// The rows − 1 successive rates of `column` (pairwise_rates). Throws as rate().
  std::vector<double> pairwise(const std::string& column) const;

  /// Shows `column`'s rates in the rendered tables: a column headed `rate_header` (default
  /// "<column> rate") right after it, with the pairwise rates per row and the least-squares
  /// rate in the last Markdown row. Calling it again replaces the header. Throws as rate().
  void evaluate_rates(const std::string& column, std::string rate_header = {});
  /// evaluate_rates for every column but the abscissa and those omitted, with default headers
  /// for columns not yet evaluated.
  void evaluate_all_rates();
  /// Keeps `column` (a count, a CPU time) out of evaluate_all_rates() and drops its rates if
  /// they were evaluated. Throws std::invalid_argument for an unknown column.
  void omit_from_rates(const std::string& column);
  /// The columns whose rates are shown, in column order.
  std::vector<std::string> rated_columns() const;

  /// How `column`'s values print in Markdown (default fmt_sci with 3 digits). Throws
  /// std::invalid_argument for an unknown column.
  void set_format(const std::string& column, Format format);
  /// How rates print in Markdown (default fmt_rate: 2 decimals, "–" for NaN).
  void set_rate_format(Format format);
  /// Text in `column`'s cell of the last Markdown row (a total CPU time, say); empty by
  /// default; in the first column it replaces the footer label. Throws
  /// std::invalid_argument for an unknown column.
  void set_footer(const std::string& column, std::string text);
  /// Label of the last Markdown row, in the first column's cell (default "least squares").
  void set_footer_label(std::string label) { footer_label_ = std::move(label); }

  /// The Markdown header: the columns in order, each rated one followed by its rate column.
  std::vector<std::string> header() const;
  /// The formatted cells of the resolution rows, matching header(); the first row's rate
  /// cells are "–" (no pair yet).
  std::vector<std::vector<std::string>> cells() const;
  /// The last row's cells: the footer label in the first column, least-squares rates in the
  /// rate columns, set_footer texts elsewhere.
  std::vector<std::string> footer() const;
  /// header(), cells() and footer() as an aligned Markdown table (reports/markdown.hpp),
  /// every column right-aligned; the footer row only if a column's rates are shown.
  std::string markdown() const;
  /// The same columns as CSV: one line of names (RFC 4180 quoting where needed), then one line
  /// per row with every value in shortest round-trip form ("nan" for NaN) and the pairwise rates
  /// (empty in the first row). No least-squares row: the file stays rectangular and numeric.
  std::string csv() const;
  /// header(), cells() and footer() as a LaTeX `booktabs` tabular (as deal.II's
  /// ConvergenceTable::write_tex): \toprule, the header, \midrule, the rows, \midrule and
  /// the footer row when markdown() shows it, \bottomrule; text escaped for LaTeX.
  std::string tex() const;

 private:
  std::size_t index(const std::string& column) const;  ///< throws for an unknown column
  std::size_t rated_index(const std::string& column) const;  ///< also refuses the abscissa
  std::string rate_header(std::size_t c) const;

  /// What the table keeps per column besides its name.
  struct Column {
    std::vector<double> values;  ///< one per row, NaN where unset
    std::size_t set_in = 0;      ///< 1 + the last row that set it (0: none)
    Format format;
    std::string footer;
    bool rated = false, omitted = false;
    std::string rate_header;  ///< empty: "<column> rate"
  };

  std::string abscissa_;
  std::size_t rows_ = 0;
  std::vector<std::string> columns_;  ///< names, in insertion order
  std::vector<Column> data_;          ///< matching columns_
  Format rate_format_;
  std::string footer_label_ = "least squares";
};

/// A table of text cells written three ways: Markdown for the report, CSV for machines and
/// LaTeX (booktabs) for a paper; a published table beside ours, in the paper's layout.
struct TextTable {
  std::vector<std::string> head;
  std::vector<char> align;                  ///< 'l', 'r' or 'c' per column; empty: first 'l', rest 'r'
  std::vector<std::vector<std::string>> rows;  ///< each as many cells as head (checked)

  std::string markdown() const;
  std::string csv() const;
  std::string tex() const;
};

}  // namespace mfv
