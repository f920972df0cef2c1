#include "cli/atomic_file.hpp"

#include "cli/errors.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <utility>

#include <fcntl.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

namespace humandyn::cli {

namespace {

[[noreturn]] void fail(const std::string& path, const char* what) {
  throw InputError(fmt::format("{}: {}: {}", path, what, std::strerror(errno)));
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
    if (hops == 40) throw InputError(path + ": too many levels of symbolic links");
    const fs::path to = fs::read_symlink(p, ec);
    if (ec) throw InputError(fmt::format("{}: cannot read the symbolic link: {}", path, ec.message()));
    p = to.is_absolute() ? to : p.parent_path() / to;
  }
  return p.string();
}

std::vector<std::pair<std::string, std::string>>& command_line_arguments() {
  static std::vector<std::pair<std::string, std::string>> arguments;
  return arguments;
}

// A target that another argument names too (however spelt: a link, a relative path) is refused.
void refuse_a_file_named_twice(const std::string& path) {
  std::vector<std::string> names;
  for (const auto& [option, value] : command_line_arguments())
    if (std::error_code ec; value != "-" && std::filesystem::equivalent(value, path, ec)) names.push_back(option);
  if (names.size() > 1)
    throw UsageError(fmt::format("{} is given to {} and {}: an output may not replace another argument's file", path,
                                 fmt::join(names.begin(), names.end() - 1, ", "), names.back()));
}

}  // namespace

std::string read_input_file(const std::string& path) {
  if (std::error_code ec; std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a folder, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(path + ": cannot read");
  return text;
}

void set_command_line_arguments(std::vector<std::pair<std::string, std::string>> arguments) {
  command_line_arguments() = std::move(arguments);
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  if (path_ == "-") {
    file_ = stdout;
    held_only_ = true;
    return;
  }
  target_ = follow_links(path_);
  struct stat st {};
  if (::stat(target_.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    if (S_ISDIR(st.st_mode)) throw InputError(path_ + ": is a folder, not a file");
    held_only_ = true;  // a device or a pipe: written in place at commit, never replaced
    return;
  }
  refuse_a_file_named_twice(path_);
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
  if (file_ && file_ != stdout) std::fclose(file_);
  if (!committed_ && !temp_path_.empty()) std::remove(temp_path_.c_str());
}

void AtomicFile::write(std::string_view text) {
  if (held_only_)
    held_.append(text);
  else if (!text.empty())
    std::fwrite(text.data(), 1, text.size(), file_);
}

void AtomicFile::commit() {
  if (file_ == stdout) {
    if (std::fwrite(held_.data(), 1, held_.size(), stdout) != held_.size() || std::fflush(stdout) != 0)
      fail("standard output", "writing failed");
    committed_ = true;
    return;
  }
  if (held_only_) {
    std::FILE* device = std::fopen(target_.c_str(), "w");
    if (!device) fail(path_, "cannot write");
    const bool written = std::fwrite(held_.data(), 1, held_.size(), device) == held_.size() && std::fflush(device) == 0;
    if (std::fclose(device) != 0 || !written) fail(path_, "writing failed");
    committed_ = true;
    return;
  }
  if (std::fflush(file_) != 0 || std::ferror(file_) || ::fsync(::fileno(file_)) != 0) fail(path_, "writing failed");
  if (!named_) {
    // give the unnamed file a temporary name beside the target (linkat cannot replace a file)
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
  committed_ = true;
}

void write_file_atomically(const std::string& path, std::string_view text) {
  AtomicFile file(path);
  file.write(text);
  file.commit();
}

}  // namespace humandyn::cli
