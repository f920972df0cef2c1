# One warnings target for every compiled target of the project (never installed, never exported):
#   target_link_libraries(<target> PRIVATE $<BUILD_INTERFACE:humandyn_warnings>)
# HUMANDYN_WERROR turns them into errors (CI, and the dev and asan presets).
option(HUMANDYN_WERROR "Treat compiler warnings as errors" OFF)
add_library(humandyn_warnings INTERFACE)
target_compile_options(humandyn_warnings INTERFACE
  -Wall -Wextra -Wshadow -Wconversion -Wpedantic
  $<$<CXX_COMPILER_ID:Clang>:-Wno-sign-conversion>  # GCC's -Wconversion leaves signedness out in C++; so does clang's here
  # GCC 12 warns falsely inside libstdc++'s string concatenation at -O3 ("literal" + std::string&&,
  # GCC bug 105651), wherever inlining happens to expose it
  $<$<AND:$<CXX_COMPILER_ID:GNU>,$<VERSION_LESS:$<CXX_COMPILER_VERSION>,13>>:-Wno-restrict>
  $<$<BOOL:${HUMANDYN_WERROR}>:-Werror>)
