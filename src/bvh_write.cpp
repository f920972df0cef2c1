// The BVH writer: the hierarchy nested as the joints' parents say, the frames with shortest round-trip numbers.
#include "bvh_text.hpp"

#include <unordered_set>

namespace humandyn::motion {

namespace {

// Refuses a clip that no BVH file reads back to: the checks parse_bvh makes, on a clip built in code.
void check_writable(const BvhClip& clip) {
  const std::string& who = clip.source.empty() ? std::string("clip") : clip.source;
  const auto fail = [&](const std::string& what) { throw BvhError(who + ": cannot be written as BVH: " + what); };
  const auto finite = [&](const Eigen::Vector3d& v, const std::string& name) {
    if (!v.allFinite()) fail("joint '" + name + "' has a non-finite OFFSET");
  };
  std::unordered_set<std::string> names;
  std::vector<int> path;  // the ancestors of the joint being checked, root first
  for (std::size_t i = 0; i < clip.joints.size(); ++i) {
    const BvhJoint& j = clip.joints[i];
    const std::string name = j.end_site ? "End Site " + std::to_string(i) : j.name;
    // joints come depth first, each right after its parent's subtree began: its parent is on the current path
    while (!path.empty() && path.back() != j.parent) path.pop_back();
    if (j.parent < -1 || j.parent >= static_cast<int>(i) || (j.parent >= 0 && path.empty()))
      fail("joint " + std::to_string(i) + " ('" + detail::shown(name) +
           "') does not follow its parent depth first (parent index " + std::to_string(j.parent) + ")");
    if (j.parent >= 0 && clip.joints[static_cast<std::size_t>(j.parent)].end_site)
      fail("an End Site has a child (" + detail::quoted(name) + ")");
    finite(j.offset, name);
    if (j.end_site) {
      if (j.parent < 0) fail("End Site " + std::to_string(i) + " is a root");
      if (!j.channels.empty()) fail("End Site " + std::to_string(i) + " has channels");
    } else {
      if (j.name.empty() || detail::trimmed(j.name) != j.name)
        fail("joint " + std::to_string(i) + " has an empty name or one with blanks at its ends ('" +
             detail::shown(j.name) + "')");
      if (const auto fault = detail::name_fault(j.name); fault.at != std::string_view::npos)
        fail("joint name " + detail::quoted(j.name) + " " + fault.how);
      if (!names.insert(j.name).second) fail("duplicate joint name " + detail::quoted(j.name));
      for (std::size_t a = 0; a < j.channels.size(); ++a)
        for (std::size_t b = 0; b < a; ++b)
          if (j.channels[a] == j.channels[b]) fail("joint '" + j.name + "' lists a channel twice");
    }
    path.push_back(static_cast<int>(i));
  }
  const auto channels = static_cast<std::size_t>(clip.channel_count());
  if (channels == 0) fail("the hierarchy has no channels");
  if (clip.values.size() % channels != 0)
    fail(std::to_string(clip.values.size()) + " values are not a whole number of frames of " +
         std::to_string(channels) + " channels");
  if (!(clip.frame_time > 0) || !std::isfinite(clip.frame_time)) fail("the frame time must be positive and finite");
  for (std::size_t k = 0; k < clip.values.size(); ++k)
    if (!std::isfinite(clip.values[k]))
      fail("value " + std::to_string(k % channels + 1) + " of frame " + std::to_string(k / channels + 1) +
           " is not finite");
}

}  // namespace

std::string to_bvh(const BvhClip& clip) {
  check_writable(clip);
  std::string out = "HIERARCHY\n";
  std::vector<int> path;  // open joints
  const auto close_to = [&](int parent) {
    while (!path.empty() && path.back() != parent) {
      path.pop_back();
      out.append(path.size(), '\t') += "}\n";
    }
  };
  const auto offset = [&](const Eigen::Vector3d& v) {
    out += "OFFSET";
    for (int k = 0; k < 3; ++k) detail::append_number(out += ' ', v[k]);
    out += '\n';
  };
  for (std::size_t i = 0; i < clip.joints.size(); ++i) {
    const BvhJoint& j = clip.joints[i];
    close_to(j.parent);
    const std::string indent(path.size(), '\t');
    if (j.end_site) {
      out += indent + "End Site\n" + indent + "{\n" + indent + '\t';
      offset(j.offset);
      out += indent + "}\n";
      continue;
    }
    out += indent + (j.parent < 0 ? "ROOT " : "JOINT ") + j.name + '\n' + indent + "{\n" + indent + '\t';
    offset(j.offset);
    out += indent + "\tCHANNELS " + std::to_string(j.channels.size());
    for (const Channel c : j.channels) (out += ' ') += channel_name(c);
    out += '\n';
    path.push_back(static_cast<int>(i));
  }
  close_to(-1);

  const auto channels = static_cast<std::size_t>(clip.channel_count());
  out += "MOTION\nFrames: " + std::to_string(clip.values.size() / channels) + "\nFrame Time: ";
  detail::append_number(out, clip.frame_time);
  out += '\n';
  for (std::size_t k = 0; k < clip.values.size(); ++k) {
    detail::append_number(out, clip.values[k]);
    out += (k + 1) % channels == 0 ? '\n' : ' ';
  }
  return out;
}

}  // namespace humandyn::motion
