// Every file the command line writes is written all or nothing: the text goes to an unnamed file in the
// target's folder (O_TMPFILE; a hidden temporary name where the file system has none), is flushed to
// disk, and takes the target's name only on commit(). A failure or a kill before that leaves the
// target as it was, and no temporary file behind (a kill can leave one only where O_TMPFILE is
// missing, named "<target>.tmp-XXXXXX"). The path "-" is standard output, held and written at commit()
// alike, so that a command that fails prints no part of its result there either; so is a path that names
// no regular file but a device or a pipe (/dev/null, /dev/stdout, a FIFO), opened and written only at
// commit(). A symbolic link is followed: the file it points to is replaced and the link stays; a replaced
// file keeps its permissions. A file
// that the command also reads (another argument names it) is never replaced (check_command_line).
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace humandyn::cli {

class AtomicFile {
 public:
  // Opens the temporary file; InputError naming `path` if its folder cannot be written. Standard output's
  // or standard error's file, a device or a pipe is written in place at publish(), never replaced.
  explicit AtomicFile(std::string path);
  ~AtomicFile();  // without commit(): the temporary file is removed, `path` untouched
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  void write(std::string_view text);
  // fsync, then the temporary file replaces `path`; InputError if any write or the rename failed.
  void commit() {
    prepare();
    publish();
  }
  // commit() in two halves, for commit_together: prepare() flushes the text to disk (every write's
  // failure shows here; `path` untouched), publish() writes standard output or a device, or names the
  // file and renames it into place.
  void prepare();
  void publish();
  const std::string& path() const { return path_; }
  // the file a rename replaces: path() with its symbolic links followed ("" where the text is held)
  const std::string& target() const { return target_; }
  // standard output, a device or a pipe: the text is held and written at publish()
  bool held_only() const { return held_only_; }

 private:
  std::string path_, temp_path_;  // temp_path_: set only while the temporary file has a name
  std::string target_;            // the file replaced: path_ with its symbolic links followed
  std::FILE* file_ = nullptr;
  bool held_only_ = false;  // standard output, a device or a pipe: the text held, written at commit only
  std::string held_;
  bool named_ = false;  // false: an O_TMPFILE, linked to a name on commit
  int mode_ = -1;       // the permissions of the file replaced, kept (-1: a new file)
  bool prepared_ = false;
  bool committed_ = false;
};

// While one is alive, a stop (SIGINT, SIGTERM, SIGHUP, SIGQUIT; one the process ignores stays ignored) is
// held instead of ending the process at once, so that a command writing several outputs can roll them all
// back: given to commit_together, a stop held once the files are flushed publishes none, and the command
// returns (its outputs and the folders it made are removed as they go out of scope). The destructor, run
// after them, restores the signals' actions and raises the stop held: the process ends by it, as it would
// have. A stop while the files take their names ends the process once every output is in place; a second
// stop ends it at once (one blocked writing to a pipe that no one reads). One at a time.
class HeldStops {
 public:
  HeldStops();
  ~HeldStops();
  HeldStops(const HeldStops&) = delete;
  HeldStops& operator=(const HeldStops&) = delete;
  // whether a stop came since the construction
  bool held() const noexcept;
};

// The outputs of one command committed as one: every file is flushed to disk first (a failure there
// leaves every target as it was), then standard output and devices are written (a failure there, such as
// a full disk behind a redirection, leaves every file as it was), and only then do the files take their
// names, one rename each. A rename that fails after others (rare: a file made immutable, a folder put in
// its place) puts those back: each file a rename replaces keeps a second name (a hard link) until all are
// in place, and a new file is removed again; only where the file system takes no hard link does a file
// replaced stay replaced. Null entries are skipped (an output not asked for). Returns false, publishing
// nothing, when `stops` holds a stop once every file is flushed (the caller then returns and its files are
// removed); true when every output is in place.
bool commit_together(const std::vector<AtomicFile*>& files, const HeldStops* stops = nullptr);

// Why `path` cannot be an output folder, or "" when it can, naming the place at fault: the nearest of it
// and its parents that exists must be a folder the command may write in (else "... is not a folder", "... is
// a symbolic link to nothing" or the system's reason, e.g. "Permission denied"), and the missing ones must be
// made (tried, with MadeFolders, and removed again: a file system that takes none, a name too long). Leaves
// nothing made: a command makes its output folder once its usage is checked, bench after its run.
std::string output_folder_fault(const std::string& path);

// Whether `path` is where standard output goes: '-', or whatever it writes to (a file, a pipe, a terminal,
// /dev/null), however named (/dev/stdout, /proc/self/fd/1, the file of `> FILE`). An AtomicFile there
// writes through standard output.
bool names_standard_output(const std::string& path);

// An output folder made with the parents it needs, removed again (those still empty) unless kept: a
// command that fails after making it leaves none.
class MadeFolders {
 public:
  MadeFolders() = default;
  MadeFolders(const MadeFolders&) = delete;
  MadeFolders& operator=(const MadeFolders&) = delete;
  ~MadeFolders();
  // Makes `folder` and its missing parents; the system's reason when it cannot, "" when it is made.
  std::string make(const std::string& folder);
  void keep() { made_.clear(); }

 private:
  std::vector<std::filesystem::path> made_;  // innermost first
};

// `text` as the whole content of `path`, all or nothing.
void write_file_atomically(const std::string& path, std::string_view text);

// The whole of a file the command reads; InputError naming it when it is a folder or cannot be read.
std::string read_input_file(const std::string& path);

// Whether two paths name the same file however spelt (a link, a relative path, ./, a/../): the same
// existing file, or the same place for one not yet made.
bool same_file(const std::string& a, const std::string& b);

// UsageError when a value of one of the `outputs` options names a file (regular, or not yet made) that
// another of the command's `arguments` ((option, value) pairs, as parsed) names too, however spelt: an
// output that would replace an input or another output. Standard output ('-'), a device or a pipe may be
// named by several; but standard output's file (`>> FILE`, `1<> FILE`) may be no input's file: UsageError
// naming the input, whatever the command writes there. Kept: from then on an AtomicFile refuses a file an input
// argument names (UsageError) and one the command has written before (InputError), for the files a command names itself
// (CLIP.csv in an output folder).
void check_command_line(std::vector<std::pair<std::string, std::string>> arguments, std::vector<std::string> outputs);

// UsageError when an input argument of the command (check_command_line) names the file `path`: for a
// command that names outputs itself (CLIP.csv in an output folder), before it writes any.
void refuse_replacing_an_input(const std::string& path);

// For a command that names several outputs itself (a folder's files), before it writes any: InputError
// when one is a folder; UsageError when one is a file an input argument or one of `inputs` names, or two
// of them name one file (a link).
void refuse_outputs(const std::vector<std::string>& outputs, const std::vector<std::string>& inputs = {});

}  // namespace humandyn::cli
