#include "cli/atomic_file.hpp"

#include "cli/errors.hpp"
#include "text/file.hpp"
#include "text/shown.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

#include <fcntl.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

namespace humandyn::cli {

namespace {

[[noreturn]] void fail(const std::string& path, const char* what) {
  throw InputError(fmt::format("{}: {}: {}", text::shown(path), what, std::strerror(errno)));
}

// A name beside `path` that no other file has: mkstemp's.
int make_named_temp(const std::string& path, std::string& temp_path) {
  std::string pattern = path + ".tmp-XXXXXX";
  const int fd = ::mkstemp(pattern.data());
  if (fd >= 0) {
    ::fchmod(fd, 0644);
    temp_path = std::move(pattern);
  }
  return fd;
}

// `path` with its symbolic links followed (as the shell's `>` follows them), up to 40 of them.
std::string follow_links(const std::string& path) {
  namespace fs = std::filesystem;
  fs::path p = path;
  std::error_code ec;
  for (int hops = 0; fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
    if (hops == 40) throw InputError(text::shown(path) + ": too many levels of symbolic links");
    const fs::path to = fs::read_symlink(p, ec);
    if (ec) throw InputError(fmt::format("{}: cannot read the symbolic link: {}", text::shown(path), ec.message()));
    p = to.is_absolute() ? to : p.parent_path() / to;
  }
  return p.string();
}

// Whether `path` names what the open descriptor `fd` is on, whatever it is (a file, a pipe, a terminal,
// /dev/null): stat follows every link, /dev/stdout's and /proc/self/fd/2's too.
bool is_stream(int fd, const std::string& path) {
  struct stat st {};
  struct stat stream {};
  return ::fstat(fd, &stream) == 0 && ::stat(path.c_str(), &st) == 0 && st.st_dev == stream.st_dev &&
         st.st_ino == stream.st_ino;
}

// Whether `path` names the file standard input (fd 0) or output (fd 1) is (a regular file only).
bool is_standard_stream(int fd, const std::string& path) {
  struct stat stream {};
  return ::fstat(fd, &stream) == 0 && S_ISREG(stream.st_mode) && is_stream(fd, path);
}

// The command's arguments, once check_command_line has them, and the files written so far.
struct CommandLine {
  std::mutex mutex;  // a folder of clips is written from several threads
  std::vector<std::pair<std::string, std::string>> arguments;
  std::vector<std::string> outputs;
  std::vector<std::filesystem::path> written;
  bool given = false;
};

CommandLine& command_line() {
  static CommandLine c;
  return c;
}

// A file the command writes, once check_command_line has the arguments, may not be one written before in
// the same run.
void refuse_a_second_write(const std::string& path) {
  CommandLine& c = command_line();
  const std::lock_guard<std::mutex> lock(c.mutex);
  if (!c.given) return;
  std::error_code ec;
  const std::filesystem::path canonical = std::filesystem::weakly_canonical(std::filesystem::absolute(path, ec), ec);
  if (std::find(c.written.begin(), c.written.end(), canonical) != c.written.end())
    throw InputError(text::shown(path) + ": written twice by one command: the second output would replace the first");
  c.written.push_back(canonical);
}

}  // namespace

bool same_file(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::equivalent(a, b, ec)) return true;
  // a file not yet made: its place, a link to it followed (a dangling link names the file it would make)
  const fs::path pa = fs::weakly_canonical(fs::absolute(follow_links(a), ec), ec);
  if (ec) return false;
  const fs::path pb = fs::weakly_canonical(fs::absolute(follow_links(b), ec), ec);
  return !ec && pa == pb;
}

bool names_standard_output(const std::string& path) { return path == "-" || is_stream(STDOUT_FILENO, path); }

std::string output_folder_fault(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path p = fs::absolute(path, ec);
  if (ec) return ec.message();
  while (!fs::exists(fs::symlink_status(p, ec)) && p.has_relative_path()) p = p.parent_path();
  if (!fs::exists(p, ec)) return text::shown(p.string()) + " is a symbolic link to nothing";
  if (!fs::is_directory(p, ec)) return text::shown(p.string()) + " is not a folder";
  if (::access(p.c_str(), W_OK | X_OK) != 0) return text::shown(p.string()) + ": " + std::strerror(errno);
  // the folders to make, made and removed again: what only trying tells (a file system that takes none, a
  // name too long)
  if (const std::string fault = MadeFolders().make(path); !fault.empty()) return text::shown(path) + ": " + fault;
  return {};
}

MadeFolders::~MadeFolders() {
  std::error_code ec;
  for (const auto& folder : made_) std::filesystem::remove(folder, ec);  // (a folder with a file stays)
}

std::string MadeFolders::make(const std::string& folder) {
  namespace fs = std::filesystem;
  std::error_code ec;
  for (fs::path p = fs::absolute(folder, ec); !ec && p.has_relative_path(); p = p.parent_path()) {
    std::error_code missing;  // (set for a path that is not there, as for one that cannot be)
    if (fs::exists(fs::symlink_status(p, missing))) break;
    made_.push_back(p);
  }
  std::error_code made, is_folder;
  if (!fs::create_directories(folder, made) && !fs::is_directory(folder, is_folder))
    return made ? made.message() : "not a folder";
  return {};
}

namespace {
constexpr std::array<int, 4> stop_signals = {SIGINT, SIGTERM, SIGHUP, SIGQUIT};
std::atomic<int> stop_held = 0;  // the signal held, 0 for none (any thread's handler may set it)
static_assert(std::atomic<int>::is_always_lock_free, "the stop handler needs a lock-free flag");
std::array<struct sigaction, stop_signals.size()> stop_actions;  // the actions replaced (one HeldStops at a time)
std::array<bool, stop_signals.size()> stop_replaced{};
extern "C" void hold_stop(int signal) {
  int none = 0;
  stop_held.compare_exchange_strong(none, signal);
}
}  // namespace

HeldStops::HeldStops() {
  stop_held = 0;
  struct sigaction hold {};
  hold.sa_handler = hold_stop;
  // a write or a read the stop interrupts goes on; a second stop ends the process at once (one blocked on
  // a pipe no one reads)
  hold.sa_flags = SA_RESTART | SA_RESETHAND;
  sigemptyset(&hold.sa_mask);
  for (std::size_t k = 0; k < stop_signals.size(); ++k) {
    stop_replaced[k] = sigaction(stop_signals[k], nullptr, &stop_actions[k]) == 0 &&
                       stop_actions[k].sa_handler != SIG_IGN && sigaction(stop_signals[k], &hold, nullptr) == 0;
  }
}

HeldStops::~HeldStops() {
  for (std::size_t k = 0; k < stop_signals.size(); ++k)
    if (stop_replaced[k]) sigaction(stop_signals[k], &stop_actions[k], nullptr);
  if (const int signal = stop_held; signal != 0) std::raise(signal);
}

bool HeldStops::held() const noexcept { return stop_held != 0; }

std::string read_input_file(const std::string& path) {
  std::string content;
  if (const std::string fault = text::read_whole_file(path, content); !fault.empty())
    throw InputError(text::shown(path) + ": " + fault);
  return content;
}

void refuse_replacing_an_input(const std::string& path) {
  CommandLine& c = command_line();
  const std::lock_guard<std::mutex> lock(c.mutex);
  for (const auto& [option, value] : c.arguments)
    if (std::find(c.outputs.begin(), c.outputs.end(), option) == c.outputs.end() &&
        (value == "-" ? is_standard_stream(STDIN_FILENO, path) : same_file(value, path)))
      throw UsageError(fmt::format("{} is given to {}: an output may not replace another argument's file",
                                   text::shown(path), option));
}

void refuse_outputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    std::error_code ec;
    if (std::filesystem::is_directory(outputs[i], ec))
      throw InputError(text::shown(outputs[i]) + ": is a folder, not a file");
    refuse_replacing_an_input(outputs[i]);
    for (const std::string& input : inputs)
      if (same_file(outputs[i], input))
        throw UsageError(
            fmt::format("{} is {}: an output may not replace an input", text::shown(outputs[i]), text::shown(input)));
    for (std::size_t k = 0; k < i; ++k)
      if (same_file(outputs[i], outputs[k]))
        throw UsageError(fmt::format("{} and {} are one file: one output would replace the other",
                                     text::shown(outputs[k]), text::shown(outputs[i])));
  }
}

void check_command_line(std::vector<std::pair<std::string, std::string>> arguments, std::vector<std::string> outputs) {
  namespace fs = std::filesystem;
  const auto is_output = [&](const std::string& option) {
    return std::find(outputs.begin(), outputs.end(), option) != outputs.end();
  };
  // standard output on a file the command reads (`id --in a.csv >> a.csv`, or `--in - < a.csv >> a.csv`):
  // what it prints would land in that input, or overwrite it in place (1<>)
  struct stat in {
  }, out{};
  const bool stdin_is_stdout = ::fstat(STDIN_FILENO, &in) == 0 && ::fstat(STDOUT_FILENO, &out) == 0 &&
                               S_ISREG(in.st_mode) && in.st_dev == out.st_dev && in.st_ino == out.st_ino;
  for (const auto& [option, path] : arguments)
    if (!is_output(option) && (path == "-" ? stdin_is_stdout : is_standard_stream(STDOUT_FILENO, path)))
      throw UsageError(
          fmt::format("{} is given to {} and standard output writes to it: an output may not replace "
                      "another argument's file",
                      path == "-" ? "standard input's file" : text::shown(path), option));
  for (const auto& [output, path] : arguments) {
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    const bool file = status.type() == fs::file_type::regular || status.type() == fs::file_type::not_found;
    // (standard output, named as '-' or as its file, and standard error's file take several outputs in turn)
    if (path == "-" || !file || !is_output(output) || is_standard_stream(STDOUT_FILENO, path) ||
        is_standard_stream(STDERR_FILENO, path))
      continue;
    std::vector<std::string> names;
    for (const auto& [option, value] : arguments)
      if (value == "-" ? !is_output(option) && is_standard_stream(STDIN_FILENO, path) : same_file(value, path))
        names.push_back(value == "-" ? option + " (standard input)" : option);
    if (names.size() > 1)
      throw UsageError(fmt::format("{} is given to {} and {}: an output may not replace another argument's file",
                                   text::shown(path), fmt::join(names.begin(), names.end() - 1, ", "), names.back()));
  }
  CommandLine& c = command_line();
  const std::lock_guard<std::mutex> lock(c.mutex);
  c.arguments = std::move(arguments);
  c.outputs = std::move(outputs);
  c.given = true;
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  if (path_ == "-") {
    file_ = stdout;
    held_only_ = true;
    return;
  }
  // the file standard output or standard error writes to (/dev/stdout, /dev/stderr, or its name): written
  // through it, in turn with what else the command prints there, never replaced (`2>> log` keeps the log)
  for (std::FILE* stream : {stdout, stderr})
    if (is_stream(::fileno(stream), path_)) {
      file_ = stream;
      held_only_ = true;
      return;
    }
  struct stat st {};
  if (::stat(path_.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    if (S_ISDIR(st.st_mode)) throw InputError(text::shown(path_) + ": is a folder, not a file");
    held_only_ = true;  // a device or a pipe: written in place at commit, never replaced
    return;
  }
  target_ = follow_links(path_);
  refuse_replacing_an_input(target_);
  refuse_a_second_write(target_);
  if (::stat(target_.c_str(), &st) == 0) mode_ = int(st.st_mode & 07777);
  // the same folder as the target, so that the final rename cannot cross file systems
  const std::filesystem::path folder = std::filesystem::path(target_).parent_path();
  int fd = ::open(folder.empty() ? "." : folder.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0644);
  named_ = fd < 0;
  if (named_) fd = make_named_temp(target_, temp_path_);
  if (fd < 0) fail(path_, "cannot write");
  file_ = ::fdopen(fd, "w");
  if (!file_) {
    ::close(fd);
    if (named_) std::remove(temp_path_.c_str());
    fail(path_, "cannot write");
  }
}

AtomicFile::~AtomicFile() {
  if (file_ && file_ != stdout && file_ != stderr) std::fclose(file_);
  if (!committed_ && !temp_path_.empty()) std::remove(temp_path_.c_str());
}

void AtomicFile::write(std::string_view text) {
  if (held_only_)
    held_.append(text);
  else if (!text.empty())
    std::fwrite(text.data(), 1, text.size(), file_);
}

void AtomicFile::prepare() {
  if (prepared_ || held_only_) {
    prepared_ = true;
    return;
  }
  if (std::fflush(file_) != 0 || std::ferror(file_) || ::fsync(::fileno(file_)) != 0) fail(path_, "writing failed");
  if (mode_ >= 0 && ::fchmod(::fileno(file_), mode_t(mode_)) != 0) fail(path_, "cannot keep the permissions");
  prepared_ = true;
}

void AtomicFile::publish() {
  prepare();
  if (file_ == stdout) {
    if (std::fwrite(held_.data(), 1, held_.size(), stdout) != held_.size() || std::fflush(stdout) != 0)
      throw InputError(standard_output_failure());
  } else if (file_ == stderr) {
    if (standard_error_closed) throw InputError("standard error: writing failed: it is closed (2>&-)");
    if (std::fwrite(held_.data(), 1, held_.size(), stderr) != held_.size() || std::fflush(stderr) != 0)
      throw InputError(std::string("standard error: writing failed: ") + std::strerror(errno));
  } else if (held_only_) {
    std::FILE* device = std::fopen(path_.c_str(), "w");
    if (!device) fail(path_, "cannot write");
    const bool written = std::fwrite(held_.data(), 1, held_.size(), device) == held_.size() && std::fflush(device) == 0;
    if (std::fclose(device) != 0 || !written) fail(path_, "writing failed");
  } else {
    // an unnamed file takes a temporary name beside the target only now (linkat cannot replace a file),
    // so that a kill before this leaves no file behind
    if (!named_) {
      const std::string proc = fmt::format("/proc/self/fd/{}", ::fileno(file_));
      for (int attempt = 0; temp_path_.empty(); ++attempt) {
        const std::string name = fmt::format("{}.tmp-{}-{}", target_, ::getpid(), attempt);
        if (::linkat(AT_FDCWD, proc.c_str(), AT_FDCWD, name.c_str(), AT_SYMLINK_FOLLOW) == 0)
          temp_path_ = name;
        else if (errno != EEXIST || attempt > 100)
          fail(path_, "cannot write");
      }
    }
    const bool close_failed = std::fclose(file_) != 0;
    file_ = nullptr;
    if (close_failed) fail(path_, "writing failed");
    if (std::rename(temp_path_.c_str(), target_.c_str()) != 0) fail(path_, "cannot replace");
  }
  committed_ = true;
}

namespace {

// A second name for the file `path` beside it (a hard link), or "" where the file system takes none.
std::string second_name(const std::string& path) {
  for (int attempt = 0; attempt <= 100; ++attempt) {
    std::string name = fmt::format("{}.old-{}-{}", path, ::getpid(), attempt);
    if (::link(path.c_str(), name.c_str()) == 0) return name;
    if (errno != EEXIST) break;
  }
  return {};
}

}  // namespace

bool commit_together(const std::vector<AtomicFile*>& files, const HeldStops* stops) {
  for (AtomicFile* f : files)
    if (f) f->prepare();
  if (stops && stops->held()) return false;  // (after the flushes, the slow part: nothing published yet)
  for (AtomicFile* f : files)
    if (f && f->held_only()) f->publish();
  // the files' renames; each file replaced kept under a second name until every rename is done
  struct Renamed {
    const AtomicFile* file;
    std::optional<std::string> old;  // the replaced file's second name ("": none could be made); none: a new file
  };
  std::vector<Renamed> renamed;
  for (AtomicFile* f : files) {
    if (!f || f->held_only()) continue;
    namespace fs = std::filesystem;
    std::error_code ec;
    std::optional<std::string> old;
    if (fs::exists(fs::symlink_status(f->target(), ec))) old = second_name(f->target());
    try {
      f->publish();
    } catch (...) {
      if (old && !old->empty()) ::unlink(old->c_str());
      for (auto r = renamed.rbegin(); r != renamed.rend(); ++r) {  // the renames before put back
        if (!r->old)
          ::unlink(r->file->target().c_str());
        else if (!r->old->empty())
          std::rename(r->old->c_str(), r->file->target().c_str());
      }
      throw;
    }
    renamed.push_back({f, std::move(old)});
  }
  for (const Renamed& r : renamed)
    if (r.old && !r.old->empty()) ::unlink(r.old->c_str());
  return true;
}

void write_file_atomically(const std::string& path, std::string_view text) {
  AtomicFile file(path);
  file.write(text);
  file.commit();
}

}  // namespace humandyn::cli
