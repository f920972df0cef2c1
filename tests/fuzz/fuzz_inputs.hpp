// What the fuzz targets do with one input, shared with test_urdf, which replays the seed corpora
// (tests/data/fuzz/) as regression inputs. Each function returns normally or throws
// humandyn::urdf::Error; anything else (a crash, a sanitizer report, another exception, a trap) is a bug.
#pragma once

#include "humandyn/urdf.hpp"

#include <string>

namespace humandyn::fuzz {

// A URDF document, imported; what it gives is exported and imported again. A first line
// "#map:j1 hip;j2 = 0.3" gives a joint map (';' separates its lines).
inline void import_urdf_input(const std::string& input) {
  std::string text = input;
  urdf::ImportOptions options;
  if (text.rfind("#map:", 0) == 0) {
    const auto nl = text.find('\n');
    std::string map = text.substr(5, nl == std::string::npos ? std::string::npos : nl - 5);
    for (auto& c : map)
      if (c == ';') c = '\n';
    options.joints = urdf::parse_joint_map(map, "fuzz map");
    text = nl == std::string::npos ? std::string() : text.substr(nl + 1);
  }
  options.balance_inertia = text.size() % 2 == 1;  // both ways of reading inertias
  const auto imported = urdf::import_urdf(text, options, "fuzz.urdf");
  // a model it gives must be valid and exportable, and its export importable
  urdf::import_urdf(urdf::to_urdf(imported.model), {}, "fuzz-export.urdf");
}

// A joint map, parsed; what it gives, written back in the grammar, must parse to the same entries.
inline void parse_joint_map_input(const std::string& text) {
  const urdf::JointMap map = urdf::parse_joint_map(text, "fuzz.jointmap");
  std::string again = "# written back\n";  // (a byte-order mark is only one on the first line)
  for (const auto& e : map.entries) {
    if (!e.locked && !urdf::name_fault(e.model_name).empty()) __builtin_trap();  // a model name broke the rule
    again += e.urdf_joint + (e.locked ? " = " + exact_number(e.value) : " " + e.model_name) + "\n";
  }
  const urdf::JointMap back = urdf::parse_joint_map(again, "fuzz-again.jointmap");
  if (back.entries.size() != map.entries.size()) __builtin_trap();
  for (std::size_t i = 0; i < map.entries.size(); ++i) {
    const auto &a = map.entries[i], &b = back.entries[i];
    if (a.urdf_joint != b.urdf_joint || a.model_name != b.model_name || a.locked != b.locked || a.value != b.value)
      __builtin_trap();
  }
}

}  // namespace humandyn::fuzz
