#include "verify/history.hpp"

#include <sqlite3.h>
#include <fcntl.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>

#include <fmt/format.h>

#include "methods/core/errors.hpp"

namespace mfv {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

/// A prepared statement, finalized on scope exit.
class Statement {
 public:
  Statement(sqlite3* db, const char* sql, const fs::path& file) : db_(db), file_(file) {
    if (sqlite3_prepare_v2(db, sql, -1, &s_, nullptr) != SQLITE_OK) fail("prepare");
  }
  ~Statement() { sqlite3_finalize(s_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  Statement& bind(int i, const std::string& v) {
    sqlite3_bind_text(s_, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
    return *this;
  }
  Statement& bind(int i, long v) {
    sqlite3_bind_int64(s_, i, v);
    return *this;
  }
  Statement& bind(int i, int v) { return bind(i, static_cast<long>(v)); }
  Statement& bind(int i, double v) {
    if (std::isfinite(v))
      sqlite3_bind_double(s_, i, v);
    else
      sqlite3_bind_null(s_, i);  // a value not measured is NULL, never 0
    return *this;
  }
  /// Steps once: true with a row, false when done.
  bool step() {
    const int rc = sqlite3_step(s_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    fail("step");
    return false;
  }
  void reset() {
    sqlite3_reset(s_);
    sqlite3_clear_bindings(s_);
  }
  long integer(int c) const { return static_cast<long>(sqlite3_column_int64(s_, c)); }
  double real(int c) const {
    return sqlite3_column_type(s_, c) == SQLITE_NULL ? NAN : sqlite3_column_double(s_, c);
  }
  std::string text(int c) const {
    const auto* t = sqlite3_column_text(s_, c);
    return t ? reinterpret_cast<const char*>(t) : "";
  }

 private:
  [[noreturn]] void fail(const char* what) const {
    throw InputError(fmt::format("history {}: {} failed: {}; if the file is damaged, move it "
                                 "away (mfv never replaces it) and a new history starts",
                                 file_.string(), what, sqlite3_errmsg(db_)));
  }
  sqlite3* db_;
  sqlite3_stmt* s_ = nullptr;
  fs::path file_;
};

void exec(sqlite3* db, const char* sql, const fs::path& file) {
  char* err = nullptr;
  if (sqlite3_exec(db, sql, nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string msg = err ? err : sqlite3_errmsg(db);
    sqlite3_free(err);
    throw InputError(fmt::format("history {}: {}; if the file is damaged or not an mfv history, "
                                 "move it away (mfv never replaces it) or give another --history",
                                 file.string(), msg));
  }
}

constexpr const char* kSchemaV1 = R"(
CREATE TABLE runs(
  id INTEGER PRIMARY KEY,
  generated_utc TEXT NOT NULL, suite TEXT NOT NULL, manifest TEXT NOT NULL, full INTEGER NOT NULL,
  commit_id TEXT NOT NULL, dirty INTEGER NOT NULL, status TEXT NOT NULL, failed INTEGER NOT NULL,
  cases INTEGER NOT NULL, wall_seconds REAL, cpu_seconds REAL, provenance TEXT NOT NULL);
CREATE TABLE quantities(
  id INTEGER PRIMARY KEY, case_id TEXT NOT NULL, quantity TEXT NOT NULL, sense INTEGER NOT NULL,
  UNIQUE(case_id, quantity));
CREATE TABLE vals(
  run INTEGER NOT NULL REFERENCES runs(id), quantity INTEGER NOT NULL REFERENCES quantities(id),
  value REAL, PRIMARY KEY(run, quantity)) WITHOUT ROWID;
CREATE TABLE verdicts(
  run INTEGER NOT NULL REFERENCES runs(id), kind TEXT NOT NULL, subject TEXT NOT NULL,
  verdict TEXT NOT NULL, PRIMARY KEY(run, kind, subject)) WITHOUT ROWID;
CREATE INDEX vals_by_quantity ON vals(quantity, run);
)";

/// A history's user_version that is not mfv's: negative, or 0 (someone else's database:
/// mfv writes its version as it creates a history), or newer than this mfv's schema.
void refuse_version(const fs::path& file, long version) {
  if (version <= 0)
    throw InputError(fmt::format("history '{}' is a SQLite database mfv did not write "
                                 "(user_version {}); give another --history (mfv never "
                                 "rewrites it)",
                                 file.string(), version));
  if (version > kHistorySchema)
    throw InputError(fmt::format("history '{}' has schema {}, newer than this mfv's {}; use a "
                                 "newer mfv or another --history",
                                 file.string(), version, kHistorySchema));
}

/// Creates a new history at `file` whole: its schema is written to a private file in the
/// same directory, which then takes the name with link() (renameat2 without replacing where
/// the file system has no hard links), so a second writer never sees a half-made history
/// (two nightly jobs creating one history at once: one saw a 0-byte file and refused it, the
/// other "database is locked"). Returns false when another writer's history took the name
/// first: that one is used.
bool create_history_whole(const fs::path& file) {
  std::string tmpl = (file.parent_path().empty() ? fs::path(".") : file.parent_path()) /
                     (".mfv-history-new-XXXXXX");
  const int fd = mkstemp(tmpl.data());
  if (fd < 0)
    throw InputError(fmt::format("history '{}' cannot be created ({}); give another --history "
                                 "or run with --no-history",
                                 file.string(), std::strerror(errno)));
  // mkstemp's file is the owner's alone (0600); a history is created as any file would be,
  // 0666 less the umask (read from /proc, since umask() can only be read by setting it).
  mode_t mask = 022;
  {
    std::ifstream status("/proc/self/status");
    for (std::string line; std::getline(status, line);)
      if (line.rfind("Umask:", 0) == 0) mask = static_cast<mode_t>(std::stoul(line.substr(6), nullptr, 8));
  }
  fchmod(fd, 0666 & ~mask);
  close(fd);
  const fs::path tmp = tmpl;
  struct Remove {
    fs::path p;
    ~Remove() {
      std::error_code ec;
      fs::remove(p, ec);
    }
  } remove_tmp{tmp};
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(tmp.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    const std::string msg = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    throw InputError(fmt::format("history '{}' cannot be created ({}); give another --history",
                                 file.string(), msg));
  }
  try {
    exec(db, "BEGIN", file);
    exec(db, kSchemaV1, file);
    exec(db, fmt::format("PRAGMA user_version = {}", kHistorySchema).c_str(), file);
    exec(db, "COMMIT", file);
  } catch (...) {
    sqlite3_close(db);
    throw;
  }
  sqlite3_close(db);
  if (link(tmp.c_str(), file.c_str()) == 0) return true;
  int why = errno;
  if (why == EEXIST) return false;
  if (why == EPERM || why == ENOTSUP || why == EOPNOTSUPP) {
    // No hard links here (some FUSE and FAT file systems): a rename that never replaces.
    if (renameat2(AT_FDCWD, tmp.c_str(), AT_FDCWD, file.c_str(), RENAME_NOREPLACE) == 0)
      return true;
    why = errno;
    if (why == EEXIST) return false;
  }
  throw InputError(fmt::format("history '{}' cannot be created ({}); give another --history "
                               "or run with --no-history",
                               file.string(), std::strerror(why)));
}

}  // namespace

HistoryStore::HistoryStore(const fs::path& file) : path_(file) {
  std::error_code ec;
  const auto st = fs::status(file, ec);
  if (st.type() != fs::file_type::not_found && st.type() != fs::file_type::regular)
    throw InputError(fmt::format("history '{}' exists and is not a regular file; give a file "
                                 "path for --history",
                                 file.string()));
  if (st.type() == fs::file_type::not_found) {
    const fs::path dir = file.parent_path().empty() ? fs::path(".") : file.parent_path();
    if (!fs::is_directory(dir, ec))
      throw InputError(fmt::format("history '{}': the directory '{}' does not exist; create it "
                                   "or give another --history",
                                   file.string(), dir.string()));
    // Made whole under its name, or another writer's made first: either way opened below
    // as an existing history, its header and version checked.
    create_history_whole(file);
  } else if (const auto size = fs::file_size(file, ec); !ec && size < 512) {
    // mfv writes a history's schema as it creates the file (a page of 4 KiB at least): a
    // shorter existing file is someone else's (an empty one made by `touch`, a stub), and a
    // file is taken as a history only where none exists.
    throw InputError(fmt::format("history '{}' exists but is not an mfv history ({} bytes; "
                                 "mfv creates its history files itself); move it away or give "
                                 "another --history",
                                 file.string(), size));
  }
  {
    // The version in the file's own header (bytes 60-63, big-endian), read before SQLite
    // opens it: opening a database recovers its hot journal or checkpoints its write-ahead
    // log, which rewrites someone else's file before mfv could tell it is not a history.
    std::ifstream in(file, std::ios::binary);
    unsigned char header[100] = {};
    in.read(reinterpret_cast<char*>(header), sizeof header);
    if (in.gcount() == static_cast<std::streamsize>(sizeof header) &&
        std::memcmp(header, "SQLite format 3", 16) == 0) {
      const std::int32_t version = static_cast<std::int32_t>(
          (std::uint32_t(header[60]) << 24) | (std::uint32_t(header[61]) << 16) |
          (std::uint32_t(header[62]) << 8) | std::uint32_t(header[63]));
      refuse_version(file, version);
    }
  }
  // Never created here: a new history was made whole above.
  if (sqlite3_open_v2(file.c_str(), &db_, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    const std::string msg = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    db_ = nullptr;
    throw InputError(fmt::format("history '{}' cannot be opened ({}); give another --history",
                                 file.string(), msg));
  }
  // Two nightly jobs on one file take turns instead of failing.
  sqlite3_busy_timeout(db_, 10000);
  try {
    // Reading the version reads the header: a file that is not SQLite fails here.
    Statement v(db_, "PRAGMA user_version", path_);
    v.step();
    const long version = v.integer(0);
    refuse_version(file, version);
    Statement check(db_, "PRAGMA quick_check", path_);
    if (check.step() && check.text(0) != "ok")
      throw InputError(fmt::format("history '{}' is damaged ({}); move it away (mfv never "
                                   "replaces it) and a new history starts",
                                   file.string(), check.text(0)));
    // Migrations from an older schema, one per version in a transaction each, go here when
    // there is a second schema (today every mfv history is version 1, kHistorySchema).
  } catch (...) {
    sqlite3_close(db_);
    db_ = nullptr;
    throw;
  }
}

HistoryStore::~HistoryStore() { sqlite3_close(db_); }

void HistoryStore::check_writable() {
  // The write lock append will take, taken and released now: a history another writer holds
  // past the busy timeout, or one on a read-only file or file system, fails before the first
  // case instead of after the last.
  // SQLite opens a file it may not write read-only without saying so, and takes the lock
  // without creating its journal: both are found here, not at the append.
  if (sqlite3_db_readonly(db_, "main") == 1)
    throw InputError(fmt::format("history '{}' cannot be written (the file is read-only for "
                                 "this user); make it writable, give another --history, or run "
                                 "with --no-history",
                                 path_.string()));
  const fs::path dir = path_.parent_path().empty() ? fs::path(".") : path_.parent_path();
  if (access(dir.c_str(), W_OK | X_OK) != 0)
    throw InputError(fmt::format("history '{}' cannot be written: its directory '{}' is not "
                                 "writable for this user, and SQLite writes its journal "
                                 "there; give another --history, or run with --no-history",
                                 path_.string(), dir.string()));
  if (sqlite3_exec(db_, "BEGIN IMMEDIATE", nullptr, nullptr, nullptr) != SQLITE_OK) {
    const std::string why = sqlite3_errmsg(db_);
    throw InputError(fmt::format("history '{}' cannot be written ({}); free it, give another "
                                 "--history, or run with --no-history",
                                 path_.string(), why));
  }
  sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
}

long HistoryStore::append(const json& results) {
  const RunRecord rec = run_record(results);
  const json& run = results.at("run");
  const json prov = run.value("provenance", json::object());
  exec(db_, "BEGIN IMMEDIATE", path_);
  try {
    Statement ins(db_,
                  "INSERT INTO runs(generated_utc, suite, manifest, full, commit_id, dirty, "
                  "status, failed, cases, wall_seconds, cpu_seconds, provenance) "
                  "VALUES(?,?,?,?,?,?,?,?,?,?,?,?)",
                  path_);
    const json suite = results.value("suite", json::object());
    const json regression = results.value("regression", json::object());
    ins.bind(1, run.value("generated_utc", std::string()))
        .bind(2, suite.value("name", std::string()))
        .bind(3, suite.value("manifest", std::string()))
        .bind(4, suite.value("full", false) ? 1 : 0)
        .bind(5, prov.value("commit", std::string("unknown")))
        .bind(6, prov.value("dirty", false) ? 1 : 0)
        .bind(7, regression.value("status", std::string()))
        .bind(8, regression.value("failed", 0))
        .bind(9, static_cast<int>(rec.order.size()))
        .bind(10, run.value("wall_seconds", NAN))
        .bind(11, run.value("cpu_seconds", NAN))
        .bind(12, prov.dump());
    ins.step();
    const long id = static_cast<long>(sqlite3_last_insert_rowid(db_));
    Statement q(db_,
                "INSERT INTO quantities(case_id, quantity, sense) VALUES(?,?,?) "
                "ON CONFLICT(case_id, quantity) DO UPDATE SET sense = excluded.sense "
                "RETURNING id",
                path_);
    Statement v(db_, "INSERT INTO vals(run, quantity, value) VALUES(?,?,?)", path_);
    // One value: its quantity's id (made on first sight), then the value under this run.
    auto record = [&](const std::string& case_id, const std::string& name, int sense,
                      double value) {
      q.bind(1, case_id).bind(2, name).bind(3, sense);
      q.step();
      const long qid = q.integer(0);
      while (q.step()) {
      }
      q.reset();
      v.bind(1, id).bind(2, qid).bind(3, value);
      v.step();
      v.reset();
    };
    for (const auto& [case_id, numbers] : rec.numbers)
      for (const auto& [name, n] : numbers) record(case_id, name, n.sense, n.value);
    for (const auto& [case_id, seconds] : rec.cpu_seconds)
      record(case_id, kCpuQuantity, 0, seconds);
    Statement w(db_, "INSERT INTO verdicts(run, kind, subject, verdict) VALUES(?,?,?,?)", path_);
    auto verdict_of = [&](const char* kind, const std::string& subject,
                          const std::string& verdict) {
      w.bind(1, id).bind(2, std::string(kind)).bind(3, subject).bind(4, verdict);
      w.step();
      w.reset();
    };
    for (const auto& [subject, verdict] : rec.case_verdicts)
      verdict_of("regression", subject, verdict);
    for (const auto& [subject, verdict] : rec.ledger_verdicts) verdict_of("ledger", subject, verdict);
    exec(db_, "COMMIT", path_);
    return id;
  } catch (...) {
    sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

std::vector<HistoryRun> HistoryStore::runs(int last) const {
  Statement s(db_,
              "SELECT id, generated_utc, suite, commit_id, status, dirty, full, failed, cases "
              "FROM runs ORDER BY id DESC LIMIT ?",
              path_);
  s.bind(1, last);
  std::vector<HistoryRun> out;
  while (s.step())
    out.push_back({s.integer(0), s.text(1), s.text(2), s.text(3), s.text(4), s.integer(5) != 0,
                   s.integer(6) != 0, static_cast<int>(s.integer(7)),
                   static_cast<int>(s.integer(8))});
  return out;
}

std::vector<HistoryPoint> HistoryStore::series(const std::string& case_id,
                                               const std::string& quantity, int last) const {
  Statement s(db_,
              "SELECT r.id, r.generated_utc, r.commit_id, v.value FROM vals v "
              "JOIN quantities q ON q.id = v.quantity JOIN runs r ON r.id = v.run "
              "WHERE q.case_id = ? AND q.quantity = ? ORDER BY r.id DESC LIMIT ?",
              path_);
  s.bind(1, case_id).bind(2, quantity).bind(3, last);
  std::vector<HistoryPoint> out;
  while (s.step()) out.push_back({s.integer(0), s.text(1), s.text(2), s.real(3)});
  std::reverse(out.begin(), out.end());
  return out;
}

std::vector<std::string> HistoryStore::quantities(const std::string& case_id) const {
  Statement s(db_, "SELECT quantity FROM quantities WHERE case_id = ? ORDER BY quantity", path_);
  s.bind(1, case_id);
  std::vector<std::string> out;
  while (s.step()) out.push_back(s.text(0));
  return out;
}

std::vector<std::string> HistoryStore::cases() const {
  Statement s(db_, "SELECT DISTINCT case_id FROM quantities ORDER BY case_id", path_);
  std::vector<std::string> out;
  while (s.step()) out.push_back(s.text(0));
  return out;
}

RunRecord HistoryStore::record(long run) const {
  RunRecord r;
  {
    Statement s(db_, "SELECT generated_utc, commit_id, dirty, suite FROM runs WHERE id = ?",
                path_);
    s.bind(1, run);
    if (!s.step())
      throw InputError(fmt::format("history {} has no run {}; `mfv history --runs` lists them",
                                   path_.string(), run));
    r.label = fmt::format("run {} of {}, {}, commit {}{}", run, path_.filename().string(),
                          s.text(0), s.text(1).substr(0, 12), s.integer(2) ? "+changes" : "");
    r.suite = s.text(3);
  }
  Statement v(db_,
              "SELECT q.case_id, q.quantity, q.sense, v.value FROM vals v "
              "JOIN quantities q ON q.id = v.quantity WHERE v.run = ?",
              path_);
  v.bind(1, run);
  while (v.step()) {
    if (v.text(1) == kCpuQuantity)
      r.cpu_seconds[v.text(0)] = v.real(3);
    else
      r.numbers[v.text(0)][v.text(1)] = {v.real(3), static_cast<int>(v.integer(2))};
  }
  Statement w(db_, "SELECT kind, subject, verdict FROM verdicts WHERE run = ? ORDER BY subject",
              path_);
  w.bind(1, run);
  while (w.step()) {
    if (w.text(0) == "regression") {
      r.case_verdicts[w.text(1)] = w.text(2);
      r.order.push_back(w.text(1));
    } else {
      r.ledger_verdicts[w.text(1)] = w.text(2);
    }
  }
  for (const auto& [id, numbers] : r.numbers)
    if (!r.case_verdicts.count(id)) r.order.push_back(id);
  return r;
}

std::optional<HistoryRun> HistoryStore::failing_since(const std::string& case_id,
                                                      long run) const {
  Statement s(db_,
              "SELECT r.id, r.generated_utc, r.suite, r.commit_id, r.status, r.dirty, r.full, "
              "r.failed, r.cases, w.verdict FROM runs r LEFT JOIN verdicts w ON w.run = r.id "
              "AND w.kind = 'regression' AND w.subject = ? WHERE r.suite = (SELECT suite FROM "
              "runs WHERE id = ?) AND r.id <= ? ORDER BY r.id DESC",
              path_);
  s.bind(1, case_id).bind(2, run).bind(3, run);
  std::optional<HistoryRun> first;
  while (s.step()) {
    if (s.text(9) != "FAIL") break;
    first = HistoryRun{s.integer(0), s.text(1), s.text(2), s.text(3), s.text(4),
                       s.integer(5) != 0, s.integer(6) != 0, static_cast<int>(s.integer(7)),
                       static_cast<int>(s.integer(8))};
  }
  return first;
}

std::vector<HistoryDrift> HistoryStore::drifts(long run, int window, double tolerance) const {
  // The window: the last `window` runs of the same suite up to `run`.
  Statement s(db_,
              "SELECT id FROM runs WHERE suite = (SELECT suite FROM runs WHERE id = ?) AND "
              "id <= ? ORDER BY id DESC LIMIT ?",
              path_);
  s.bind(1, run).bind(2, run).bind(3, window);
  std::vector<long> ids;
  while (s.step()) ids.push_back(s.integer(0));
  std::vector<HistoryDrift> out;
  if (ids.size() < 3) return out;  // two runs are diff's business, not a trend
  std::reverse(ids.begin(), ids.end());
  std::map<std::pair<std::string, std::string>, std::vector<double>> values;
  std::map<std::pair<std::string, std::string>, int> sense;
  Statement v(db_,
              "SELECT q.case_id, q.quantity, q.sense, v.value FROM vals v "
              "JOIN quantities q ON q.id = v.quantity WHERE v.run = ? AND q.sense != 0",
              path_);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    v.bind(1, ids[k]);
    while (v.step()) {
      auto& series = values[{v.text(0), v.text(1)}];
      series.resize(ids.size(), NAN);
      series[k] = v.real(3);
      sense[{v.text(0), v.text(1)}] = static_cast<int>(v.integer(2));
    }
    v.reset();
  }
  for (const auto& [key, series] : values) {
    const double first = series.front(), last = series.back();
    if (!std::isfinite(first) || !std::isfinite(last) || std::abs(first) < 1e-12) continue;
    const double rel = (last - first) / std::abs(first);
    const bool wrong_way = sense.at(key) < 0 ? rel > 0 : rel < 0;
    if (!wrong_way || !(std::abs(rel) > tolerance)) continue;
    // A creep: every step inside the tolerance (a jump is the night-to-night drift's).
    bool creep = true;
    for (std::size_t k = 1; k < series.size() && creep; ++k)
      if (std::isfinite(series[k]) && std::isfinite(series[k - 1]) &&
          std::abs(series[k] - series[k - 1]) > tolerance * std::abs(series[k - 1]))
        creep = false;
    if (!creep) continue;
    out.push_back({key.first, key.second, first, last, static_cast<int>(ids.size()),
                   fmt::format("{}: {} crept from {:.4g} to {:.4g} ({:+.1f} %) over the last {} "
                               "runs, each step within {:.0f} % {}",
                               key.first, key.second, first, last, 100 * rel, ids.size(),
                               100 * tolerance, sparkline(series))});
  }
  return out;
}

std::string sparkline(const std::vector<double>& values) {
  static const char* kBars[] = {"▁", "▂", "▃", "▄", "▅", "▆", "▇", "█"};
  double lo = INFINITY, hi = -INFINITY;
  for (double v : values)
    if (std::isfinite(v)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  std::string out;
  for (double v : values) {
    if (!std::isfinite(v)) {
      out += " ";
      continue;
    }
    const int k = hi > lo ? static_cast<int>(std::lround(7 * (v - lo) / (hi - lo))) : 3;
    out += kBars[std::clamp(k, 0, 7)];
  }
  return out;
}

}  // namespace mfv
