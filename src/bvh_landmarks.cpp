// Landmarks: which BVH joints are the body's joint centres (the built-in map and its file format), and a clip's
// landmark positions per frame.
#include "bvh_text.hpp"
#include "text/file.hpp"

#include <algorithm>

namespace humandyn::motion {

namespace {

constexpr int landmark_count = int(Landmark::count);

std::string all_landmark_names() {
  std::string out;
  for (const auto name : landmark_names) (out += out.empty() ? "" : ", ") += name;
  return out;
}

}  // namespace

std::optional<Landmark> landmark_named(std::string_view name) {
  for (int i = 0; i < landmark_count; ++i)
    if (landmark_names[static_cast<std::size_t>(i)] == name) return static_cast<Landmark>(i);
  return std::nullopt;
}

LandmarkMap default_landmark_map() {
  LandmarkMap map;
  const auto set = [&](Landmark l, std::vector<std::string> joints) { map.joints[std::size_t(l)] = std::move(joints); };
  set(Landmark::pelvis, {"LeftUpLeg", "RightUpLeg"});  // the mid-hip point
  for (const auto& [side, hip, knee, ankle, toe, shoulder, elbow, wrist] :
       {std::tuple{std::string("Right"), Landmark::r_hip, Landmark::r_knee, Landmark::r_ankle, Landmark::r_toe,
                   Landmark::r_shoulder, Landmark::r_elbow, Landmark::r_wrist},
        std::tuple{std::string("Left"), Landmark::l_hip, Landmark::l_knee, Landmark::l_ankle, Landmark::l_toe,
                   Landmark::l_shoulder, Landmark::l_elbow, Landmark::l_wrist}}) {
    set(hip, {side + "UpLeg"});
    set(knee, {side + "Leg"});
    set(ankle, {side + "Foot"});
    set(toe, {side + "ToeBase"});
    set(shoulder, {side + "Arm"});
    set(elbow, {side + "ForeArm"});
    set(wrist, {side + "Hand"});
  }
  set(Landmark::lower_back, {"Spine"});
  set(Landmark::neck, {"Neck"});
  set(Landmark::head, {"Head"});
  return map;
}

LandmarkMap parse_landmark_map(std::string_view text, const std::string& source) {
  LandmarkMap map = default_landmark_map();
  map.source = source;
  std::array<bool, landmark_count> set{};
  const auto lines = detail::split_lines(text);
  for (std::size_t n = 0; n < lines.size(); ++n) {
    const std::string_view line = lines[n];
    const auto fail = [&](std::size_t at, const std::string& what) { detail::fail_at(source, n, line, at, what); };
    const std::size_t end = std::min(line.find('#'), line.size());  // a comment runs to the line's end
    std::size_t pos = 0;
    while (pos < end && detail::is_blank(line[pos])) ++pos;
    if (pos == end) continue;
    const std::size_t name_at = pos;
    while (pos < end && !detail::is_blank(line[pos]) && line[pos] != '=') ++pos;
    const std::string_view name = line.substr(name_at, pos - name_at);
    if (name.empty()) fail(name_at, "expected a landmark name before '='");
    const auto landmark = landmark_named(name);
    if (!landmark) fail(name_at, "unknown landmark " + detail::quoted(name) + " (one of " + all_landmark_names() + ")");
    const auto l = static_cast<std::size_t>(*landmark);
    if (set[l])
      fail(name_at,
           "landmark '" + std::string(name) + "' set twice (first on line " + std::to_string(map.lines[l]) + ")");
    while (pos < end && detail::is_blank(line[pos])) ++pos;
    if (pos == end || line[pos] != '=')
      fail(pos, "expected '=' after the landmark name (landmark = bvh_joint[, bvh_joint ...])");
    std::vector<std::string> joints;
    do {  // comma-separated joint names, each trimmed
      const std::size_t from = ++pos;
      while (pos < end && line[pos] != ',') ++pos;
      const std::string_view joint = detail::trimmed(line.substr(from, pos - from));
      std::size_t at = from;
      while (at < pos && detail::is_blank(line[at])) ++at;
      if (joint.empty()) fail(at, "expected a BVH joint name");
      if (const auto fault = detail::name_fault(joint); fault.at != std::string_view::npos)
        fail(at + fault.at, "joint name " + detail::quoted(joint) + " " + fault.how);
      if (std::find(joints.begin(), joints.end(), joint) != joints.end())
        fail(at, "joint " + detail::quoted(joint) + " named twice for landmark '" + std::string(name) + "'");
      joints.emplace_back(joint);
    } while (pos < end);
    map.joints[l] = std::move(joints);
    map.lines[l] = static_cast<int>(n) + 1;
    set[l] = true;
  }
  return map;
}

LandmarkMap read_landmark_map(const std::string& path) {
  std::string content;
  if (const std::string fault = text::read_whole_file(path, content); !fault.empty())
    throw BvhError(text::shown(path) + ": " + fault);
  return parse_landmark_map(content, text::shown(path));
}

std::string to_text(const LandmarkMap& map) {
  std::string out;
  for (std::size_t l = 0; l < landmark_names.size(); ++l) {
    out += std::string(landmark_names[l]) + " =";
    for (std::size_t k = 0; k < map.joints[l].size(); ++k) (out += k == 0 ? " " : ", ") += map.joints[l][k];
    out += '\n';
  }
  return out;
}

namespace {

// The joint a map's name stands for: the joint of that name, or else the one joint named "prefix:name".
int resolve(const BvhClip& clip, const LandmarkMap& map, std::size_t landmark, const std::string& name) {
  if (const int exact = clip.find(name); exact >= 0) return exact;
  std::vector<int> found;  // the joints named "prefix:name"
  for (std::size_t i = 0; i < clip.joints.size(); ++i) {
    const std::string& j = clip.joints[i].name;
    if (!clip.joints[i].end_site && j.size() > name.size() &&
        j.compare(j.size() - name.size(), name.size(), name) == 0 && j[j.size() - name.size() - 1] == ':')
      found.push_back(static_cast<int>(i));
  }
  if (found.size() == 1) return found[0];
  // those joints for the message: 'a:Neck' on line 58 and 'b:Neck' on line 62 (a clip built in code: no lines)
  std::string which;
  for (std::size_t k = 0; k < found.size(); ++k) {
    const BvhJoint& j = clip.joints[std::size_t(found[k])];
    which += k > 0 && k + 1 == found.size() ? " and " : ", ";
    which += detail::quoted(j.name) + (j.line > 0 ? " on line " + std::to_string(j.line) : "");
  }
  // the map line that named the joint, or the built-in entry a map file left as it was
  const std::string built_in = LandmarkMap{}.source;
  const std::string asks = map.lines[landmark] != 0 ? map.source + ":" + std::to_string(map.lines[landmark]) + " asks"
                           : map.source == built_in
                               ? "the " + built_in + " asks"
                               : "the " + built_in + " asks, which " + map.source + " does not change";
  throw BvhError(clip.source + ": landmark '" + std::string(landmark_names[landmark]) + "': " +
                 (found.empty()
                      ? "no joint " + detail::quoted(name) + " in the hierarchy"
                      : std::to_string(found.size()) + " joints named '<prefix>:" + detail::shown(name) + "'" + which) +
                 " (as " + asks + "; a landmark map file can name another joint)");
}

}  // namespace

LandmarkClip to_landmarks(const BvhClip& clip, const LandmarkOptions& options) {
  // each landmark: the joints whose mean it is
  std::array<std::vector<int>, landmark_count> joints;
  for (std::size_t l = 0; l < joints.size(); ++l) {
    if (options.map.joints[l].empty())
      throw BvhError(options.map.source + ": landmark '" + std::string(landmark_names[l]) + "' names no joint");
    for (const auto& name : options.map.joints[l]) joints[l].push_back(resolve(clip, options.map, l, name));
  }
  // two landmarks on the same joints stand at one point: a segment of length 0
  const auto where = [&](std::size_t l) {
    return options.map.lines[l] == 0 ? std::string("built in") : "line " + std::to_string(options.map.lines[l]);
  };
  auto sets = joints;
  for (auto& s : sets) {
    std::sort(s.begin(), s.end());
    s.erase(std::unique(s.begin(), s.end()), s.end());
  }
  for (std::size_t l = 1; l < sets.size(); ++l) {
    const std::vector<int>& these = sets[l];
    for (std::size_t k = 0; k < l; ++k) {
      if (sets[k] != these) continue;
      // the message points at the file's line that made them meet (the later one)
      const std::size_t at = options.map.lines[k] > options.map.lines[l] ? k : l, other = at == k ? l : k;
      std::string names;
      for (const int j : these) (names += names.empty() ? "" : ", ") += clip.joints[std::size_t(j)].name;
      throw BvhError((options.map.lines[at] == 0 ? options.map.source
                                                 : options.map.source + ":" + std::to_string(options.map.lines[at])) +
                     ": landmarks '" + std::string(landmark_names[other]) + "' (" + where(other) + ") and '" +
                     std::string(landmark_names[at]) + "' (" + where(at) + ") both stand at BVH joint" +
                     (these.size() == 1 ? " " : "s ") + detail::quoted(names) +
                     ": every landmark needs joints of its own");
    }
  }
  const int first = options.drop_first_frame ? 1 : 0;
  if (clip.frame_count() <= first)
    throw BvhError(clip.source + ": no frame left (" + std::to_string(clip.frame_count()) + " frames" +
                   (first ? ", the first dropped)" : ")"));

  LandmarkClip out;
  out.frame_time = clip.frame_time;
  out.source = clip.source;
  out.first_frame = first + 1;
  const auto positions = all_joint_positions(clip, options.world);
  out.frames.resize(positions.size() - static_cast<std::size_t>(first));
  for (std::size_t f = 0; f < out.frames.size(); ++f) {
    const auto& p = positions[f + static_cast<std::size_t>(first)];
    for (std::size_t l = 0; l < joints.size(); ++l) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (const int j : joints[l]) sum += p[static_cast<std::size_t>(j)];
      out.frames[f][l] = sum / static_cast<double>(joints[l].size());
    }
  }
  return out;
}

}  // namespace humandyn::motion
