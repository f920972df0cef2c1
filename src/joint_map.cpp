// The joint map: which URDF joints become model joints, which are locked and at what angle.
#include "humandyn/urdf.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace humandyn::urdf {

JointMap parse_joint_map(const std::string& text, const std::string& source) {
  JointMap map;
  map.source = source;
  std::istringstream lines(text);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream in(line);
    std::vector<std::string> words;
    for (std::string w; in >> w;) words.push_back(w);
    if (words.empty()) continue;
    const std::string where = source + ":" + std::to_string(number) + ": ";
    JointMapEntry e;
    e.urdf_joint = words[0];
    e.line = number;
    if (words.size() == 3 && words[1] == "=") {
      char* end = nullptr;
      e.value = std::strtod(words[2].c_str(), &end);
      if (*end != '\0' || !std::isfinite(e.value))
        throw Error(where + "joint '" + e.urdf_joint + "': '" + words[2] + "' is not a finite number");
      e.locked = true;
    } else if (words.size() == 1 || (words.size() == 2 && words[1] != "=")) {
      e.model_name = words.size() == 2 ? words[1] : words[0];
    } else {
      throw Error(where + "expected `urdf_joint [model_name]` or `urdf_joint = value`, found '" + line + "'");
    }
    map.entries.push_back(e);
  }
  return map;
}

JointMap read_joint_map(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw Error(path + ": cannot read the joint map");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_joint_map(text.str(), path);
}

}  // namespace humandyn::urdf
