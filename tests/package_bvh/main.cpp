// A BVH clip through the installed `bvh` component: read, written, read back the same; its end site placed.
#include <humandyn/bvh.hpp>

#include <cstdio>

int main() {
  const char* text =
      "HIERARCHY\nROOT hip\n{\n\tOFFSET 0 0 0\n\tCHANNELS 4 Xposition Yposition Zposition Zrotation\n"
      "\tEnd Site\n\t{\n\t\tOFFSET 1 0 0\n\t}\n}\nMOTION\nFrames: 1\nFrame Time: 0.01\n0 1 0 90\n";
  namespace hm = humandyn::motion;
  const hm::BvhClip clip = hm::parse_bvh(text, "consumer.bvh");
  const hm::BvhClip back = hm::parse_bvh(hm::to_bvh(clip), "again.bvh");
  // the end site: (0, 1, 0) + Rz(90°) (1, 0, 0) = (0, 2, 0) in the file, (0, 0, 2) in the world (Y up)
  const auto p = hm::joint_positions(clip, 0);
  std::printf("humandyn::bvh: %d frame, end site at (%g, %g, %g)\n", clip.frame_count(), p[1].x(), p[1].y(), p[1].z());
  return back.values == clip.values && (p[1] - Eigen::Vector3d(0, 0, 2)).norm() < 1e-12 ? 0 : 1;
}
