#include "reports/convergence_table.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "reports/convergence.hpp"
#include "reports/markdown.hpp"

namespace mfv {

ConvergenceTable::ConvergenceTable(std::string abscissa)
    : abscissa_(std::move(abscissa)), rate_format_([](double v) { return fmt_rate(v); }) {}

void ConvergenceTable::add_row() {
  ++rows_;
  // Until set, a cell is NaN: "not measured", never a number.
  for (auto& d : data_) d.values.push_back(NAN);
}

void ConvergenceTable::add_value(const std::string& column, double value) {
  if (rows_ == 0)
    throw std::logic_error(
        fmt::format("ConvergenceTable: add_row() before add_value(\"{}\", …)", column));
  const auto it = std::find(columns_.begin(), columns_.end(), column);
  const std::size_t c = it - columns_.begin();
  if (it == columns_.end()) {
    columns_.push_back(column);
    Column d;
    d.values.assign(rows_, NAN);
    d.format = [](double v) { return fmt_sci(v); };
    data_.push_back(std::move(d));
  } else if (data_[c].set_in == rows_) {
    throw std::logic_error(fmt::format(
        "ConvergenceTable: row {} already holds a value for \"{}\"", rows_ - 1, column));
  }
  data_[c].values[rows_ - 1] = value;
  data_[c].set_in = rows_;
}

void ConvergenceTable::add_row(const std::vector<std::pair<std::string, double>>& values) {
  add_row();
  for (const auto& [column, value] : values) add_value(column, value);
}

bool ConvergenceTable::has_column(const std::string& column) const {
  return std::find(columns_.begin(), columns_.end(), column) != columns_.end();
}

std::size_t ConvergenceTable::index(const std::string& column) const {
  const auto it = std::find(columns_.begin(), columns_.end(), column);
  if (it != columns_.end()) return it - columns_.begin();
  std::vector<std::string> quoted;
  for (const auto& k : columns_) quoted.push_back(fmt::format("\"{}\"", k));
  throw std::invalid_argument(fmt::format(
      "ConvergenceTable: no column \"{}\"; the columns are {}", column,
      quoted.empty() ? std::string("(none)") : fmt::format("{}", fmt::join(quoted, ", "))));
}

std::size_t ConvergenceTable::rated_index(const std::string& column) const {
  if (column == abscissa_)
    throw std::invalid_argument(fmt::format(
        "ConvergenceTable: \"{}\" is the abscissa the rates are taken against", column));
  const std::size_t c = index(column);
  if (!has_column(abscissa_))
    throw std::invalid_argument(fmt::format(
        "ConvergenceTable: no abscissa column \"{}\" to take the rates of \"{}\" against",
        abscissa_, column));
  return c;
}

const std::vector<double>& ConvergenceTable::values(const std::string& column) const {
  return data_[index(column)].values;
}

double ConvergenceTable::value(std::size_t row, const std::string& column) const {
  const std::size_t c = index(column);
  if (row >= rows_)
    throw std::out_of_range(
        fmt::format("ConvergenceTable: row {} of \"{}\", but the table has {} rows", row,
                    column, rows_));
  return data_[c].values[row];
}

double ConvergenceTable::rate(const std::string& column) const {
  const std::vector<double>& e = data_[rated_index(column)].values;
  if (std::any_of(e.begin(), e.end(), [](double v) { return std::isnan(v); })) return NAN;
  return fitted_rate(data_[index(abscissa_)].values, e);
}

std::vector<double> ConvergenceTable::pairwise(const std::string& column) const {
  return pairwise_rates(data_[index(abscissa_)].values, data_[rated_index(column)].values);
}

void ConvergenceTable::evaluate_rates(const std::string& column, std::string rate_header) {
  Column& d = data_[rated_index(column)];
  d.rated = true;
  d.omitted = false;
  d.rate_header = std::move(rate_header);
}

void ConvergenceTable::evaluate_all_rates() {
  for (std::size_t c = 0; c < columns_.size(); ++c)
    if (columns_[c] != abscissa_ && !data_[c].omitted)
      evaluate_rates(columns_[c], data_[c].rate_header);
}

void ConvergenceTable::omit_from_rates(const std::string& column) {
  Column& d = data_[index(column)];
  d.omitted = true;
  d.rated = false;
}

std::vector<std::string> ConvergenceTable::rated_columns() const {
  std::vector<std::string> out;
  for (std::size_t c = 0; c < columns_.size(); ++c)
    if (data_[c].rated) out.push_back(columns_[c]);
  return out;
}

void ConvergenceTable::set_format(const std::string& column, Format format) {
  data_[index(column)].format = std::move(format);
}

void ConvergenceTable::set_rate_format(Format format) { rate_format_ = std::move(format); }

void ConvergenceTable::set_footer(const std::string& column, std::string text) {
  data_[index(column)].footer = std::move(text);
}

std::string ConvergenceTable::rate_header(std::size_t c) const {
  return data_[c].rate_header.empty() ? columns_[c] + " rate" : data_[c].rate_header;
}

std::vector<std::string> ConvergenceTable::header() const {
  std::vector<std::string> out;
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    out.push_back(columns_[c]);
    if (data_[c].rated) out.push_back(rate_header(c));
  }
  return out;
}

std::vector<std::vector<std::string>> ConvergenceTable::cells() const {
  std::vector<std::vector<double>> pair(columns_.size());
  for (std::size_t c = 0; c < columns_.size(); ++c)
    if (data_[c].rated) pair[c] = pairwise(columns_[c]);
  std::vector<std::vector<std::string>> out;
  for (std::size_t r = 0; r < rows_; ++r) {
    std::vector<std::string> row;
    for (std::size_t c = 0; c < columns_.size(); ++c) {
      row.push_back(data_[c].format(data_[c].values[r]));
      if (data_[c].rated) row.push_back(r == 0 ? "–" : rate_format_(pair[c][r - 1]));
    }
    out.push_back(std::move(row));
  }
  return out;
}

std::vector<std::string> ConvergenceTable::footer() const {
  std::vector<std::string> out;
  for (std::size_t c = 0; c < columns_.size(); ++c) {
    out.push_back(c == 0 && data_[c].footer.empty() ? footer_label_ : data_[c].footer);
    if (data_[c].rated) out.push_back(rate_format_(rate(columns_[c])));
  }
  return out;
}

std::string ConvergenceTable::markdown() const {
  const std::vector<std::string> head = header();
  MarkdownTable t(head, std::vector<char>(head.size(), 'r'));
  for (auto& row : cells()) t.add_row(std::move(row));
  if (std::any_of(data_.begin(), data_.end(),
                  [](const Column& d) { return d.rated || !d.footer.empty(); }))
    t.add_row(footer());
  return t.str();
}

namespace {

/// Text as LaTeX typesets it: its special characters escaped, the en dash of an empty rate
/// cell as "--".
std::string tex_text(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char ch = s[i];
    if (s.compare(i, 3, "\xE2\x80\x93") == 0) {  // U+2013
      out += "--";
      i += 2;
      continue;
    }
    switch (ch) {
      case '&': case '%': case '$': case '#': case '_': case '{': case '}':
        out += '\\';
        out += ch;
        break;
      case '~': out += "\\textasciitilde{}"; break;
      case '^': out += "\\textasciicircum{}"; break;
      case '\\': out += "\\textbackslash{}"; break;
      default: out += ch;
    }
  }
  return out;
}

std::string tex_row(const std::vector<std::string>& cells) {
  std::vector<std::string> t;
  for (const auto& c : cells) t.push_back(tex_text(c));
  return fmt::format("{} \\\\\n", fmt::join(t, " & "));
}

}  // namespace

std::string ConvergenceTable::tex() const {
  const std::vector<std::string> head = header();
  std::string out = fmt::format("\\begin{{tabular}}{{{}}}\n\\toprule\n", std::string(head.size(), 'r'));
  out += tex_row(head) + "\\midrule\n";
  for (const auto& row : cells()) out += tex_row(row);
  // The footer row exactly when markdown() shows it.
  if (std::any_of(data_.begin(), data_.end(),
                  [](const Column& d) { return d.rated || !d.footer.empty(); }))
    out += "\\midrule\n" + tex_row(footer());
  return out + "\\bottomrule\n\\end{tabular}\n";
}

std::string ConvergenceTable::csv() const {
  std::vector<std::string> names;
  for (const auto& h : header()) names.push_back(csv_field(h));
  std::string out = fmt::format("{}\n", fmt::join(names, ","));
  std::vector<std::vector<double>> pair(columns_.size());
  for (std::size_t c = 0; c < columns_.size(); ++c)
    if (data_[c].rated) pair[c] = pairwise(columns_[c]);
  for (std::size_t r = 0; r < rows_; ++r) {
    std::vector<std::string> row;
    for (std::size_t c = 0; c < columns_.size(); ++c) {
      row.push_back(fmt::format("{}", data_[c].values[r]));
      if (data_[c].rated) row.push_back(r == 0 ? "" : fmt::format("{}", pair[c][r - 1]));
    }
    out += fmt::format("{}\n", fmt::join(row, ","));
  }
  return out;
}

namespace {

/// The table's rows, each checked against the header: a short row is a caller's bug that would
/// shift every cell of a paper's table.
void check_rows(const TextTable& t) {
  for (std::size_t r = 0; r < t.rows.size(); ++r)
    if (t.rows[r].size() != t.head.size())
      throw std::invalid_argument(fmt::format("TextTable: row {} has {} cells for {} columns", r,
                                              t.rows[r].size(), t.head.size()));
}

std::vector<char> alignment(const TextTable& t) {
  if (!t.align.empty()) return t.align;
  std::vector<char> a(t.head.size(), 'r');
  if (!a.empty()) a[0] = 'l';
  return a;
}

}  // namespace

std::string TextTable::markdown() const {
  check_rows(*this);
  MarkdownTable t(head, alignment(*this));
  for (const auto& r : rows) t.add_row(r);
  return t.str();
}

std::string TextTable::csv() const {
  check_rows(*this);
  auto line = [](const std::vector<std::string>& cells) {
    std::vector<std::string> f;
    for (const auto& c : cells) f.push_back(csv_field(c));
    return fmt::format("{}\n", fmt::join(f, ","));
  };
  std::string out = line(head);
  for (const auto& r : rows) out += line(r);
  return out;
}

std::string TextTable::tex() const {
  check_rows(*this);
  std::string spec;
  for (char a : alignment(*this)) spec += a;
  std::string out = fmt::format("\\begin{{tabular}}{{{}}}\n\\toprule\n", spec);
  out += tex_row(head) + "\\midrule\n";
  for (const auto& r : rows) out += tex_row(r);
  return out + "\\bottomrule\n\\end{tabular}\n";
}

}  // namespace mfv
