#include "reports/markdown.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <stdexcept>

#include <fmt/format.h>

namespace mfv {

namespace {

constexpr const char* kNoValue = "–";  // en dash: reads as "no value", unlike "nan"

/// Columns a cell takes in a monospaced editor: UTF-8 code points, not bytes.
std::size_t display_width(const std::string& s) {
  return static_cast<std::size_t>(
      std::count_if(s.begin(), s.end(), [](char c) { return (c & 0xC0) != 0x80; }));
}

std::string escape_cell(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    if (c == '|') {
      out += "\\|";
    } else if (c == '\n') {
      out += ' ';  // a line break would end the table row
    } else if (c != '\r') {
      out += c;
    }
  }
  return out;
}

std::string pad(const std::string& s, std::size_t width, char align) {
  const std::size_t fill = width - std::min(width, display_width(s));
  switch (align) {
    case 'r':
      return std::string(fill, ' ') + s;
    case 'c':
      return std::string(fill / 2, ' ') + s + std::string(fill - fill / 2, ' ');
    default:
      return s + std::string(fill, ' ');
  }
}

std::string delimiter(std::size_t width, char align) {
  switch (align) {
    case 'r':
      return std::string(width - 1, '-') + ':';
    case 'c':
      return ':' + std::string(width - 2, '-') + ':';
    default:
      return ':' + std::string(width - 1, '-');
  }
}

void append_line(std::string& out, const std::vector<std::string>& cells) {
  out += '|';
  for (const auto& c : cells) out += ' ' + c + " |";
  out += '\n';
}

}  // namespace

MarkdownTable::MarkdownTable(std::vector<std::string> header, std::vector<char> align)
    : align_(std::move(align)) {
  if (header.empty()) throw std::invalid_argument("MarkdownTable: the header has no columns");
  if (align_.empty()) align_.assign(header.size(), 'l');
  if (align_.size() != header.size())
    throw std::invalid_argument(fmt::format("MarkdownTable: {} alignments for {} columns",
                                            align_.size(), header.size()));
  for (char a : align_)
    if (a != 'l' && a != 'r' && a != 'c')
      throw std::invalid_argument(
          fmt::format("MarkdownTable: alignment '{}' is not one of 'l', 'r', 'c'", a));
  header_.reserve(header.size());
  for (const auto& h : header) header_.push_back(escape_cell(h));
}

void MarkdownTable::add_row(std::vector<std::string> cells) {
  if (cells.size() != header_.size())
    throw std::invalid_argument(fmt::format("MarkdownTable: a row has {} cells, the header {}",
                                            cells.size(), header_.size()));
  for (auto& c : cells) c = escape_cell(c);
  rows_.push_back(std::move(cells));
}

std::string MarkdownTable::str() const {
  const std::size_t ncol = header_.size();
  // At least 3 so that the delimiter row keeps a dash between the alignment colons.
  std::vector<std::size_t> width(ncol, 3);
  for (std::size_t j = 0; j < ncol; ++j) {
    width[j] = std::max(width[j], display_width(header_[j]));
    for (const auto& row : rows_) width[j] = std::max(width[j], display_width(row[j]));
  }
  std::string out;
  std::vector<std::string> line(ncol);
  for (std::size_t j = 0; j < ncol; ++j) line[j] = pad(header_[j], width[j], align_[j]);
  append_line(out, line);
  for (std::size_t j = 0; j < ncol; ++j) line[j] = delimiter(width[j], align_[j]);
  append_line(out, line);
  for (const auto& row : rows_) {
    for (std::size_t j = 0; j < ncol; ++j) line[j] = pad(row[j], width[j], align_[j]);
    append_line(out, line);
  }
  return out;
}

std::string fmt_sci(double v, int digits) {
  if (std::isnan(v)) return kNoValue;
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{:.{}e}", v, std::max(digits, 0));
}

std::string fmt_fix(double v, int decimals) {
  if (std::isnan(v)) return kNoValue;
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{:.{}f}", v, std::max(decimals, 0));
}

std::string fmt_rate(double v) { return fmt_fix(v, 2); }

std::string fmt_rates(const std::vector<double>& v) {
  if (v.empty()) return "–";
  std::string s;
  for (double x : v) s += (s.empty() ? "" : ", ") + fmt_rate(x);
  return s;
}

std::string utc_now(const char* strftime_format) {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, strftime_format, &tm);
  return buf;
}

std::string fmt_seconds(double s) {
  if (!(s >= 0)) return kNoValue;
  if (std::isinf(s)) return "inf";
  if (s < 1) return fmt::format("{:.3f} s", s);
  if (s < 59.95) return fmt::format("{:.1f} s", s);  // 59.95 would print as "60.0 s"
  const long long total = std::llround(s);
  if (total < 3600) return fmt::format("{} min {:02} s", total / 60, total % 60);
  const long long minutes = std::llround(s / 60);
  return fmt::format("{} h {:02} min", minutes / 60, minutes % 60);
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (char ch : s) {
    if (ch == '"') out += '"';
    out += ch;
  }
  return out + '"';
}

}  // namespace mfv
