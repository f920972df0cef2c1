// A reader's input file read whole, with the one wording of what can go wrong (the URDF importer, the joint
// map, the BVH reader and landmark map, and the command line's inputs). Header-only and internal, as
// shown.hpp.
#pragma once

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <string_view>
#include <system_error>

namespace humandyn::text {

/// The whole of the file at `path` into `text`.
/// \return "" when it was read; else what went wrong, to follow the file's name in a message: "is a folder,
///         not a file", "cannot open: <the system's reason>" or "cannot read: <the system's reason>"
inline std::string read_whole_file(const std::string& path, std::string& text) {
  if (std::error_code ec; std::filesystem::is_directory(path, ec)) return "is a folder, not a file";
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::string("cannot open: ") + std::strerror(errno);
  text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (in.bad()) return std::string("cannot read: ") + std::strerror(errno);
  return "";
}

/// Why a text file's contents cannot be read as UTF-8 from how they start: a UTF-16 byte-order mark (a
/// text editor's "Unicode"), or "" (the CSV and JSON readers refuse such a file with this, at line 1).
inline std::string utf16_fault(std::string_view text) {
  if (text.starts_with("\xFF\xFE") || text.starts_with("\xFE\xFF"))
    return "the file is UTF-16 (it starts with a UTF-16 byte-order mark): save it as UTF-8";
  return "";
}

}  // namespace humandyn::text
