// Text for standard output or standard error, formatted by fmt, written by fwrite and never thrown from
// (fmt::print throws when a write fails). A standard error that cannot be written (closed, a full disk)
// loses the message, not the run: the command still writes its files and its exit code tells how it
// went. A failed write to standard output leaves the stream's error flag set, which main checks once at
// the end (exit code 1).
#pragma once

#include <cstdio>
#include <iterator>
#include <utility>

#include <fmt/format.h>

namespace humandyn::cli {

template <class... A>
void print(std::FILE* to, fmt::format_string<A...> format, A&&... args) noexcept {
  fmt::memory_buffer text;
  try {
    fmt::format_to(std::back_inserter(text), format, std::forward<A>(args)...);
  } catch (...) {  // (no memory for the text: nothing can be said)
    return;
  }
  std::fwrite(text.data(), 1, text.size(), to);
}

}  // namespace humandyn::cli
