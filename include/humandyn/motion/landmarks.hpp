// The motion pipeline's input: a clip as the positions of named landmarks (joint centres and a few
// points of the head, trunk and feet), per frame, in the humandyn world (z up, x forward, y left, m).
// A reader (BVH, ...) fills it; fitting (motion/fit.hpp) consumes it.
#pragma once

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace humandyn::motion {
enum class Landmark : int { pelvis /*mid-hip point*/, r_hip, r_knee, r_ankle, r_toe, l_hip, l_knee, l_ankle, l_toe,
                            lower_back, neck /*base of the neck, between the shoulders*/, head, r_shoulder, r_elbow, r_wrist,
                            l_shoulder, l_elbow, l_wrist, count };
struct LandmarkClip {   // positions in metres, humandyn world: z up, right-handed
  double frame_time = 0;  // s
  std::vector<std::array<Eigen::Vector3d, int(Landmark::count)>> frames;
  std::string source;     // file name, for messages
};

}  // namespace humandyn::motion
