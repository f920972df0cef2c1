// Motion-capture import (humandyn/bvh.hpp): a 10-s clip at 120 Hz on the CMU skeleton's layout (31 joints,
// 96 channels, 1200 frames, smooth motion of every channel), written once as BVH text; timed: reading that
// text, the landmarks of every frame from the clip, and both together (text to LandmarkClip), and writing.
// Then the whole import of a captured walk (CMU's 35_02 from the shared data, its frames repeated to 10 s):
// BVH text to landmarks, scaling, fitting, filtering, contact phases and stance forms (motion/import.hpp),
// what `humandyn motion import` does before it writes its files.
//
//   humandyn_bench_bvh [--benchmark_min_time=0.5] [--benchmark_repetitions=5]
#include "humandyn/bvh.hpp"
#include "humandyn/motion/import.hpp"

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

namespace {

namespace hm = humandyn::motion;

// The CMU layout: every joint after its parent, depth first; offsets of a 1.7-m person in CMU's units.
hm::BvhClip cmu_like_clip(int frames) {
  struct Row {
    const char* name;
    const char* parent;
    double x, y, z;
  };
  static constexpr Row rows[] = {
      {"Hips", "", 0, 0, 0},
      {"LHipJoint", "Hips", 0, 0, 0},
      {"LeftUpLeg", "LHipJoint", 1.8, -1.7, 0.8},
      {"LeftLeg", "LeftUpLeg", 2.4, -6.5, 0},
      {"LeftFoot", "LeftLeg", 2.5, -7.0, 0},
      {"LeftToeBase", "LeftFoot", 0.2, -0.4, 1.9},
      {"RHipJoint", "Hips", 0, 0, 0},
      {"RightUpLeg", "RHipJoint", -1.7, -1.7, 0.8},
      {"RightLeg", "RightUpLeg", -2.4, -6.7, 0},
      {"RightFoot", "RightLeg", -2.4, -6.7, 0},
      {"RightToeBase", "RightFoot", -0.2, -0.6, 2.0},
      {"LowerBack", "Hips", 0, 0, 0},
      {"Spine", "LowerBack", 0, 2.0, 0},
      {"Spine1", "Spine", 0, 2.0, 0},
      {"Neck", "Spine1", 0, 0, 0},
      {"Neck1", "Neck", 0, 1.6, 0},
      {"Head", "Neck1", 0, 1.6, 0},
      {"LeftShoulder", "Spine1", 0, 0, 0},
      {"LeftArm", "LeftShoulder", 3.2, 0.4, 0},
      {"LeftForeArm", "LeftArm", 5.0, 0, 0},
      {"LeftHand", "LeftForeArm", 3.4, 0, 0},
      {"LeftFingerBase", "LeftHand", 0, 0, 0},
      {"LeftHandIndex1", "LeftFingerBase", 0.7, 0, 0},
      {"LThumb", "LeftHand", 0, 0, 0},
      {"RightShoulder", "Spine1", 0, 0, 0},
      {"RightArm", "RightShoulder", -3.2, 0.4, 0},
      {"RightForeArm", "RightArm", -5.0, 0, 0},
      {"RightHand", "RightForeArm", -3.4, 0, 0},
      {"RightFingerBase", "RightHand", 0, 0, 0},
      {"RightHandIndex1", "RightFingerBase", -0.7, 0, 0},
      {"RThumb", "RightHand", 0, 0, 0},
  };
  hm::BvhClip clip;
  clip.source = "bench.bvh";
  clip.frame_time = 1.0 / 120;
  using C = hm::Channel;
  for (const Row& r : rows) {
    hm::BvhJoint j;
    j.name = r.name;
    j.parent = clip.find(r.parent);
    j.offset = {r.x, r.y, r.z};
    j.channels = {C::Zrotation, C::Yrotation, C::Xrotation};
    if (j.parent < 0) j.channels.insert(j.channels.begin(), {C::Xposition, C::Yposition, C::Zposition});
    clip.joints.push_back(j);
  }
  const int channels = clip.channel_count();
  for (int f = 0; f < frames; ++f)
    for (int c = 0; c < channels; ++c)
      clip.values.push_back(c == 2 ? 25.0 * f * clip.frame_time : 30.0 * std::sin(0.05 * f + c));  // walk along z
  return clip;
}

const std::string& clip_text() {
  static const std::string text = hm::to_bvh(cmu_like_clip(1200));
  return text;
}

hm::LandmarkOptions cmu_options() {
  hm::LandmarkOptions options;
  options.world = {hm::cmu_metres_per_unit, hm::UpAxis::y};
  options.drop_first_frame = true;
  return options;
}

void read_text(benchmark::State& state) {
  for ([[maybe_unused]] auto _ : state) benchmark::DoNotOptimize(hm::parse_bvh(clip_text(), "bench.bvh"));
  state.counters["bytes"] = double(clip_text().size());
}

void landmarks(benchmark::State& state) {
  const hm::BvhClip clip = hm::parse_bvh(clip_text(), "bench.bvh");
  const hm::LandmarkOptions options = cmu_options();
  for ([[maybe_unused]] auto _ : state) benchmark::DoNotOptimize(hm::to_landmarks(clip, options));
}

void text_to_landmarks(benchmark::State& state) {
  const hm::LandmarkOptions options = cmu_options();
  for ([[maybe_unused]] auto _ : state)
    benchmark::DoNotOptimize(hm::to_landmarks(hm::parse_bvh(clip_text(), "bench.bvh"), options));
}

void write_text(benchmark::State& state) {
  const hm::BvhClip clip = hm::parse_bvh(clip_text(), "bench.bvh");
  for ([[maybe_unused]] auto _ : state) benchmark::DoNotOptimize(hm::to_bvh(clip));
}

// A captured clip as BVH text, its frames repeated to `frames`; BvhError for a clip that cannot be read or
// has no frames
std::string repeated_text(const std::string& path, int frames) {
  hm::BvhClip clip = hm::read_bvh_file(path);
  const std::size_t per_frame = std::size_t(clip.channel_count());
  const std::size_t captured = per_frame > 0 ? clip.values.size() / per_frame : 0;
  if (captured == 0) throw hm::BvhError(path + ": no frames to repeat");
  std::vector<double> values;
  for (std::size_t f = 0; f < std::size_t(frames); ++f) {
    const auto from = clip.values.begin() + std::ptrdiff_t((f % captured) * per_frame);
    values.insert(values.end(), from, from + std::ptrdiff_t(per_frame));
  }
  clip.values = std::move(values);
  return hm::to_bvh(clip);
}

void import_walk(benchmark::State& state, const std::string& path) {
  std::string text;  // made here, so that a run that leaves this row out does not pay for it
  try {
    text = repeated_text(path, 1200);
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
    return;
  }
  const hm::LandmarkOptions options = cmu_options();
  for ([[maybe_unused]] auto _ : state)
    benchmark::DoNotOptimize(hm::import_clip(hm::to_landmarks(hm::parse_bvh(text, "walk.bvh"), options)));
  state.counters["frames"] = 1200;
}

}  // namespace

BENCHMARK(read_text)->Name("bvh/read/10s_120Hz")->Unit(benchmark::kMillisecond);
BENCHMARK(landmarks)->Name("bvh/landmarks/10s_120Hz")->Unit(benchmark::kMillisecond);
BENCHMARK(text_to_landmarks)->Name("bvh/read+landmarks/10s_120Hz")->Unit(benchmark::kMillisecond);
BENCHMARK(write_text)->Name("bvh/write/10s_120Hz")->Unit(benchmark::kMillisecond);

int main(int argc, char** argv) {
  // the captured walk lives in the shared data folder beside the project; without it that row is left out
  const std::string walk = HUMANDYN_SHARED_DATA "/mocap/35_02.bvh";
  if (std::filesystem::exists(walk))
    benchmark::RegisterBenchmark("motion/import/10s_120Hz", import_walk, walk)->Unit(benchmark::kMillisecond);
  else
    std::fprintf(stderr, "motion/import/10s_120Hz left out: %s is absent (CMU's clip 35_02, shared data)\n",
                 walk.c_str());
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
