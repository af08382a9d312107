#include "reports/atomic.hpp"

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <ctime>
#include <fstream>
#include <mutex>
#include <set>
#include <thread>
#include <stdexcept>
#include <system_error>

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

#include "methods/core/errors.hpp"
#include "methods/core/signal_cleanup.hpp"
#include "reports/markdown.hpp"

namespace mfv {

namespace fs = std::filesystem;

namespace {

std::string errno_text(int err) { return std::generic_category().message(err); }

/// Closes a descriptor on every path out of write_file_atomic, including exceptions.
class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }
  /// Closes now and returns the error, because close() can report a failed write-back.
  int close() {
    const int rc = ::close(fd_);
    fd_ = -1;
    return rc == 0 ? 0 : errno;
  }

 private:
  int fd_;
};

}  // namespace

PendingFile::PendingFile(fs::path target, std::string_view tag) : target_(std::move(target)) {
  if (!target_.has_filename())
    throw std::runtime_error(fmt::format("cannot write '{}': the path names no file",
                                         target_.string()));
  const std::string stem = fmt::format("{}.{}-{}-", target_.string(), tag, ::getpid());
  // O_EXCL makes the name ours alone; a clash (another thread, or a stale file left by a
  // crashed process with a recycled pid) just moves on to the next number.
  for (int n = 0; n < 10000; ++n) {
    fs::path candidate = stem + std::to_string(n);
    const int fd = ::open(candidate.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      ::close(fd);
      temp_ = std::move(candidate);
      return;
    }
    if (errno != EEXIST)
      throw std::runtime_error(fmt::format("cannot create a temporary file for '{}': {}",
                                           target_.string(), errno_text(errno)));
  }
  throw std::runtime_error(fmt::format(
      "cannot create a temporary file for '{}': too many stale '{}*' files", target_.string(),
      stem));
}

PendingFile::~PendingFile() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove(temp_, ignored);
  }
}

void PendingFile::commit() {
  std::error_code ec;
  fs::rename(temp_, target_, ec);
  if (ec)
    throw std::runtime_error(fmt::format("cannot move '{}' into place as '{}': {}",
                                         temp_.string(), target_.string(), ec.message()));
  committed_ = true;
}

void write_file_atomic(const fs::path& path, std::string_view content) {
  PendingFile temp(path);
  const auto fail = [&](int err) {
    return std::runtime_error(fmt::format("cannot write '{}': {}", path.string(), errno_text(err)));
  };
  FileDescriptor fd(::open(temp.path().c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC));
  if (fd.get() < 0) throw fail(errno);
  const char* data = content.data();
  std::size_t left = content.size();
  while (left > 0) {
    const ssize_t n = ::write(fd.get(), data, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw fail(errno);
    }
    data += n;
    left -= static_cast<std::size_t>(n);
  }
  // Without fsync a crash shortly after the rename can leave an empty file on some
  // filesystems, which is exactly the half-written report this function exists to prevent.
  if (::fsync(fd.get()) != 0) throw fail(errno);
  if (const int err = fd.close(); err != 0) throw fail(err);
  temp.commit();
}

namespace {

std::string what_is(fs::file_type t) {
  switch (t) {
    case fs::file_type::regular: return "a regular file";
    case fs::file_type::symlink: return "a symbolic link";
    case fs::file_type::block: return "a block device";
    case fs::file_type::character: return "a character device";
    case fs::file_type::fifo: return "a named pipe";
    case fs::file_type::socket: return "a socket";
    case fs::file_type::directory: return "a directory";
    default: return "not a regular file or directory";
  }
}

/// "file.md", "plots/a.svg", …: every non-directory entry below `dir`, links not followed.
std::vector<std::string> files_below(const fs::path& dir) {
  std::vector<std::string> files;
  for (auto it = fs::recursive_directory_iterator(dir); it != fs::recursive_directory_iterator();
       ++it) {
    if (it->is_directory(/*follows no link*/) && !it->is_symlink()) continue;
    files.push_back(fs::relative(it->path(), dir).generic_string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

/// The live staging directories of this process, for the signal thread. A process-wide
/// registry is unavoidable here: a signal names no object.
struct StagingRegistry {
  std::mutex mutex;
  std::set<fs::path> live;   ///< staging directories
  std::set<fs::path> locks;  ///< lock files
  static StagingRegistry& get() {
    static StagingRegistry r;
    return r;
  }
};

bool is_pid_suffix(const std::string& s) {
  return !s.empty() && s.size() <= 9 &&
         std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

/// A staging marker as mfv writes it for this directory: "mfv-staging 1" and the pid of the
/// directory's suffix (a marker that is only a file of that name, or names another pid, is
/// not taken for mfv's: the directory stays, with what it holds; F18). The target is the
/// directory's name already, and may have been spelled another way by the dead run.
bool staging_marker_is_ours(const fs::path& dir, const std::string& pid) {
  std::error_code ec;
  const fs::path m = dir / kStagingMarker;
  if (fs::symlink_status(m, ec).type() != fs::file_type::regular || fs::file_size(m, ec) > 4096)
    return false;
  std::ifstream in(m);
  std::string first, pid_line;
  std::getline(in, first);
  std::getline(in, pid_line);
  return first == "mfv-staging 1" && pid_line == "pid " + pid;
}

/// Whether the process `pid` (decimal) is alive. Our own pid counts as dead: a directory
/// named after it before we created ours was left by an earlier process of that pid.
bool pid_alive(const std::string& pid) {
  const long p = std::stol(pid);
  if (p <= 0 || p == ::getpid()) return false;
  if (::kill(static_cast<pid_t>(p), 0) != 0 && errno != EPERM) return false;
  // A zombie writes nothing more: a rank killed under mpiexec is reparented to pid 1, which
  // in a container may not reap it for a while, and its directory must not outlive that.
  std::ifstream stat(fmt::format("/proc/{}/stat", p));
  std::string line;
  if (std::getline(stat, line)) {
    const auto paren = line.rfind(')');  // the command name may hold spaces and parentheses
    if (paren != std::string::npos && paren + 2 < line.size() &&
        (line[paren + 2] == 'Z' || line[paren + 2] == 'X'))
      return false;
  }
  return true;
}

/// The temporary file write_file_atomic() writes a marker through (`<marker>.tmp-<pid>-<n>`):
/// what a run killed while marking a directory leaves in it.
bool is_marker_temp(const std::string& name) {
  for (const char* marker : {kStagingMarker, kReportMarker})
    if (name.rfind(std::string(marker) + ".tmp-", 0) == 0) return true;
  return false;
}

/// A marker or a marker's temporary file.
bool is_marker_entry(const std::string& name) {
  return name == kStagingMarker || name == kReportMarker || is_marker_temp(name);
}

/// Removes a staging or old directory of ours with its markers last, so that a run killed
/// part way (SIGKILL after SIGTERM, as mpiexec does) leaves a directory that is still marked
/// as mfv's and that the next run therefore removes.
void remove_marked_last(const fs::path& dir) {
  std::error_code ignored;
  std::vector<fs::path> markers;
  for (auto it = fs::directory_iterator(dir, ignored); !ignored && it != fs::directory_iterator();
       it.increment(ignored)) {
    if (is_marker_entry(it->path().filename().string())) markers.push_back(it->path());
    else fs::remove_all(it->path(), ignored);
  }
  for (const auto& m : markers) fs::remove(m, ignored);
  fs::remove_all(dir, ignored);
}

/// An unmarked directory a dead run may have left: nothing in it but empty directories and
/// markers' temporary files (a run killed while marking it, or a page creating its
/// sub-directory in the moment between the signal thread's clean-up and the process's end).
/// Removing it loses no file; anything else in it keeps it.
bool only_empty_dirs_and_marker_temps(const fs::path& dir) {
  std::error_code ec;
  for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
       it.increment(ec)) {
    const auto type = it->symlink_status(ec).type();
    if (ec) return false;
    if (type == fs::file_type::directory) {
      if (!only_empty_dirs_and_marker_temps(it->path())) return false;
    } else if (type != fs::file_type::regular ||
               !is_marker_temp(it->path().filename().string())) {
      return false;
    }
  }
  return !ec;
}

}  // namespace

std::optional<ReportMarker> read_report_marker(const fs::path& dir) {
  const fs::path file = dir / kReportMarker;
  std::error_code ec;
  if (fs::symlink_status(file, ec).type() != fs::file_type::regular) return std::nullopt;
  std::ifstream in(file);
  std::string line;
  if (!std::getline(in, line) || line != "mfv-report 1") return std::nullopt;
  ReportMarker m;
  while (std::getline(in, line)) {
    const auto space = line.find(' ');
    if (space == std::string::npos) continue;
    const std::string key = line.substr(0, space), value = line.substr(space + 1);
    if (key == "suite") m.suite = value;
    else if (key == "time") m.time = value;
    else if (key == "version") m.version = value;
    else if (key == "file") m.files.push_back(value);
  }
  return m;
}

void check_report_target(const fs::path& target_in, bool force) {
  fs::path target = target_in;
  if (!target.has_filename()) target = target.parent_path();
  const std::string name = target.filename().string();
  if (target.empty() || name == "." || name == "..")
    throw InputError(fmt::format(
        "report directory '{}' names no directory of its own; give a new or empty directory, "
        "e.g. 'reports/run'", target_in.string()));
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(target, ec);
  if (ec && ec != std::errc::no_such_file_or_directory)
    throw InputError(fmt::format("cannot inspect report directory '{}': {}", target.string(),
                                 ec.message()));
  if (st.type() == fs::file_type::not_found) return;
  if (st.type() != fs::file_type::directory)
    throw InputError(fmt::format(
        "report directory '{}' exists and is {}; mfv never replaces it{}: give a new or empty "
        "directory, or an earlier mfv report",
        target.string(), what_is(st.type()),
        st.type() == fs::file_type::symlink ? " (nor what it points to)" : ""));
  std::vector<std::string> present;
  try {
    present = files_below(target);
  } catch (const fs::filesystem_error& e) {
    throw InputError(fmt::format("cannot list report directory '{}': {}", target.string(),
                                 e.code().message()));
  }
  const auto marker = read_report_marker(target);
  if (!marker) {
    bool empty = fs::is_empty(target, ec);
    if (empty) return;
    std::string legacy;
    {
      std::ifstream index(target / "index.md");
      std::string first;
      if (std::getline(index, first) && first.rfind("# mfv ", 0) == 0)
        legacy = " (it looks like a report of an mfv older than the marker: remove it yourself "
                 "if it is)";
    }
    throw InputError(fmt::format(
        "report directory '{}' is not empty and is not an mfv report (no {} marker; it holds "
        "'{}'{}){}; mfv never replaces it: give a new or empty directory, e.g. '{}'",
        target.string(), kReportMarker, present.empty() ? "empty folders" : present.front(),
        present.size() > 1 ? fmt::format(" and {} more", present.size() - 1) : "", legacy,
        (target / "mfv-report").string()));
  }
  const std::set<std::string> ours(marker->files.begin(), marker->files.end());
  std::vector<std::string> foreign;
  for (const auto& f : present)
    if (f != kReportMarker && !ours.count(f)) foreign.push_back(f);
  if (!foreign.empty() && !force)
    throw InputError(fmt::format(
        "report directory '{}' is an mfv report (suite '{}', {}) but holds {} file(s) mfv did not "
        "write, e.g. '{}'; move them out, or pass --force to replace the report with them",
        target.string(), marker->suite, marker->time, foreign.size(), foreign.front()));
  // --force replaces what a user added, but never a database (a run history kept in the
  // report directory: every recorded run would go with it).
  for (const auto& f : foreign) {
    // A regular file only: opening a FIFO left in the report would block.
    if (!fs::is_regular_file(fs::symlink_status(target / f, ec))) continue;
    std::ifstream in(target / f, std::ios::binary);
    char head[16] = {};
    if (in.read(head, sizeof head) &&
        std::string(head, sizeof head) == std::string("SQLite format 3\0", 16))
      throw InputError(fmt::format(
          "report directory '{}' holds '{}', a SQLite database (a run history?); --force never "
          "deletes one: move it out of the report directory (the history's place is beside "
          "it, '{}.history.sqlite')",
          target.string(), f, target.string()));
  }
}

void check_output_file(const fs::path& path, const std::string& what,
                       bool (*ours)(const std::string& head)) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(path, ec);
  if (st.type() == fs::file_type::not_found) {
    // Checked before any computation: the file is written next to itself (a temporary and a
    // rename), so its directory must exist and be writable now, not after an hour's run.
    const fs::path dir = path.parent_path().empty() ? fs::path(".") : path.parent_path();
    if (!fs::is_directory(dir, ec))
      throw InputError(fmt::format("{} '{}': the directory '{}' does not exist; create it or give "
                                   "another path",
                                   what, path.string(), dir.string()));
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
      throw InputError(fmt::format("{} '{}': the directory '{}' is not writable ({}); give "
                                   "another path",
                                   what, path.string(), dir.string(), errno_text(errno)));
    return;
  }
  if (st.type() != fs::file_type::regular)
    throw InputError(fmt::format("{} '{}' exists and is {}; mfv never replaces it: give another "
                                 "file name",
                                 what, path.string(), what_is(st.type())));
  std::ifstream in(path, std::ios::binary);
  std::string head(512, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (!head.empty() && !ours(head))
    throw InputError(fmt::format("{} '{}' exists and is not a file mfv wrote; mfv never replaces "
                                 "it: give another file name, or move it away",
                                 what, path.string()));
}

StagedDirectory::StagedDirectory(fs::path target, Options options)
    : target_(std::move(target)), options_(std::move(options)) {
  if (!target_.has_filename()) target_ = target_.parent_path();  // "reports/run/"
  check_report_target(target_, options_.force);
  const fs::path parent = target_.parent_path();
  const std::string name = target_.filename().string();
  std::error_code ec;
  if (!parent.empty()) {
    fs::create_directories(parent, ec);
    if (ec || !fs::is_directory(parent))
      throw InputError(fmt::format("cannot create the directory '{}' for report '{}': {}",
                                   parent.string(), target_.string(),
                                   ec ? ec.message() : "it exists and is not a directory"));
  }
  const fs::path dir = parent.empty() ? fs::path(".") : parent;
  lock_ = dir / fmt::format(".{}.mfv-lock", name);
  // The lock file is removed on release, so a file locked here may have been unlinked (and
  // replaced by a newer one) between open and flock: lock again until the path is ours.
  for (int attempt = 0; lock_fd_ < 0; ++attempt) {
    const int fd = ::open(lock_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0666);
    if (fd < 0) {
      const int err = errno;
      struct stat st {};
      // O_NOFOLLOW refuses a link with ELOOP: name what it is (F18: the message said the
      // directory was not writable), and that mfv never follows or removes it.
      if (err == ELOOP && ::lstat(lock_.c_str(), &st) == 0 && S_ISLNK(st.st_mode))
        throw InputError(fmt::format("the lock file '{}' of report '{}' is a symbolic link, "
                                     "which mfv never makes, follows or removes; remove the "
                                     "link or choose another report directory",
                                     lock_.string(), target_.string()));
      if (err == ENXIO || err == EISDIR || (::lstat(lock_.c_str(), &st) == 0 && !S_ISREG(st.st_mode)))
        throw InputError(fmt::format("the lock file '{}' of report '{}' is {}, not a file of "
                                     "mfv's; remove it or choose another report directory",
                                     lock_.string(), target_.string(),
                                     ::lstat(lock_.c_str(), &st) == 0 && S_ISDIR(st.st_mode)
                                         ? "a directory"
                                         : "a special file"));
      throw InputError(fmt::format("cannot write into '{}' for report '{}': {}; choose a writable "
                                   "report directory",
                                   dir.string(), target_.string(), errno_text(err)));
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      ::close(fd);
      throw InputError(
          err == EWOULDBLOCK
              ? fmt::format("another mfv run is writing the report '{}'; wait for it to finish "
                            "or choose another report directory",
                            target_.string())
              : fmt::format("cannot lock '{}': {}", lock_.string(), errno_text(err)));
    }
    struct stat held {}, named {};
    if (::fstat(fd, &held) == 0 && ::stat(lock_.c_str(), &named) == 0 &&
        held.st_dev == named.st_dev && held.st_ino == named.st_ino) {
      lock_fd_ = fd;
    } else {
      ::close(fd);
      if (attempt > 100)
        throw InputError(fmt::format("cannot lock '{}': it keeps being replaced", lock_.string()));
    }
  }
  // Under the lock no other live run writes this target; a staging or old copy of it left by
  // a dead run is removed, but only one that mfv's markers say is ours (a staging directory
  // holds kStagingMarker from its creation, an old copy the previous report's kReportMarker)
  // and whose pid is not alive: a directory of the user's that only looks like ours stays.
  const std::string stage_prefix = fmt::format(".{}.staging-", name);
  const std::string old_prefix = fmt::format(".{}.old-", name);
  try {
    for (const auto& e : fs::directory_iterator(dir)) {
      const std::string n = e.path().filename().string();
      for (const auto& prefix : {stage_prefix, old_prefix}) {
        if (n.rfind(prefix, 0) != 0 || !is_pid_suffix(n.substr(prefix.size())) ||
            e.symlink_status().type() != fs::file_type::directory)
          continue;
        if (pid_alive(n.substr(prefix.size()))) continue;
        std::error_code ignored;
        if (staging_marker_is_ours(e.path(), n.substr(prefix.size())) ||
            read_report_marker(e.path())) {
          remove_marked_last(e.path());
          continue;
        }
        // Unmarked: ours only if it holds nothing but markers' temporary files and empty
        // directories; then nothing but those is removed (remove_all of a tree with no file).
        if (only_empty_dirs_and_marker_temps(e.path())) fs::remove_all(e.path(), ignored);
      }
    }
  } catch (const fs::filesystem_error&) {
    // An unlistable parent fails below, where the staging directory is created.
  }
  staging_ = parent / fmt::format("{}{}", stage_prefix, ::getpid());
  {
    auto& reg = StagingRegistry::get();
    std::lock_guard<std::mutex> hold(reg.mutex);
    reg.live.insert(staging_);
    reg.locks.insert(lock_);
  }
  const bool created = fs::create_directory(staging_, ec) && !ec;
  if (created) {
    // Marks the directory as mfv's from its first moment, for the clean-up of a later run
    // should this one be killed.
    try {
      write_file_atomic(staging_ / kStagingMarker,
                        fmt::format("mfv-staging 1\npid {}\ntarget {}\n", ::getpid(), target_.string()));
    } catch (const std::exception& e) {
      fs::remove_all(staging_, ec);
      ec = std::make_error_code(std::errc::io_error);
    }
  }
  if (!created || ec) {
    {
      auto& reg = StagingRegistry::get();
      std::lock_guard<std::mutex> hold(reg.mutex);
      reg.live.erase(staging_);
      reg.locks.erase(lock_);
    }
    ::unlink(lock_.c_str());
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw InputError(fmt::format("cannot create the staging directory '{}' for report '{}': {}",
                                 staging_.string(), target_.string(),
                                 ec ? ec.message() : "it exists"));
  }
}

StagedDirectory::~StagedDirectory() {
  {
    auto& reg = StagingRegistry::get();
    std::lock_guard<std::mutex> hold(reg.mutex);
    if (!committed_) remove_marked_last(staging_);
    reg.live.erase(staging_);
    if (lock_fd_ >= 0) {
      ::unlink(lock_.c_str());  // while still held: a run that opened it re-checks the inode
      ::close(lock_fd_);
    }
    reg.locks.erase(lock_);
  }
}

void StagedDirectory::commit() {
  if (committed_)
    throw std::logic_error(fmt::format("'{}' was already committed", target_.string()));
  // The signal thread waits while the swap is under way: never half a swap.
  auto& reg = StagingRegistry::get();
  std::lock_guard<std::mutex> hold(reg.mutex);
  std::string marker = fmt::format("mfv-report 1\nsuite {}\ntime {}\nversion {}\n",
                                   options_.suite.empty() ? "-" : options_.suite,
                                   utc_now("%Y-%m-%dT%H:%M:%SZ"),
                                   MFV_VERSION);
  for (const auto& f : files_below(staging_))
    if (!is_marker_entry(f)) marker += fmt::format("file {}\n", f);
  // The report's own marker takes the staging marker's place; written first, so the
  // directory is marked at every moment.
  write_file_atomic(staging_ / kReportMarker, marker);
  std::error_code gone;
  fs::remove(staging_ / kStagingMarker, gone);
  // Someone may have put files into the target while we computed: check again.
  check_report_target(target_, options_.force);
  std::error_code ec;
  const bool had_previous = fs::exists(fs::symlink_status(target_, ec));
  if (had_previous) {
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, target_.c_str(), RENAME_EXCHANGE) == 0) {
      committed_ = true;
      // The staging name now holds the previous report (ours, or an empty directory).
      remove_marked_last(staging_);
      return;
    }
    if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP)
      throw std::runtime_error(fmt::format("cannot swap '{}' into place as '{}': {}",
                                           staging_.string(), target_.string(),
                                           errno_text(errno)));
    // A filesystem without the exchange: move the old report aside first (a short moment
    // without a report at the path, never a mix of two).
    const fs::path old = target_.parent_path() /
                         fmt::format(".{}.old-{}", target_.filename().string(), ::getpid());
    fs::remove_all(old, ec);
    fs::rename(target_, old, ec);
    if (ec)
      throw std::runtime_error(fmt::format("cannot move the previous '{}' aside: {}",
                                           target_.string(), ec.message()));
    fs::rename(staging_, target_, ec);
    if (ec) {
      std::error_code back;
      fs::rename(old, target_, back);
      throw std::runtime_error(fmt::format("cannot move '{}' into place as '{}': {}{}",
                                           staging_.string(), target_.string(), ec.message(),
                                           back ? fmt::format("; the previous report is left in '{}'",
                                                              old.string())
                                                : ""));
    }
    committed_ = true;
    remove_marked_last(old);
    return;
  }
  fs::rename(staging_, target_, ec);
  if (ec)
    throw std::runtime_error(fmt::format("cannot move '{}' into place as '{}': {}",
                                         staging_.string(), target_.string(), ec.message()));
  committed_ = true;
}

fs::path make_report_subdir(const fs::path& root, const fs::path& rel) {
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(root, ec)))
    throw std::runtime_error(fmt::format(
        "cannot create '{}' in the report directory '{}': it is not a directory (a run being "
        "stopped removes its staging directory)", rel.string(), root.string()));
  fs::path path = root;
  for (const auto& part : rel) {
    if (part.empty() || part == ".") continue;
    path /= part;
    fs::create_directory(path, ec);
    if (ec)
      throw std::runtime_error(
          fmt::format("cannot create the directory '{}': {}", path.string(), ec.message()));
  }
  return path;
}

void install_staging_cleanup() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  std::thread([set] {
    int sig = 0;
    if (sigwait(&set, &sig) != 0) return;
    // First what the computation registered (an external solver's process group, then its
    // case directory), then the staging directories; the process dies right after.
    SignalCleanups::get().run_all_and_hold();
    {
      auto& reg = StagingRegistry::get();
      std::lock_guard<std::mutex> hold(reg.mutex);
      // A page may create a sub-directory between the listing and the final rmdir (the
      // computing thread runs on); the staging directory itself is never re-created
      // (make_report_subdir), so a few passes leave nothing.
      for (const auto& dir : reg.live) {
        std::error_code ec;
        for (int pass = 0; pass < 20 && fs::exists(fs::symlink_status(dir, ec)); ++pass)
          remove_marked_last(dir);
      }
      for (const auto& lock : reg.locks) ::unlink(lock.c_str());
      reg.live.clear();
      reg.locks.clear();
      // Die of the same signal, with the registry held so no commit starts afterwards.
      std::signal(sig, SIG_DFL);
      pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
      ::raise(sig);
    }
    ::_exit(128 + sig);
  }).detach();
}

}  // namespace mfv
