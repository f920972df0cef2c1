// The motion pipeline's input: a clip as the positions of named landmarks (joint centres of a human skeleton) per
// frame, in the humandyn world (z up, right-handed, metres). A reader (BVH: humandyn/bvh.hpp) fills it; fitting
// consumes it.
#pragma once

#include <Eigen/Core>

#include <array>
#include <string>
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

/// Landmark positions per frame, in metres, in humandyn's world (z up, right-handed; x need not be the subject's
/// facing direction), one array per frame.
struct LandmarkClip {
  double frame_time = 0;                                                  ///< s
  std::vector<std::array<Eigen::Vector3d, int(Landmark::count)>> frames;  ///< [frame][landmark], m
  std::string source;                                                     ///< file name, for messages
};

}  // namespace humandyn::motion
