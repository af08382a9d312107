/// `mfv docs --check FILE…` / `--write FILE…`: the blocks of README.md and docs/ that are
/// generated from a manifest, so that the counts and the methods × problems table stated there
/// never drift from `mfv verify --list` (issue 42, item 4). A block is
///
///   <!-- mfv:begin KIND MANIFEST -->
///   …generated text…
///   <!-- mfv:end -->
///
/// with KIND one of
///   counts               one sentence: the manifest's cases (nightly and --full) and its
///                        ledger's rows;
///   methods-by-problems  the table of problems (rows) × methods (columns, in the order the
///                        manifest first uses them), ● where at least one case (--full ones
///                        included) runs that method on that problem.
/// MANIFEST is relative to the working directory (the repository root in the tests).
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "apps/commands.hpp"
#include "methods/core/errors.hpp"
#include "reports/atomic.hpp"
#include "verify/ledger.hpp"
#include "verify/manifest.hpp"

namespace mfv {

namespace {

constexpr const char* kBegin = "<!-- mfv:begin ";
constexpr const char* kEnd = "<!-- mfv:end -->";

std::string counts_block(const Catalogue& c, const Manifest& m) {
  int nightly = 0, full_only = 0;
  for (const auto& mc : m.cases) (mc.full_only ? full_only : nightly) += 1;
  std::string ledger;
  if (!m.ledger.empty()) {
    const Ledger l = load_ledger(m.ledger, m, c);
    // By paper key (the source's first word: 000, 001, 003, 004); rows whose source is
    // another reference (Martin & Moyce, Lamé, …) counted apart.
    std::map<std::string, int> by_paper;
    int other = 0, checks = 0, costs = 0, claims = 0;
    for (const auto& r : l.rows) {
      if (r.role == LedgerRow::Role::check) {
        ++checks;
        continue;
      }
      if (r.role == LedgerRow::Role::cost) {
        ++costs;
        continue;
      }
      ++claims;
      const std::string key = r.source.substr(0, r.source.find(' '));
      const bool paper = key.size() == 3 && std::all_of(key.begin(), key.end(), ::isdigit);
      paper ? ++by_paper[key] : ++other;
    }
    std::vector<std::string> parts;
    for (const auto& [paper, n] : by_paper) parts.push_back(fmt::format("{} of {}", n, paper));
    if (other > 0) parts.push_back(fmt::format("{} of other references", other));
    ledger = fmt::format(
        "; its ledger `{}` holds {} claims ({}), {} claims about CPU time (counted apart) and {} "
        "of our own checks",
        m.ledger.string(), claims, fmt::join(parts, ", "), costs, checks);
  }
  return fmt::format("`{}` runs {} cases nightly and {} more with `--full` ({} in all){}.\n",
                     m.path.string(), nightly, full_only, nightly + full_only, ledger);
}

std::string methods_by_problems_block(const Manifest& m) {
  std::vector<std::string> methods;
  std::map<std::string, std::set<std::string>> ran;  // problem → methods
  for (const auto& mc : m.cases) {
    if (std::find(methods.begin(), methods.end(), mc.method) == methods.end())
      methods.push_back(mc.method);
    ran[mc.problem].insert(mc.method);
  }
  std::string out = fmt::format("| problem | {} |\n|:--|", fmt::join(methods, " | "));
  for (std::size_t k = 0; k < methods.size(); ++k) out += ":-:|";
  out += "\n";
  for (const auto& [problem, used] : ran) {
    out += "| " + problem + " |";
    for (const auto& method : methods) out += used.count(method) ? " ● |" : "  |";
    out += "\n";
  }
  return out;
}

std::string block(const Catalogue& c, const std::string& kind, const std::string& manifest,
                  const std::string& where) {
  const Manifest m = load_manifest(manifest);
  if (kind == "counts") return counts_block(c, m);
  if (kind == "methods-by-problems") return methods_by_problems_block(m);
  throw InputError(fmt::format("{}: unknown generated block '{}'; the kinds are counts and "
                               "methods-by-problems",
                               where, kind));
}

}  // namespace

int command_docs(const Catalogue& c, const std::vector<std::string>& files, bool write,
                 std::ostream& out) {
  int stale = 0;
  for (const auto& file : files) {
    std::ifstream in(file, std::ios::binary);
    if (!in)
      throw InputError(fmt::format("mfv docs: cannot read '{}'; name a Markdown file", file));
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    std::string result;
    std::size_t at = 0;
    int blocks = 0, file_stale = 0;
    while (true) {
      const std::size_t b = text.find(kBegin, at);
      if (b == std::string::npos) {
        result += text.substr(at);
        break;
      }
      const std::size_t head_end = text.find("-->", b);
      const std::size_t line_end = text.find('\n', b);
      const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + b, '\n'));
      const std::string where = fmt::format("{}:{}", file, line);
      if (head_end == std::string::npos || line_end == std::string::npos || head_end > line_end)
        throw InputError(fmt::format("{}: a generated block's head must be one line "
                                     "'<!-- mfv:begin KIND MANIFEST -->'",
                                     where));
      std::istringstream head(text.substr(b + std::string(kBegin).size(),
                                          head_end - b - std::string(kBegin).size()));
      std::string kind, manifest;
      head >> kind >> manifest;
      if (manifest.empty())
        throw InputError(fmt::format("{}: the block names no manifest: write "
                                     "'<!-- mfv:begin {} suites/default.toml -->'",
                                     where, kind));
      const std::size_t e = text.find(kEnd, line_end);
      if (e == std::string::npos)
        throw InputError(fmt::format("{}: block '{}' has no '{}'", where, kind, kEnd));
      const std::string now = text.substr(line_end + 1, e - line_end - 1);
      const std::string want = block(c, kind, manifest, where);
      ++blocks;
      if (now != want) {
        ++file_stale;
        out << fmt::format("{}: block '{} {}' is out of date{}\n", where, kind, manifest,
                           write ? "; rewritten" : "; run `mfv docs --write " + file + "`");
      }
      result += text.substr(at, line_end + 1 - at) + want;
      at = e;
    }
    if (blocks == 0)
      throw InputError(fmt::format("mfv docs: '{}' holds no generated block "
                                   "('<!-- mfv:begin KIND MANIFEST -->')",
                                   file));
    if (write && file_stale > 0) write_file_atomic(file, result);
    stale += file_stale;
  }
  if (stale == 0) out << fmt::format("mfv docs: every generated block of {} file(s) is up to date\n",
                                     files.size());
  return write || stale == 0 ? 0 : 1;
}

}  // namespace mfv
