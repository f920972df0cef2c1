// What the BVH fuzz targets do with one input, shared with test_bvh, which replays the seed corpora
// (tests/data/fuzz/bvh, tests/data/fuzz/landmark_map) as regression inputs. Each function returns normally or
// throws humandyn::motion::BvhError; anything else (a crash, a sanitizer report, another exception, a trap) is a bug.
#pragma once

#include "humandyn/bvh.hpp"

#include <string>

namespace humandyn::fuzz {

// A BVH file, read; what it gives is written, read back (the same clip, exactly, and the same text when written
// again), and run through forward kinematics and the built-in landmark map.
inline void bvh_input(const std::string& text) {
  const motion::BvhClip clip = motion::parse_bvh(text, "fuzz.bvh");
  const std::string written = motion::to_bvh(clip);
  const motion::BvhClip back = motion::parse_bvh(written, "fuzz-again.bvh");
  if (back.joints.size() != clip.joints.size() || back.values != clip.values || back.frame_time != clip.frame_time)
    __builtin_trap();
  for (std::size_t i = 0; i < clip.joints.size(); ++i) {
    const auto &a = clip.joints[i], &b = back.joints[i];
    if (a.name != b.name || a.parent != b.parent || a.offset != b.offset || a.channels != b.channels ||
        a.end_site != b.end_site)
      __builtin_trap();
  }
  if (motion::to_bvh(back) != written) __builtin_trap();
  if (clip.frame_count() > 0) motion::joint_positions(clip, clip.frame_count() - 1, {0.01, motion::UpAxis::y});
  motion::LandmarkOptions options;
  options.drop_first_frame = text.size() % 2 == 1;  // both ways
  motion::to_landmarks(clip, options);
}

// A landmark map, parsed; written back, it must parse to the same joints.
inline void landmark_map_input(const std::string& text) {
  const motion::LandmarkMap map = motion::parse_landmark_map(text, "fuzz.map");
  if (motion::parse_landmark_map(motion::to_text(map), "fuzz-again.map").joints != map.joints) __builtin_trap();
}

}  // namespace humandyn::fuzz
