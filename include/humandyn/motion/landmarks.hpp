// The motion pipeline's input: a clip as the positions of named landmarks (joint centres of a human skeleton) per
// frame, in the humandyn world (z up, right-handed, metres). A reader (BVH: humandyn/bvh.hpp) fills it; fitting
// consumes it.
#pragma once

#include <Eigen/Core>

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace humandyn::motion {

/// The body landmarks a fit needs: joint centres of a human skeleton (r_ right, l_ left).
enum class Landmark : int {
  pelvis /*mid-hip point*/,
  r_hip,
  r_knee,
  r_ankle,
  r_toe,
  l_hip,
  l_knee,
  l_ankle,
  l_toe,
  lower_back,
  neck /*base of the neck, between the shoulders*/,
  head,
  r_shoulder,
  r_elbow,
  r_wrist,
  l_shoulder,
  l_elbow,
  l_wrist,
  count
};

/// Each landmark's name (its enumerator), in the enumeration's order: landmark map files and messages use them.
inline constexpr std::array<std::string_view, int(Landmark::count)> landmark_names{
    "pelvis",     "r_hip", "r_knee", "r_ankle",    "r_toe",   "l_hip",   "l_knee",     "l_ankle", "l_toe",
    "lower_back", "neck",  "head",   "r_shoulder", "r_elbow", "r_wrist", "l_shoulder", "l_elbow", "l_wrist"};

/// Landmark positions per frame, in metres, in humandyn's world (z up, right-handed; x need not be the subject's
/// facing direction), one array per frame.
struct LandmarkClip {
  double frame_time = 0;                                                  ///< s
  std::vector<std::array<Eigen::Vector3d, int(Landmark::count)>> frames;  ///< [frame][landmark], m
  std::string source;                                                     ///< file name, for messages
  /// The number of frames[0] in `source`, counted from 1 as the BVH reader counts a file's frames (2
  /// when the file's first frame was left out): messages name frame f as frame_number(f).
  int first_frame = 1;
  int frame_number(std::size_t f) const { return first_frame + int(f); }
};

}  // namespace humandyn::motion
