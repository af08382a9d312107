/// JUnit XML of a verification run (`mfv verify --junit FILE`), for the test views of CI
/// servers: the layout of Jenkins' xunit junit-10.xsd, which GitLab's and GitHub's JUnit
/// readers also parse (tests/data/junit-10.xsd; a test validates against it).
///   <testsuites> ─ <testsuite name=suite> ─ <properties> (provenance, ledger verdicts)
///                                          └ <testcase classname="mfv.<problem>" name=<case id>>
///                                              ├ <failure type="band|stability|baseline"> per miss
///                                              ├ <error type="could-not-run"> when it did not run
///                                              └ <system-out> the case's verdict row
/// A testcase element has no properties in that schema, so the ledger's verdicts are the
/// suite's properties, one per row ("ledger:<row id>" → "<verdict>; cases …").
#pragma once
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mfv {

struct JUnitProblem {
  enum class Kind { failure, error };
  Kind kind = Kind::failure;
  std::string type;     ///< "band", "stability", "baseline", "could-not-run"
  std::string message;  ///< one line: the miss with its numbers
  std::string text;     ///< the element's body (may be empty)
};

struct JUnitCase {
  std::string classname, name;
  double seconds = 0;
  std::vector<JUnitProblem> problems;
  std::string system_out;
};

struct JUnitSuite {
  std::string name;
  std::string timestamp;  ///< ISO 8601, UTC ("2026-11-28T09:30:00")
  std::string hostname;
  double seconds = 0;
  std::vector<std::pair<std::string, std::string>> properties;
  std::vector<JUnitCase> cases;
};

/// The document, UTF-8, with the marker comment `is_mfv_junit` recognizes.
std::string junit_xml(const JUnitSuite& suite);

/// Whether a file's first bytes are a JUnit file mfv wrote (and may be replaced).
bool is_mfv_junit(const std::string& head);

/// Text as XML character data or an attribute value: & < > " ' escaped, and the characters
/// XML 1.0 forbids (controls other than tab, newline, carriage return; invalid UTF-8 bytes)
/// replaced by U+FFFD, so a message holding any byte still makes a well-formed document.
std::string xml_escape(std::string_view text);

}  // namespace mfv
