/// Issue 28's nightly-grade command line: `mfv verify --junit` writes JUnit XML that validates
/// against Jenkins' junit-10.xsd (tests/data/, read by xmllint); `mfv diff` names exactly the
/// values that moved and the report leads with them; case globs and near-miss hints, "did you
/// mean" on names and keys, `mfv list <kind|name>`, and the provenance that `mfv --version`
/// and results.json carry.
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <thread>

#include "apps/commands.hpp"
#include "methods/core/errors.hpp"
#include "methods/core/names.hpp"
#include "verify/diff.hpp"
#include "verify/history.hpp"
#include "verify/junit.hpp"
#include "verify/provenance.hpp"

namespace mfv {
namespace {

namespace fs = std::filesystem;

const fs::path kSchema = fs::path(MFV_SOURCE_DIR) / "tests" / "data" / "junit-10.xsd";

/// xmllint's verdict on `file` against the JUnit schema: "" when it validates, else its output.
std::string schema_errors(const fs::path& file) {
  const fs::path log = file.string() + ".xmllint";
  const std::string cmd = "xmllint --noout --schema '" + kSchema.string() + "' '" +
                          file.string() + "' > '" + log.string() + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  std::stringstream text;
  text << std::ifstream(log).rdbuf();
  if (rc == 0) return "";
  if (WIFEXITED(rc) && WEXITSTATUS(rc) == 127)
    return "xmllint is not installed: install libxml2-utils (scripts/setup.sh does)";
  return text.str().empty() ? "xmllint failed" : text.str();
}

std::string read(const fs::path& p) {
  std::stringstream s;
  s << std::ifstream(p).rdbuf();
  return s.str();
}

class Nightly : public ::testing::Test {
 protected:
  void SetUp() override {
    static std::atomic<int> n{0};
    dir_ = fs::temp_directory_path() /
           ("mfv-nightly-" + std::to_string(::getpid()) + "-" + std::to_string(n++));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  /// Two FEM cases on laplace-tanh (L2 rate about 2), the second with a band it misses.
  fs::path two_cases() {
    return write("suite.toml",
                 "[suite]\nname = \"t\"\n"
                 "[[case]]\nid = \"lt/fem\"\nproblem = \"laplace-tanh\"\nmethod = \"fem\"\n"
                 "nodes = [21, 41]\n[case.bands]\nl2_rate = [1.5, 2.5]\n"
                 "[[case]]\nid = \"lt/fem-tight\"\nproblem = \"laplace-tanh\"\nmethod = \"fem\"\n"
                 "nodes = [21, 41]\n[case.bands]\nl2_rate = [2.8, 3.0]\n"
                 "[[case]]\nid = \"other/fem\"\nproblem = \"laplace-tanh\"\nmethod = \"fem\"\n"
                 "nodes = [21, 41]\n");
  }
  VerifyOptions options(const fs::path& m) {
    VerifyOptions o;
    o.manifest = m.string();
    o.no_report = true;
    return o;
  }
  /// The two-case manifest reported into dir_/report, without VTK (history beside it).
  VerifyOptions reported() {
    VerifyOptions o = options(two_cases());
    o.no_report = false;
    o.report = (dir_ / "report").string();
    o.vtk = false;
    return o;
  }
  const Catalogue catalogue_;
  fs::path dir_;
};

TEST(JUnitXml, ValidatesAgainstTheJenkinsSchemaWithEveryKindOfOutcome) {
  JUnitSuite s;
  s.name = "default";
  s.timestamp = "2026-11-28T10:00:00";
  s.hostname = "host";
  s.seconds = 12.3456;
  s.properties = {{"ledger:004-II-T1-fem", "reproduced; cases laplace-tanh/fem"}};
  s.cases.push_back({"mfv.laplace-tanh", "laplace-tanh/fem", 1.5, {}, "PASS"});
  s.cases.push_back({"mfv.rod-pulse",
                     "rod-pulse/sph",
                     2.0,
                     {{JUnitProblem::Kind::failure, "band", "l2_rate = 1.2 outside [1.8, 2.2]",
                       "l2_rate = 1.2, band [1.8, 2.2]"},
                      {JUnitProblem::Kind::failure, "baseline", "l2 worse", ""}},
                     ""});
  s.cases.push_back({"mfv.funnel", "funnel/kbm-si", 0,
                     {{JUnitProblem::Kind::error, "could-not-run", "singular <&> \"x\"", ""}}, ""});
  const std::string xml = junit_xml(s);
  EXPECT_NE(xml.find("tests=\"3\" failures=\"1\" errors=\"1\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("time=\"12.346\""), std::string::npos) << xml;
  EXPECT_TRUE(is_mfv_junit(xml));
  const fs::path f = fs::temp_directory_path() / ("mfv-junit-" + std::to_string(::getpid()) + ".xml");
  std::ofstream(f) << xml;
  EXPECT_EQ(schema_errors(f), "") << xml;
  fs::remove(f);
  fs::remove(f.string() + ".xmllint");
}

TEST(JUnitXml, AnyBytesInAMessageStillMakeAWellFormedDocument) {
  // Controls XML 1.0 forbids, a lone continuation byte, an overlong '/', a surrogate, markup.
  const std::string nasty = std::string("a\x01" "b\x1f\x80" "c\xC0\xAF" "d\xED\xA0\x80") +
                            "<e>&\"'\n\t\xC3\xA9\xE2\x86\x92";
  const std::string esc = xml_escape(nasty);
  EXPECT_EQ(esc.find('\x01'), std::string::npos);
  EXPECT_EQ(esc.find('<'), std::string::npos);
  EXPECT_NE(esc.find("\xC3\xA9\xE2\x86\x92"), std::string::npos) << "valid UTF-8 is kept";
  EXPECT_NE(esc.find("&lt;e&gt;&amp;&quot;&apos;&#10;&#9;"), std::string::npos) << esc;
  JUnitSuite s;
  s.name = nasty;
  s.cases.push_back({nasty, nasty, NAN, {{JUnitProblem::Kind::failure, nasty, nasty, nasty}},
                     nasty});
  const fs::path f =
      fs::temp_directory_path() / ("mfv-junit-bytes-" + std::to_string(::getpid()) + ".xml");
  std::ofstream(f) << junit_xml(s);
  EXPECT_EQ(schema_errors(f), "") << read(f);
  EXPECT_NE(read(f).find("time=\"0.000\""), std::string::npos) << "a NaN time is written as 0";
  fs::remove(f);
  fs::remove(f.string() + ".xmllint");
}

TEST_F(Nightly, VerifyWritesAJUnitFileThatValidatesAndKeepsItsExitCode) {
  VerifyOptions o = options(two_cases());
  o.junit = (dir_ / "junit.xml").string();
  std::ostringstream out, progress;
  EXPECT_EQ(command_verify(catalogue_, o, out, progress), 1) << out.str();
  const std::string xml = read(o.junit);
  EXPECT_EQ(schema_errors(o.junit), "") << xml;
  EXPECT_NE(xml.find("tests=\"3\" failures=\"1\" errors=\"0\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("classname=\"mfv.laplace-tanh\" name=\"lt/fem-tight\""), std::string::npos);
  // The failure names the metric, the value and the band.
  EXPECT_TRUE(std::regex_search(xml, std::regex("<failure type=\"band\" message=\"[^\"]*l2_rate")))
      << xml;
  EXPECT_NE(xml.find("band [2.8, 3]"), std::string::npos) << xml;
  EXPECT_NE(xml.find("name=\"mfv.commit\""), std::string::npos) << xml;
  // A file mfv did not write is never replaced; its own is.
  std::ofstream(o.junit) << "<notes>mine</notes>";
  std::ostringstream out2;
  EXPECT_THROW(command_verify(catalogue_, o, out2, progress), InputError);
  EXPECT_EQ(read(o.junit), "<notes>mine</notes>");
}

TEST_F(Nightly, CaseGlobsSelectInManifestOrderAndAMissNamesTheNearIds) {
  VerifyOptions o = options(two_cases());
  o.list = true;
  o.cases = {"lt/*"};
  std::ostringstream out, progress;
  EXPECT_EQ(command_verify(catalogue_, o, out, progress), 0);
  EXPECT_NE(out.str().find("lt/fem "), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("lt/fem-tight"), std::string::npos) << out.str();
  EXPECT_EQ(out.str().find("other/fem"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("2 case(s)"), std::string::npos) << out.str();

  o.cases = {"lt/fme"};
  try {
    command_verify(catalogue_, o, out, progress);
    FAIL() << "a missing id was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("near ones: lt/fem"), std::string::npos) << what;
    EXPECT_NE(what.find("3 cases"), std::string::npos) << what;
    EXPECT_LT(what.size(), 400u) << "a miss names near ids, not every id: " << what;
  }
  o.cases = {"nothing/*"};
  EXPECT_THROW(command_verify(catalogue_, o, out, progress), InputError);
}

TEST_F(Nightly, DiffNamesExactlyTheValuesThatMovedAndTheReportLeadsWithThem) {
  VerifyOptions o = reported();
  std::ostringstream out, progress;
  ASSERT_EQ(command_verify(catalogue_, o, out, progress), 1) << out.str();
  const std::string first = read(dir_ / "report" / "index.md");
  EXPECT_NE(first.find("no earlier verification run"), std::string::npos) << first.substr(0, 2000);
  // The same run again: nothing moved, and the report says so before anything else.
  ASSERT_EQ(command_verify(catalogue_, o, out, progress), 1) << out.str();
  const std::string second = read(dir_ / "report" / "index.md");
  const auto changes = second.find("## Changes since the last run");
  ASSERT_NE(changes, std::string::npos) << second.substr(0, 2000);
  EXPECT_LT(changes, second.find("## Contents"));
  EXPECT_NE(second.find("**0 worse, 0 better"), std::string::npos) << second.substr(0, 2000);

  // One error made 50 % larger, one verdict flipped: the diff names those two and no other.
  const nlohmann::json a = load_run_results(dir_ / "report");
  nlohmann::json b = a;
  for (auto& c : b["cases"])
    if (c["id"] == "lt/fem") {
      c["verdict"] = "FAIL";
      auto& e = b["studies"][c["study"].get<std::size_t>()]["resolutions"][1]["errors"]["common"]
                 ["l2"]["relative"];
      e = e.get<double>() * 1.5;
    }
  const RunDiff d = diff_runs(a, b);
  EXPECT_EQ(d.worse(), 2) << diff_text(d);
  EXPECT_EQ(d.better(), 0) << diff_text(d);
  ASSERT_EQ(d.numbers.size(), 1u) << diff_text(d);
  EXPECT_EQ(d.numbers[0].case_id, "lt/fem");
  EXPECT_EQ(d.numbers[0].quantity, "L2 relative error at 41 nodes");
  EXPECT_NEAR(d.numbers[0].relative, 0.5, 1e-12);
  ASSERT_EQ(d.verdicts.size(), 1u);
  EXPECT_EQ(d.verdicts[0].before, "PASS");
  // The full H1 norm's error is compared as the others are (issue 45: a 1.5x worse H1 error
  // was not seen: only L2, the H1 seminorm and the energy were read).
  nlohmann::json h = a;
  for (auto& c : h["cases"])
    if (c["id"] == "lt/fem") {
      auto& res = h["studies"][c["study"].get<std::size_t>()]["resolutions"][1]["errors"];
      ASSERT_TRUE(res["common"].contains("h1")) << res.dump();
      auto& e = res["common"]["h1"]["relative"];
      e = e.get<double>() * 1.5;
    }
  const RunDiff dh = diff_runs(a, h);
  ASSERT_EQ(dh.numbers.size(), 1u) << diff_text(dh);
  EXPECT_EQ(dh.numbers[0].quantity, "H1 relative error at 41 nodes");
  EXPECT_EQ(dh.worse(), 1);
  // A case gone and a measurement lost are named too; the command exits 1 on anything worse.
  b["cases"].erase(b["cases"].begin() + 2);
  const RunDiff d2 = diff_runs(a, b);
  EXPECT_EQ(d2.removed, std::vector<std::string>{"other/fem"});
  std::ofstream(dir_ / "b.json") << b.dump();
  std::ostringstream text;
  EXPECT_EQ(command_diff({(dir_ / "report").string(), (dir_ / "b.json").string(), 0.05}, text), 1);
  EXPECT_NE(text.str().find("L2 relative error at 41 nodes"), std::string::npos) << text.str();
  EXPECT_EQ(command_diff({(dir_ / "report").string(), (dir_ / "report").string(), 0.05}, text), 0);
  // Not a results.json: an input error naming the file.
  std::ofstream(dir_ / "junk.json") << "{\"a\": 1}";
  EXPECT_THROW(load_run_results(dir_ / "junk.json"), InputError);
  EXPECT_THROW(load_run_results(dir_ / "missing"), InputError);
}

TEST_F(Nightly, EachRunIsAppendedToTheHistoryWhichAnswersOverTime) {
  VerifyOptions o = reported();
  std::ostringstream out, progress;
  command_verify(catalogue_, o, out, progress);
  command_verify(catalogue_, o, out, progress);
  const fs::path file = dir_ / "report.history.sqlite";
  ASSERT_TRUE(fs::exists(file)) << "the history sits beside the report: " << out.str();
  const HistoryStore h(file);
  ASSERT_EQ(h.runs().size(), 2u);
  EXPECT_EQ(h.runs().front().status, "FAIL");
  const auto pts = h.series("lt/fem", "L2 relative error at 41 nodes");
  ASSERT_EQ(pts.size(), 2u);
  EXPECT_EQ(pts[0].value, pts[1].value) << "the same run twice records the same number";
  EXPECT_GT(pts[0].value, 0);
  // mfv history and mfv diff by run id.
  std::ostringstream text;
  HistoryCommandOptions ho{file.string(), "lt/fem/L2 relative error at 41 nodes", "", 20};
  EXPECT_EQ(command_history(ho, text), 0);
  EXPECT_NE(text.str().find("trend:"), std::string::npos) << text.str();
  ho.subject = "lt/fme";
  EXPECT_THROW(command_history(ho, text), InputError);
  EXPECT_EQ(command_diff({"1", "2", 0.05, file.string()}, text), 0) << text.str();
  EXPECT_NE(text.str().find("0 worse, 0 better"), std::string::npos) << text.str();
  EXPECT_THROW(command_diff({"1", "7", 0.05, file.string()}, text), InputError);
  // A report path with a trailing slash keeps its history beside it, not inside.
  VerifyOptions slash = reported();
  slash.report = (dir_ / "slash").string() + "/";
  command_verify(catalogue_, slash, out, progress);
  EXPECT_TRUE(fs::exists(dir_ / "slash.history.sqlite"));
  EXPECT_FALSE(fs::exists(dir_ / "slash" / ".history.sqlite"));
  // --no-report without --history writes none.
  o.no_report = true;
  o.report.clear();
  command_verify(catalogue_, o, out, progress);
  EXPECT_EQ(HistoryStore(file).runs().size(), 2u);
}

// Two nightly jobs that create one new history at once (issue 45: one saw the other's file
// before its schema was written and refused it as "not an mfv history", or met "database is
// locked"): a history appears under its name whole, and the loser opens the winner's.
TEST_F(Nightly, TwoWritersCreatingOneNewHistoryBothOpenIt) {
  for (int round = 0; round < 25; ++round) {
    const fs::path file = dir_ / fmt::format("new-{}.sqlite", round);
    std::atomic<int> ready{0};
    std::string errors[2];
    auto open = [&](int k) {
      ++ready;
      while (ready.load() < 2) {
      }
      try {
        HistoryStore h(file);
        h.check_writable();
      } catch (const std::exception& e) {
        errors[k] = e.what();
      }
    };
    std::thread a(open, 0), b(open, 1);
    a.join();
    b.join();
    EXPECT_EQ(errors[0], "") << "round " << round;
    EXPECT_EQ(errors[1], "") << "round " << round;
    EXPECT_TRUE(HistoryStore(file).runs().empty());
  }
  // No private file of a creation is left beside the histories.
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_EQ(e.path().filename().string().rfind(".mfv-history-new-", 0), std::string::npos)
        << e.path();
}

TEST_F(Nightly, AHistoryFileThatIsNotOursIsRefusedAndKept) {
  const fs::path junk = write("junk.sqlite", "not a database at all, just text\n");
  EXPECT_THROW(HistoryStore{junk}, InputError);
  EXPECT_EQ(read(junk), "not a database at all, just text\n");
  EXPECT_THROW(HistoryStore{dir_}, InputError) << "a directory";
  EXPECT_THROW(HistoryStore{dir_ / "missing-dir" / "h.sqlite"}, InputError);
  // Someone else's SQLite database, and one from a newer mfv.
  for (const char* sql : {"CREATE TABLE mine(x);", "PRAGMA user_version = 99;"}) {
    const fs::path f = dir_ / (std::string("db-") + std::to_string(sql[0]) + ".sqlite");
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(f.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, sql, nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
    const auto size = fs::file_size(f);
    try {
      HistoryStore h(f);
      FAIL() << "accepted " << sql;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(f.string()), std::string::npos) << e.what();
    }
    EXPECT_EQ(fs::file_size(f), size);
  }
}

TEST_F(Nightly, AHistoryIsCreatedOnlyWhereNoFileExistsAndIsCheckedWritableBeforeTheFirstCase) {
  // Issue 45: a zero-length or 1-byte file, a foreign database whose user_version is negative
  // or 0, were taken over (user_version rewritten to 1); each is refused and left as it was.
  const fs::path empty = write("empty.sqlite", "");
  const fs::path one = write("one.sqlite", "x");
  for (const fs::path& f : {empty, one}) {
    const auto size = fs::file_size(f);
    EXPECT_THROW(HistoryStore{f}, InputError) << f;
    EXPECT_EQ(fs::file_size(f), size);
  }
  auto user_version = [](const fs::path& f) {
    sqlite3* db = nullptr;
    sqlite3_open(f.c_str(), &db);
    sqlite3_stmt* st = nullptr;
    sqlite3_prepare_v2(db, "PRAGMA user_version", -1, &st, nullptr);
    sqlite3_step(st);
    const int v = sqlite3_column_int(st, 0);
    sqlite3_finalize(st);
    sqlite3_close(db);
    return v;
  };
  for (const char* sql : {"CREATE TABLE t(x); DROP TABLE t; PRAGMA user_version = -3;",
                          "CREATE TABLE t(x); DROP TABLE t;"}) {
    const fs::path f = dir_ / (std::string("foreign-") + std::to_string(std::strlen(sql)) + ".db");
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(f.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, sql, nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
    const int before = user_version(f);
    try {
      HistoryStore h(f);
      FAIL() << "took over " << sql;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("mfv did not write"), std::string::npos) << e.what();
    }
    EXPECT_EQ(user_version(f), before) << sql;
  }
  // Another writer holding the history past the busy timeout: refused by check_writable
  // (verify calls it before the first case), not after the last.
  const fs::path file = dir_ / "locked.sqlite";
  { HistoryStore create(file); }
  sqlite3* other = nullptr;
  ASSERT_EQ(sqlite3_open(file.c_str(), &other), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(other, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr), SQLITE_OK);
  HistoryStore h(file);  // reading needs no lock
  try {
    h.check_writable();
    ADD_FAILURE() << "a locked history was taken as writable";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot be written"), std::string::npos) << e.what();
  }
  sqlite3_exec(other, "ROLLBACK", nullptr, nullptr, nullptr);
  sqlite3_close(other);
  EXPECT_NO_THROW(h.check_writable());
}

/// The InputError `f` throws, or "(accepted)" when it throws none.
std::string input_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST_F(Nightly, AHistoryOrJUnitInsideTheReportIsRefusedAndForceNeverDeletesAHistory) {
  std::ostringstream out, progress;
  VerifyOptions o = reported();
  o.history = (dir_ / "report" / "h.sqlite").string();
  const std::string history_inside =
      input_error_of([&] { command_verify(catalogue_, o, out, progress); });
  EXPECT_NE(history_inside.find("is inside the report directory"), std::string::npos)
      << history_inside;
  EXPECT_EQ(progress.str().find("[1/"), std::string::npos) << "a case ran: " << progress.str();
  o = reported();
  o.junit = (dir_ / "report" / "junit.xml").string();
  EXPECT_THROW(command_verify(catalogue_, o, out, progress), InputError);
  // A JUnit file inside an existing report, with a history and with --no-history (the check
  // is not part of the history's).
  o = reported();
  command_verify(catalogue_, o, out, progress);
  for (const bool no_history : {false, true}) {
    o = reported();
    o.junit = (dir_ / "report" / "junit.xml").string();
    o.no_history = no_history;
    const std::string junit_inside =
        input_error_of([&] { command_verify(catalogue_, o, out, progress); });
    EXPECT_NE(junit_inside.find("--junit"), std::string::npos) << junit_inside;
    EXPECT_FALSE(fs::exists(dir_ / "report" / "junit.xml"));
  }
  // A report with a history someone put inside it: --force replaces the report's added
  // files, but not a database.
  o = reported();
  fs::copy_file(dir_ / "report.history.sqlite", dir_ / "report" / "kept.sqlite");
  o.force = true;
  const std::string forced =
      input_error_of([&] { command_verify(catalogue_, o, out, progress); });
  EXPECT_NE(forced.find("--force never deletes one"), std::string::npos) << forced;
  EXPECT_TRUE(fs::exists(dir_ / "report" / "kept.sqlite"));
}

TEST_F(Nightly, DiffRefusesRunsOfAnotherSuiteAFifoAndAHugeFileAndFailsWhenCasesVanish) {
  // Issue 45: diff exited 0 for two reports of different suites and when every case
  // vanished, and blocked on a FIFO.
  VerifyOptions o = reported();
  o.no_history = true;
  std::ostringstream out, progress;
  command_verify(catalogue_, o, out, progress);
  nlohmann::json run = load_run_results(dir_ / "report");
  nlohmann::json other = run;
  other["suite"]["name"] = "another";
  std::ofstream(dir_ / "other.json") << other.dump();
  std::ostringstream text;
  try {
    command_diff({(dir_ / "report").string(), (dir_ / "other.json").string(), 0.05}, text);
    ADD_FAILURE() << "diffed two suites";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("different suites"), std::string::npos) << e.what();
  }
  nlohmann::json none = run;
  none["cases"] = nlohmann::json::array();
  std::ofstream(dir_ / "none.json") << none.dump();
  EXPECT_EQ(command_diff({(dir_ / "report").string(), (dir_ / "none.json").string(), 0.05}, text),
            1);
  EXPECT_NE(text.str().find("(every one: nothing was compared)"), std::string::npos) << text.str();
  ASSERT_EQ(::mkfifo((dir_ / "fifo.json").c_str(), 0600), 0);
  EXPECT_THROW(load_run_results(dir_ / "fifo.json"), InputError);
  {
    std::ofstream big(dir_ / "big.json");
    big.seekp((std::streamoff{257} << 20));
    big << ' ';
  }
  EXPECT_THROW(load_run_results(dir_ / "big.json"), InputError);
  // A run id out of range, and a history that does not exist (diff reads, never creates).
  o = reported();
  command_verify(catalogue_, o, out, progress);
  try {
    command_diff({"99999999999999999999999", "1", 0.05, (dir_ / "report.history.sqlite").string()},
                 text);
    ADD_FAILURE() << "a run id out of range";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  }
  EXPECT_THROW(command_diff({"1", "2", 0.05, (dir_ / "nowhere.sqlite").string()}, text),
               InputError);
  EXPECT_FALSE(fs::exists(dir_ / "nowhere.sqlite"));
}

/// A results.json with one L2 error set to `l2` (the rest from a real run).
nlohmann::json with_l2(nlohmann::json j, double l2) {
  for (auto& c : j["cases"])
    if (c["id"] == "lt/fem")
      j["studies"][c["study"].get<std::size_t>()]["resolutions"][1]["errors"]["common"]["l2"]
       ["relative"] = l2;
  return j;
}

TEST_F(Nightly, ConcurrentWritersTakeTurnsAndASlowCreepIsFound) {
  VerifyOptions o = reported();
  o.no_history = true;
  std::ostringstream out, progress;
  command_verify(catalogue_, o, out, progress);
  const nlohmann::json base = load_run_results(dir_ / "report");
  const fs::path file = dir_ / "h.sqlite";
  { HistoryStore create(file); }
  // Two writers at once, each its own connection, as two nightly jobs would be.
  std::vector<std::thread> writers;
  std::atomic<int> failures{0};
  for (int w = 0; w < 2; ++w)
    writers.emplace_back([&] {
      try {
        HistoryStore h(file);
        for (int k = 0; k < 4; ++k) h.append(base);
      } catch (...) {
        ++failures;
      }
    });
  for (auto& t : writers) t.join();
  EXPECT_EQ(failures.load(), 0);
  HistoryStore h(file);
  EXPECT_EQ(h.runs(100).size(), 8u);
  // 3 % a night for five nights: no night-to-night drift at 5 %, a creep of 16 % over them.
  long last = 0;
  for (int k = 1; k <= 5; ++k) last = h.append(with_l2(base, 0.01 * std::pow(1.03, k)));
  const auto creep = h.drifts(last, 5, 0.05);
  ASSERT_EQ(creep.size(), 1u);
  EXPECT_EQ(creep[0].case_id, "lt/fem");
  EXPECT_EQ(creep[0].quantity, "L2 relative error at 41 nodes");
  EXPECT_NE(creep[0].message.find("crept"), std::string::npos) << creep[0].message;
  // A jump is the night-to-night comparison's business, not a creep.
  const long jump = h.append(with_l2(base, 0.02));
  EXPECT_TRUE(h.drifts(jump, 3, 0.05).empty());
}

TEST_F(Nightly, VtkFinestWritesEachStudysFinestResolutionAndSaysHowToGetTheRest) {
  for (const bool finest : {true, false}) {
    VerifyOptions o = options(two_cases());
    o.cases = {"lt/fem"};
    o.no_report = false;
    o.no_history = true;
    o.report = (dir_ / (finest ? "finest" : "all")).string();
    o.vtk = true;
    o.vtk_finest_only = finest;
    std::ostringstream out, progress;
    ASSERT_EQ(command_verify(catalogue_, o, out, progress), 0) << out.str();
    const fs::path study = fs::path(o.report) / "vtk" / "laplace-tanh" / "lt-fem";
    EXPECT_TRUE(fs::exists(study / "n41.vtp"));
    EXPECT_TRUE(fs::exists(study / "study.pvd"));
    EXPECT_EQ(fs::exists(study / "n21.vtp"), !finest);
    const std::string page = read(fs::path(o.report) / "problems" / "laplace-tanh.md");
    EXPECT_EQ(page.find("--vtk=all") != std::string::npos, finest) << page;
    // Every study's convergence table as CSV and LaTeX.
    const fs::path table = fs::path(o.report) / "tables" / "laplace-tanh" / "lt-fem";
    const std::string csv = read(table.string() + ".csv");
    EXPECT_EQ(csv.rfind("h,particles,L2 relative,L2 relative rate,", 0), 0u) << csv;
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 3) << "a header and two resolutions";
    const std::string tex = read(table.string() + ".tex");
    EXPECT_NE(tex.find("\\toprule"), std::string::npos) << tex;
    EXPECT_NE(tex.find("least squares"), std::string::npos) << tex;
    EXPECT_NE(tex.find("\\bottomrule"), std::string::npos) << tex;
  }
}

TEST(Names, NearMatchesFindTyposAndPrefixesAndNothingFar) {
  const std::vector<std::string> valid = {"kbm-si", "kbm-ni", "kbm-ci", "sph", "efg"};
  EXPECT_EQ(near_matches("kbm-sj", valid).front(), "kbm-si");
  EXPECT_EQ(near_matches("spj", valid).front(), "sph");
  EXPECT_TRUE(near_matches("wendland-c2", valid).empty());
  // A refused name of 10 kB is shown by its start and its length (issue 45, F16).
  EXPECT_EQ(shown_name("sph"), "sph");
  const std::string huge(10000, 'x');
  EXPECT_EQ(shown_name(huge), std::string(60, 'x') + "… (10000 characters)");
  try {
    const Catalogue catalogue;
    catalogue.methods.entry(huge);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_LT(std::string(e.what()).size(), 2000u) << std::string(e.what()).substr(0, 200);
  }
  EXPECT_EQ(did_you_mean("zzzzzz", valid), "");
  EXPECT_EQ(did_you_mean("efh", valid), "did you mean 'efg'? ");
  EXPECT_EQ(edit_distance("fme", "fem"), 1u) << "a swap is one slip";
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
}

TEST_F(Nightly, UnknownNamesAndKeysSayWhatWasMeant) {
  try {
    (void)catalogue_.methods.create("kbm-sj");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'kbm-si'"), std::string::npos) << e.what();
  }
  try {
    (void)catalogue_.methods.create("sph", Params::parse("dmx=2"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'dmax'"), std::string::npos) << e.what();
  }
}

TEST_F(Nightly, ListTakesAKindOrANameAndRefusesAnythingElseWithAHint) {
  std::ostringstream all, methods, one;
  command_list(catalogue_, "", all);
  EXPECT_NE(all.str().find("analyses:"), std::string::npos) << "the plural of analysis";
  EXPECT_EQ(all.str().find("analysiss"), std::string::npos);
  command_list(catalogue_, "methods", methods);
  EXPECT_NE(methods.str().find("dmax="), std::string::npos) << "a kind lists the parameters";
  EXPECT_EQ(methods.str().find("problems:"), std::string::npos) << "and only that kind";
  command_list(catalogue_, "kbm-si", one);
  EXPECT_NE(one.str().find("kbm-si"), std::string::npos);
  const std::string entry = one.str();
  EXPECT_LT(std::count(entry.begin(), entry.end(), '\n'), 40) << entry;
  std::ostringstream sink;
  try {
    command_list(catalogue_, "methds", sink);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'methods'"), std::string::npos) << e.what();
  }
}

TEST(Provenance, NamesTheCommitCompilerAndMachine) {
  const Provenance p = provenance();
  EXPECT_TRUE(p.commit == "unknown" || std::regex_match(p.commit, std::regex("[0-9a-f]{40}")))
      << p.commit;
  EXPECT_FALSE(p.version.empty());
  EXPECT_FALSE(p.compiler.empty());
  EXPECT_GE(p.threads, 1);
  EXPECT_GE(p.cores, 1u);
  const std::string text = version_text(p);
  EXPECT_NE(text.find("mfv " + p.version), std::string::npos) << text;
  EXPECT_NE(text.find("Eigen"), std::string::npos) << text;
  const auto j = provenance_json(p);
  EXPECT_EQ(j.at("commit"), p.commit);
  EXPECT_TRUE(j.contains("load_average"));
}

}  // namespace
}  // namespace mfv
