#include "verify/junit.hpp"

#include <cmath>

#include <fmt/format.h>

namespace mfv {

namespace {

constexpr const char* kMarker = "<!-- written by mfv verify, JUnit XML -->";
constexpr const char* kReplacement = "\xEF\xBF\xBD";  // U+FFFD

/// The length of the well-formed UTF-8 sequence starting at s[i] that XML 1.0 allows, or 0.
std::size_t valid_char_length(std::string_view s, std::size_t i) {
  const auto b = static_cast<unsigned char>(s[i]);
  if (b < 0x80) return (b >= 0x20 || b == '\t' || b == '\n' || b == '\r') ? 1 : 0;
  std::size_t n = 0;
  char32_t cp = 0;
  if ((b & 0xE0) == 0xC0) {
    n = 2;
    cp = b & 0x1F;
  } else if ((b & 0xF0) == 0xE0) {
    n = 3;
    cp = b & 0x0F;
  } else if ((b & 0xF8) == 0xF0) {
    n = 4;
    cp = b & 0x07;
  } else {
    return 0;
  }
  if (i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k) {
    const auto c = static_cast<unsigned char>(s[i + k]);
    if ((c & 0xC0) != 0x80) return 0;
    cp = (cp << 6) | (c & 0x3F);
  }
  // Overlong forms, surrogates, U+FFFE/FFFF and beyond U+10FFFF are not characters of XML.
  static constexpr char32_t kMin[5] = {0, 0, 0x80, 0x800, 0x10000};
  if (cp < kMin[n] || (cp >= 0xD800 && cp <= 0xDFFF) || cp == 0xFFFE || cp == 0xFFFF ||
      cp > 0x10FFFF)
    return 0;
  return n;
}

/// Seconds as the schema's SUREFIRE_TIME takes them: fixed point, no exponent, never negative.
std::string seconds_text(double s) {
  return fmt::format("{:.3f}", std::isfinite(s) && s > 0 ? s : 0.0);
}

}  // namespace

std::string xml_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t n = valid_char_length(text, i);
    if (n == 0) {
      out += kReplacement;
      ++i;
      continue;
    }
    if (n == 1) {
      switch (text[i]) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        case '\'': out += "&apos;"; break;
        // In an attribute a newline would be read back as a space: keep it as a reference.
        case '\n': out += "&#10;"; break;
        case '\r': out += "&#13;"; break;
        case '\t': out += "&#9;"; break;
        default: out += text[i];
      }
    } else {
      out.append(text.substr(i, n));
    }
    i += n;
  }
  return out;
}

std::string junit_xml(const JUnitSuite& suite) {
  int failures = 0, errors = 0;
  for (const auto& c : suite.cases) {
    bool failed = false, errored = false;
    for (const auto& p : c.problems) (p.kind == JUnitProblem::Kind::error ? errored : failed) = true;
    // A case counts once: as an error when it could not run, else as a failure.
    errors += errored;
    failures += failed && !errored;
  }
  const auto tests = static_cast<int>(suite.cases.size());
  std::string x = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  x += kMarker;
  x += "\n";
  x += fmt::format(
      "<testsuites name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" time=\"{}\">\n",
      xml_escape("mfv verify " + suite.name), tests, failures, errors, seconds_text(suite.seconds));
  x += fmt::format(
      "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"0\" "
      "time=\"{}\" timestamp=\"{}\" hostname=\"{}\">\n",
      xml_escape(suite.name), tests, failures, errors, seconds_text(suite.seconds),
      xml_escape(suite.timestamp), xml_escape(suite.hostname));
  if (!suite.properties.empty()) {
    x += "    <properties>\n";
    for (const auto& [name, value] : suite.properties)
      x += fmt::format("      <property name=\"{}\" value=\"{}\"/>\n", xml_escape(name),
                       xml_escape(value));
    x += "    </properties>\n";
  }
  for (const auto& c : suite.cases) {
    x += fmt::format("    <testcase classname=\"{}\" name=\"{}\" time=\"{}\"", xml_escape(c.classname),
                     xml_escape(c.name), seconds_text(c.seconds));
    if (c.problems.empty() && c.system_out.empty()) {
      x += "/>\n";
      continue;
    }
    x += ">\n";
    for (const auto& p : c.problems)
      x += fmt::format("      <{0} type=\"{1}\" message=\"{2}\">{3}</{0}>\n",
                       p.kind == JUnitProblem::Kind::error ? "error" : "failure",
                       xml_escape(p.type), xml_escape(p.message), xml_escape(p.text));
    if (!c.system_out.empty())
      x += fmt::format("      <system-out>{}</system-out>\n", xml_escape(c.system_out));
    x += "    </testcase>\n";
  }
  x += "  </testsuite>\n</testsuites>\n";
  return x;
}

bool is_mfv_junit(const std::string& head) { return head.find(kMarker) != std::string::npos; }

}  // namespace mfv
