// libFuzzer target: the importer fed arbitrary bytes. Every input must give a model or a
// humandyn::urdf::Error; a crash, a hang, a sanitizer report or any other exception is a bug.
// Build: cmake -DCMAKE_CXX_COMPILER=clang++ -DHUMANDYN_BUILD_FUZZER=ON; run on the seeds in
// tests/data/urdf (see docs/urdf.md). The first line of an input may hold a joint map, after "#map:".
#include "humandyn/urdf.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  humandyn::urdf::ImportOptions options;
  try {
    // "#map:j1 j2=0.3;j3\n" before the XML selects joints; ';' separates map lines
    if (text.rfind("#map:", 0) == 0) {
      const auto nl = text.find('\n');
      std::string map = text.substr(5, nl == std::string::npos ? std::string::npos : nl - 5);
      for (auto& c : map)
        if (c == ';') c = '\n';
      options.joints = humandyn::urdf::parse_joint_map(map, "fuzz map");
      text = nl == std::string::npos ? std::string() : text.substr(nl + 1);
    }
    const auto imported = humandyn::urdf::import_urdf(text, options, "fuzz.urdf");
    // a model it gives must be valid and exportable, and its export importable
    const std::string again = humandyn::urdf::to_urdf(imported.model);
    humandyn::urdf::import_urdf(again, {}, "fuzz-export.urdf");
  } catch (const humandyn::urdf::Error&) {
  }
  return 0;
}
