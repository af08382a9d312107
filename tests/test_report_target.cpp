/// A report target is replaced only when it is absent, empty or an mfv report: the data-loss
/// cases of issue 12 (a user's directory, file, device, link), the lock against a second
/// writer, dead runs' staging directories, and runs killed by SIGTERM and SIGKILL.
#include <csignal>
#include <map>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "methods/core/errors.hpp"
#include "reports/atomic.hpp"
#include "tests/temp_files.hpp"
#include "verify/manifest.hpp"

namespace mfv {
namespace {

namespace fs = std::filesystem;
using test::names_in;
using test::expect_refused;
using test::read_file;

struct TempDir : test::TempDir {
  TempDir() : test::TempDir("mfv-target") {}
};

/// Every file below `dir` with its content (links as "-> target").
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> s;
  for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator();
       ++it) {
    const auto rel = fs::relative(it->path(), dir).generic_string();
    if (it->is_symlink()) s[rel] = "-> " + fs::read_symlink(it->path()).string();
    else if (it->is_regular_file()) s[rel] = read_file(it->path());
  }
  return s;
}

/// A report as mfv writes it: staged, then committed.
void write_report(const fs::path& target, const std::string& text, bool force = false) {
  StagedDirectory staged(target, {force, "test"});
  test::write_text(staged.path() / "index.md", text);
  test::write_text(staged.path() / "plots" / "a.svg", "<svg/>");
  staged.commit();
}

TEST(ReportTarget, AbsentTargetGetsTheReportAndItsMarker) {
  TempDir dir;
  const auto target = dir.path() / "reports" / "run";
  write_report(target, "hello");
  EXPECT_EQ(read_file(target / "index.md"), "hello");
  const auto marker = read_report_marker(target);
  ASSERT_TRUE(marker);
  EXPECT_EQ(marker->suite, "test");
  EXPECT_EQ(marker->files, (std::vector<std::string>{"index.md", "plots/a.svg"}));
  EXPECT_FALSE(marker->time.empty());
  // No staging directory, old copy or lock file is left beside it.
  EXPECT_EQ(names_in(target.parent_path()), std::vector<std::string>{"run"});
}

TEST(ReportTarget, EmptyDirectoryAndEarlierReportAreReplaced) {
  TempDir dir;
  const auto target = dir.path() / "run";
  fs::create_directory(target);
  write_report(target, "first");
  write_report(target, "second");
  EXPECT_EQ(read_file(target / "index.md"), "second");
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"run"});
}

TEST(ReportTarget, UserDirectoryIsRefusedEvenWithForce) {
  TempDir dir;
  const auto target = dir.path() / "DIR";
  test::write_text(target / "user.txt", "precious");
  const auto before = snapshot(target);
  for (bool force : {false, true})
    expect_refused([&] { write_report(target, "report", force); }, target);
  EXPECT_EQ(snapshot(target), before);
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"DIR"});
}

TEST(ReportTarget, ReportWithAddedFilesNeedsForce) {
  TempDir dir;
  const auto target = dir.path() / "run";
  write_report(target, "first");
  test::write_text(target / "notes.txt", "mine");
  expect_refused([&] { write_report(target, "second"); }, target);
  EXPECT_EQ(read_file(target / "notes.txt"), "mine");
  EXPECT_EQ(read_file(target / "index.md"), "first");
  write_report(target, "second", /*force=*/true);
  EXPECT_EQ(read_file(target / "index.md"), "second");
  EXPECT_FALSE(fs::exists(target / "notes.txt"));
}

TEST(ReportTarget, NonDirectoriesAreNeverReplaced) {
  TempDir dir;
  const auto file = dir.path() / "file";
  test::write_text(file, "user data");
  const auto fifo = dir.path() / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto outside = dir.path() / "outside";
  test::write_text(outside / "keep.txt", "keep");
  const auto link = dir.path() / "link";
  fs::create_directory_symlink(outside, link);
  const auto dangling = dir.path() / "dangling";
  fs::create_symlink(dir.path() / "nowhere", dangling);
  for (const auto& p : {file, fifo, link, dangling})
    for (bool force : {false, true}) expect_refused([&] { write_report(p, "r", force); }, p);
  EXPECT_EQ(read_file(file), "user data");
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(link)));
  EXPECT_EQ(snapshot(outside), (std::map<std::string, std::string>{{"keep.txt", "keep"}}));
  EXPECT_EQ(names_in(dir.path()),
            (std::vector<std::string>{"dangling", "fifo", "file", "link", "outside"}));
}

TEST(ReportTarget, DeviceIsRefusedBeforeAnythingIsWritten) {
  // /dev/null is a character device on every Linux machine: refused before the parent is
  // touched (no lock file, no staging directory in /dev).
  expect_refused([] { StagedDirectory staged("/dev/null"); }, "/dev/null");
  EXPECT_TRUE(fs::is_character_file(fs::symlink_status("/dev/null")));
  EXPECT_FALSE(fs::exists("/dev/.null.mfv-lock"));
}

TEST(ReportTarget, DotAndEmptyNamesAreRefused) {
  for (const char* p : {".", "..", "a/..", ""})
    EXPECT_THROW(check_report_target(p, false), InputError) << p;
}

// F18: a lock file that is a symbolic link is named as one (the message said the directory
// was not writable), and the file it points at is never touched.
TEST(ReportTarget, ALockFileThatIsALinkIsNamedAndNotFollowed) {
  TempDir dir;
  test::write_text(dir.path() / "precious.txt", "mine");
  fs::create_symlink("precious.txt", dir.path() / ".run.mfv-lock");
  try {
    write_report(dir.path() / "run", "new");
    FAIL() << "a linked lock file was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("is a symbolic link"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_file(dir.path() / "precious.txt"), "mine");
  EXPECT_TRUE(fs::is_symlink(dir.path() / ".run.mfv-lock"));
  EXPECT_FALSE(fs::exists(dir.path() / "run"));
}

TEST(ReportTarget, SecondWriterIsRefusedUntilTheFirstIsDone) {
  TempDir dir;
  const auto target = dir.path() / "run";
  {
    StagedDirectory first(target);
    try {
      StagedDirectory second(target);
      ADD_FAILURE() << "a second writer was let in";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("another mfv run"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::is_directory(first.path()));  // the refusal did not touch the first
  }
  write_report(target, "after");
  EXPECT_EQ(read_file(target / "index.md"), "after");
}

TEST(ReportTarget, DeadRunsStagingIsCleanedAndNothingElse) {
  TempDir dir;
  const auto target = dir.path() / "run";
  // A dead run's staging directory (its marker) and old copy (the previous report's marker).
  test::write_text(dir.path() / ".run.staging-999999" / "index.md", "dead run");
  test::write_text(dir.path() / ".run.staging-999999" / kStagingMarker,
                   "mfv-staging 1\npid 999999\ntarget " + target.string() + "\n");
  // F18: a marker that is only a file of that name (no pid), or names another pid, is not
  // mfv's: the directory and what it holds stay.
  test::write_text(dir.path() / ".run.staging-999989" / kStagingMarker, "mfv-staging 1\n");
  test::write_text(dir.path() / ".run.staging-999989" / "thesis.tex", "a user's chapter");
  test::write_text(dir.path() / ".run.staging-999988" / kStagingMarker, "mfv-staging 1\npid 5\n");
  test::write_text(dir.path() / ".run.old-999998" / "index.md", "dead run");
  test::write_text(dir.path() / ".run.old-999998" / kReportMarker, "mfv-report 1\nsuite -\n");
  fs::create_directories(dir.path() / ".run.old-999996");  // empty: nothing to lose
  // Killed while marking: only the marker's temporary file (write_file_atomic's name).
  test::write_text(dir.path() / ".run.staging-999994" / (std::string(kStagingMarker) + ".tmp-999994-0"),
                   "mfv-stag");
  // A marker's temporary name beside a file of the user's does not make the directory ours.
  test::write_text(dir.path() / ".run.staging-999993" / (std::string(kStagingMarker) + ".tmp-1-0"), "");
  test::write_text(dir.path() / ".run.staging-999993" / "data.csv", "a user's file");
  // Killed in the moment after its signal thread's clean-up, while a page created its
  // sub-directory (the CI failure of 2026-12-05): unmarked, holding only empty directories.
  fs::create_directories(dir.path() / ".run.staging-999991" / "plots" / "part");
  // The same with a file in it is not ours to remove.
  test::write_text(dir.path() / ".run.staging-999990" / "plots" / "a.svg", "a user's plot");
  // A file that only bears a marker's name, not its content, is not a marker.
  test::write_text(dir.path() / ".run.staging-999992" / kReportMarker, "a user's notes");
  // Issue 26: names that only look like ours stay — no marker, or a live pid (1 is init).
  test::write_text(dir.path() / ".run.staging-999995" / "thesis.tex", "a user's directory");
  test::write_text(dir.path() / ".run.staging-1" / kStagingMarker, "mfv-staging 1\n");
  test::write_text(dir.path() / ".run.staging-1" / "index.md", "a live process's");
  test::write_text(dir.path() / ".run.staging-notes", "a user's file that only looks like ours");
  test::write_text(dir.path() / ".other.staging-999997" / "index.md", "another target's");
  write_report(target, "new");
  EXPECT_EQ(names_in(dir.path()),
            (std::vector<std::string>{".other.staging-999997", ".run.staging-1",
                                      ".run.staging-999988", ".run.staging-999989",
                                      ".run.staging-999990", ".run.staging-999992", ".run.staging-999993",
                                      ".run.staging-999995",
                                      ".run.staging-notes", "run"}));
  EXPECT_EQ(read_file(dir.path() / ".run.staging-999993" / "data.csv"), "a user's file");
  EXPECT_EQ(read_file(dir.path() / ".run.staging-999992" / kReportMarker), "a user's notes");
  EXPECT_EQ(read_file(dir.path() / ".run.staging-999995" / "thesis.tex"), "a user's directory");
  EXPECT_EQ(read_file(dir.path() / ".run.staging-999989" / "thesis.tex"), "a user's chapter");
  // The staging marker never reaches the report.
  EXPECT_FALSE(fs::exists(target / kStagingMarker));
}

TEST(ReportTarget, PagesNeverRecreateARemovedStagingDirectory) {
  TempDir dir;
  const auto root = dir.path() / "staging";
  fs::create_directory(root);
  EXPECT_EQ(make_report_subdir(root, "tables/cantilever"), root / "tables" / "cantilever");
  EXPECT_TRUE(fs::is_directory(root / "tables" / "cantilever"));
  EXPECT_EQ(make_report_subdir(root, "tables/cantilever"), root / "tables" / "cantilever");
  // The signal thread removed the staging directory: a page's sub-directory fails instead of
  // bringing it back unmarked.
  fs::remove_all(root);
  EXPECT_THROW(make_report_subdir(root, "plots"), std::runtime_error);
  EXPECT_FALSE(fs::exists(root));
  // A file where a directory belongs is an error, not silently kept.
  fs::create_directory(root);
  test::write_text(root / "plots", "a file");
  EXPECT_THROW(make_report_subdir(root, "plots/x"), std::runtime_error);
}

TEST(ReportTarget, AZombiesStagingIsCleaned) {
  // Issue 26: a rank killed under mpiexec stays a zombie until pid 1 reaps it; it writes
  // nothing more, so its staging directory is a dead run's.
  TempDir dir;
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ASSERT_GT(child, 0);
  ::usleep(100000);  // the child has exited and, unreaped, is a zombie
  const auto staging = dir.path() / fmt::format(".run.staging-{}", child);
  test::write_text(staging / kStagingMarker, fmt::format("mfv-staging 1\npid {}\n", child));
  test::write_text(staging / "index.md", "a killed rank's");
  write_report(dir.path() / "run", "new");
  EXPECT_FALSE(fs::exists(staging));
  ::waitpid(child, nullptr, 0);
}

TEST(ReportTarget, AStagingDirectoryIsMarkedFromItsCreation) {
  TempDir dir;
  StagedDirectory staged(dir.path() / "run");
  EXPECT_TRUE(fs::is_regular_file(staged.path() / kStagingMarker));
}

TEST(ReportTarget, CommitChecksTheTargetAgain) {
  TempDir dir;
  const auto target = dir.path() / "run";
  write_report(target, "first");
  StagedDirectory staged(target);
  test::write_text(staged.path() / "index.md", "second");
  test::write_text(target / "added-while-running.txt", "mine");  // the user, meanwhile
  expect_refused([&] { staged.commit(); }, target);
  EXPECT_EQ(read_file(target / "index.md"), "first");
  EXPECT_EQ(read_file(target / "added-while-running.txt"), "mine");
}

/// Forks a child that stages a report of `target` (after install_staging_cleanup when
/// `cleanup`) and waits; returns its pid once the staging directory is written.
pid_t stage_in_child(const fs::path& target, bool cleanup) {
  int ready[2];
  if (::pipe(ready) != 0) return -1;
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(ready[0]);
    if (cleanup) install_staging_cleanup();
    StagedDirectory staged(target);
    test::write_text(staged.path() / "index.md", "half-written");
    const char byte = 1;
    if (::write(ready[1], &byte, 1) != 1) ::_exit(3);
    for (;;) ::pause();
  }
  ::close(ready[1]);
  char byte = 0;
  const bool ok = ::read(ready[0], &byte, 1) == 1;
  ::close(ready[0]);
  return ok ? pid : -1;
}

TEST(ReportTarget, TerminatedRunLeavesThePreviousReportAndNoStaging) {
  TempDir dir;
  const auto target = dir.path() / "run";
  write_report(target, "previous");
  const auto before = snapshot(target);
  const pid_t pid = stage_in_child(target, /*cleanup=*/true);
  ASSERT_GT(pid, 0);
  EXPECT_EQ(names_in(dir.path()).size(), 3u);  // run, its lock and the child's staging
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
  EXPECT_EQ(snapshot(target), before);
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"run"});
}

TEST(ReportTarget, KilledRunLeavesThePreviousReportAndTheNextRunCleansUp) {
  TempDir dir;
  const auto target = dir.path() / "run";
  write_report(target, "previous");
  const auto before = snapshot(target);
  const pid_t pid = stage_in_child(target, /*cleanup=*/false);
  ASSERT_GT(pid, 0);
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_EQ(snapshot(target), before);
  // What a SIGKILL leaves is hidden (dot names) and is ours to remove on the next run.
  for (const auto& n : names_in(dir.path())) EXPECT_TRUE(n == "run" || n.front() == '.') << n;
  write_report(target, "next");
  EXPECT_EQ(read_file(target / "index.md"), "next");
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"run"});
}

bool starts_with_ours(const std::string& head) { return head.rfind("# ours", 0) == 0; }

TEST(OutputFile, OnlyAbsentOrOwnFilesMayBeWritten) {
  TempDir dir;
  const auto p = dir.path() / "out.txt";
  EXPECT_NO_THROW(check_output_file(p, "output", starts_with_ours));
  test::write_text(p, "# ours\n");
  EXPECT_NO_THROW(check_output_file(p, "output", starts_with_ours));
  test::write_text(p, "the user's\n");
  expect_refused([&] { check_output_file(p, "output", starts_with_ours); }, p);
  expect_refused([&] { check_output_file(dir.path(), "output", starts_with_ours); }, dir.path());
  expect_refused([] { check_output_file("/dev/null", "output", starts_with_ours); }, "/dev/null");
}

TEST(SuiteName, IsANameNeverAPath) {
  TempDir dir;
  for (const std::string name : {"../victim", "a/b", "/abs", "..", ".hidden", ""}) {
    const auto m = dir.path() / "m.toml";
    test::write_text(m, "[suite]\nname = \"" + name +
                       "\"\n[[case]]\nid = \"a\"\nproblem = \"laplace-tanh\"\nmethod = \"fem\"\n"
                       "nodes = [11]\n");
    EXPECT_THROW(load_manifest(m), InputError) << name;
  }
}

}  // namespace
}  // namespace mfv
