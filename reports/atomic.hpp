/// Atomic file and directory replacement: nothing half-written may replace a good report.
#pragma once
#include <filesystem>
#include <string>
#include <optional>
#include <string_view>
#include <vector>

namespace mfv {

/// Writes `content` to a temporary file next to `path`, flushes it to disk and renames it
/// over `path`, so readers (and a crash) see either the old or the new file, never a part.
/// On failure the temporary file is removed and std::runtime_error names the path and cause.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

/// Creates `root / rel` and every directory between them, but never `root` itself, and
/// returns `root / rel`. Report pages use it for their sub-directories: the report is written
/// into a staging directory that the signal handler removes while the computing thread may
/// still be writing; std::filesystem::create_directories would bring the staging directory
/// back, unmarked, for no later run to remove. Throws std::runtime_error when `root` is not
/// a directory or a component cannot be created.
std::filesystem::path make_report_subdir(const std::filesystem::path& root,
                                         const std::filesystem::path& rel);

/// A uniquely named temporary file next to `target` (`<target>.<tag>-<pid>-<n>`), created
/// empty and exclusively, for writers that insist on a file name of their own (VTK,
/// gnuplot). commit() renames it over `target`; otherwise the destructor removes it.
/// Being in the same directory as the target keeps the rename atomic (same filesystem).
class PendingFile {
 public:
  /// Throws std::runtime_error naming `target` if the file cannot be created.
  explicit PendingFile(std::filesystem::path target, std::string_view tag = "tmp");
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;
  ~PendingFile();

  const std::filesystem::path& path() const { return temp_; }
  const std::filesystem::path& target() const { return target_; }

  /// Renames the temporary file over the target; throws std::runtime_error naming both.
  void commit();

 private:
  std::filesystem::path target_, temp_;
  bool committed_ = false;
};

/// The marker file mfv writes into every report directory: "mfv-report 1", the suite, the
/// time, mfv's version and one "file <relative path>" line per file of the report. A target
/// directory is replaced only when it is absent, empty, or holds this marker.
inline constexpr const char* kReportMarker = ".mfv-report";

/// The marker of a staging directory from its creation until commit() ("mfv-staging 1", the
/// pid and the target): what lets a later run remove it after a SIGKILL, and nothing else.
inline constexpr const char* kStagingMarker = ".mfv-staging";

/// What a report directory's marker says; `files` are the paths mfv wrote, relative to it.
struct ReportMarker {
  std::string suite, time, version;
  std::vector<std::string> files;
};

/// Reads `dir`/.mfv-report; std::nullopt when there is none or it is not mfv's.
std::optional<ReportMarker> read_report_marker(const std::filesystem::path& dir);

/// Builds a whole report directory in `<parent>/.<name>.staging-<pid>` and, on commit(),
/// swaps it in for `<parent>/<name>` with one atomic exchange (renameat2 RENAME_EXCHANGE), so
/// there is no moment without a report at the path.
///
/// The constructor runs before the computation, so that a bad target fails in a second:
/// - the target must be absent, an empty directory, or a report mfv wrote (kReportMarker)
///   holding only files mfv wrote; anything else (a directory of the user's, a regular file, a
///   device, a symbolic link) throws InputError naming the path and the fix. `force` lets mfv
///   replace one of its own reports to which files were added, never anything else;
/// - `<parent>/.<name>.mfv-lock` is locked (flock) against a second writer of the target and
///   removed when this object goes;
/// - staging and old copies left by dead runs for this target are removed: only directories
///   named `.<name>.staging-<pid>` / `.<name>.old-<pid>` whose pid is not alive and that hold
///   mfv's marker (kStagingMarker, or a report's kReportMarker), or nothing but a marker's
///   temporary file (a run killed while marking it), or are empty. mfv removes such a
///   directory with its markers last, so a run killed while removing one leaves it marked;
/// - the staging directory is created, which proves the parent writable.
/// A run that fails before commit() leaves the previous report untouched; the destructor only
/// removes the staging directory. With install_staging_cleanup() a SIGINT, SIGTERM or SIGHUP
/// removes it too; after a SIGKILL it is hidden (a dot name) and removed by the next run.
class StagedDirectory {
 public:
  struct Options {
    bool force = false;
    std::string suite;  ///< recorded in the marker
  };
  explicit StagedDirectory(std::filesystem::path target) : StagedDirectory(std::move(target), Options{}) {}
  StagedDirectory(std::filesystem::path target, Options options);
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;
  ~StagedDirectory();

  /// Where to write the report's files until commit().
  const std::filesystem::path& path() const { return staging_; }
  const std::filesystem::path& target() const { return target_; }
  bool committed() const { return committed_; }

  /// Writes the marker (listing every file in the staging directory), checks the target
  /// again, and exchanges the staging directory with it (or renames it into place when there
  /// is none), then removes the previous report. Throws InputError if the target stopped
  /// being ours to replace, std::runtime_error naming both paths if the exchange fails.
  void commit();

 private:
  std::filesystem::path target_, staging_, lock_;
  Options options_;
  int lock_fd_ = -1;
  bool committed_ = false;
};

/// Checks that `target` may be replaced by a report (the rules of StagedDirectory) without
/// creating or locking anything; throws InputError naming the path and the fix.
void check_report_target(const std::filesystem::path& target, bool force);

/// Checks that a single output file (a .vtp, a baseline, a CTest script) may be written:
/// absent, or a regular file that `ours` recognises from its content as one mfv writes.
/// Throws InputError naming the path otherwise (a directory, device, link or foreign file).
void check_output_file(const std::filesystem::path& path, const std::string& what,
                       bool (*ours)(const std::string& head));

/// Blocks SIGINT, SIGTERM and SIGHUP in the calling thread (call it first in main, before
/// any other thread starts, so every thread inherits the mask) and starts a thread that, on
/// one of them, removes every live staging directory and then dies of the same signal. A
/// staging directory being committed is waited for, so a report is never left half-swapped.
void install_staging_cleanup();

}  // namespace mfv
