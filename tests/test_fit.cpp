// The motion pipeline's fit: a body scaled to a clip, and the floating form's pose per frame from the
// clip's segment directions. Closed loop: landmarks made by the engine's own forward kinematics from
// known angles are fitted back to those angles.
#include "humandyn/motion/fit.hpp"
#include "humandyn/motion/import.hpp"
#include "support/floating_motion.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace test_fit {

using namespace humandyn;
using namespace humandyn::motion;

namespace {

// A body whose landmarks the tests make: the default person, with a lower back, foot and head.
ClipBody source_body(double lower_back = 0.1) {
  ClipBody b = humandyn::testing::closed_loop_body();
  b.stature = anthropometry::reference_male.height;
  b.lower_back_length = lower_back;
  return b;
}

// A smooth whole-body motion (a stylised walk with arm swing, the pelvis turning and travelling).
struct Motion {
  Pose<double> base(const FloatingModel& model, double t) const {
    Pose<double> X = model.base_pose();
    const Eigen::Matrix3d turn = (Eigen::AngleAxisd(0.3 * std::sin(2 * t) + 0.5, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(0.1 * std::sin(3 * t), Eigen::Vector3d::UnitX()) *
                                  Eigen::AngleAxisd(0.15 * std::cos(2 * t), Eigen::Vector3d::UnitY()))
                                     .toRotationMatrix();
    X.R = turn * X.R;
    X.p += Eigen::Vector3d(1.2 * t, 0.05 * std::sin(4 * t), 0.03 * std::cos(6 * t));
    return X;
  }
  JointAngles q(double t, bool waist_pitch = true) const {
    JointAngles q;
    for (int i = 0; i < 16; ++i) q[i] = 0.2 + 0.4 * std::sin(5.0 * t + 0.7 * i) + 0.05 * i * std::cos(3.0 * t);
    if (!waist_pitch) q[seed_body.index("waist_pitch")] = 0;
    return q;
  }
};

LandmarkClip make_clip(const Fitter& source, const Motion& m, int frames, double h, bool waist_pitch = true) {
  LandmarkClip clip;
  clip.frame_time = h;
  clip.source = "synthetic";
  for (int k = 0; k < frames; ++k)
    clip.frames.push_back(source.landmarks(m.base(source.model(), k * h), m.q(k * h, waist_pitch)));
  return clip;
}

}  // namespace

TEST(Scale, RecoversTheLengthsAndDeLevasMasses) {
  const Fitter source(source_body());
  const LandmarkClip clip = make_clip(source, Motion{}, 50, 1.0 / 120);
  const ClipBody body = scale_to_clip(clip, {.mass = 70});
  EXPECT_EQ(body.parameters.name, clip.source + " (scaled to the clip, 70 kg)");  // the mass as given, no padding
  const SeedParameters &p = body.parameters, ref = source_body().parameters;
  for (const auto& [a, b] : {std::pair{p.a1, ref.a1},
                             {p.a2, ref.a2},
                             {p.d4, ref.d4},
                             {p.d6, ref.d6},
                             {p.d7, ref.d7},
                             {p.a8, ref.a8},
                             {p.a9, ref.a9},
                             {p.a16, ref.a16}})
    EXPECT_NEAR(a, b, 1e-12);
  EXPECT_NEAR(body.stature, anthropometry::reference_male.height, 1e-12);
  EXPECT_NEAR(body.foot_length, 0.19, 1e-12);
  EXPECT_NEAR(body.toe_drop, ref.a16, 1e-12) << "no planted foot in the clip: the toe on the sole";
  EXPECT_NEAR(body.head_length, 0.24, 1e-12);
  EXPECT_NEAR(body.lower_back_length, 0.1, 1e-12);
  // the whole body weighs the given mass, each segment its de Leva fraction of it
  const double total = p.shank.mass * 2 + p.thigh.mass * 2 + p.pelvis.mass + p.upper_body.mass + p.upper_arm.mass * 2 +
                       p.forearm.mass * 2 + p.foot.mass + p.stance_foot.mass;
  EXPECT_NEAR(total, 70.0, 1e-12);
  const double basis = 70.0 / anthropometry::whole_body_mass_fraction(anthropometry::Sex::Male);
  EXPECT_NEAR(p.thigh.mass, anthropometry::row("thigh", "HJC-KJC", anthropometry::Sex::Male).mass_fraction * basis,
              1e-12);
}

// A clip fitted with a body of other lengths: each length more than 5 % off the clip's own is named,
// with both values; the clip's own body and a length 3 % off are not.
TEST(Scale, AGivenBodyOfOtherLengthsIsNamed) {
  const Fitter source(source_body());
  const LandmarkClip clip = make_clip(source, Motion{}, 50, 1.0 / 120);
  const SeedParameters own = source_body().parameters;
  EXPECT_TRUE(length_mismatches(clip, own).empty());
  SeedParameters other = own;
  other.a2 *= 1.10;  // a thigh 10 % longer
  other.a8 *= 0.97;  // an upper arm 3 % shorter: within the tolerance
  const auto m = length_mismatches(clip, other);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].clip.dim, Dim::a2);
  EXPECT_STREQ(m[0].clip.between, "hip-knee");
  EXPECT_NEAR(m[0].clip.length, own.a2, 1e-12);
  EXPECT_NEAR(m[0].body, 1.10 * own.a2, 1e-12);
  EXPECT_EQ(length_mismatches(clip, other, 0.02).size(), 2u);
  // a length the clip does not show (both hips on one joint) is not compared, and refuses no import
  LandmarkClip one_hip = clip;
  for (auto& f : one_hip.frames) f[std::size_t(Landmark::l_hip)] = f[std::size_t(Landmark::r_hip)];
  const auto refusal = [](const LandmarkClip& c) {
    try {
      clip_lengths(c);
    } catch (const MotionError& e) {
      return std::string(e.what());
    }
    return std::string("no refusal");
  };
  EXPECT_EQ(refusal(one_hip), clip.source +
                                  ": the half hip-hip distance is 0 m, 1 mm or less: two landmarks at one point, or "
                                  "the clip read in too small a unit");
  // a clip read in micrometres for metres: its lengths, said as they are (once called zero)
  LandmarkClip tiny = clip;
  for (auto& f : tiny.frames)
    for (auto& p : f) p *= 1e-6;
  const std::string small = refusal(tiny);
  EXPECT_EQ(small.rfind(clip.source + ": the knee-ankle distance is 4", 0), 0u) << small;
  EXPECT_NE(small.find("e-07 m, 1 mm or less"), std::string::npos) << small;
  std::vector<LengthMismatch> m1;
  EXPECT_NO_THROW(m1 = length_mismatches(one_hip, own));
  for (const auto& x : m1) EXPECT_NE(x.clip.dim, Dim::d4) << x.clip.between;
  // the pipeline reports them for a given body only
  ImportOptions io;
  io.filter.cutoff = 0;
  EXPECT_TRUE(import_clip(clip, io).mismatched.empty());
  ClipBody given = source_body();
  given.parameters = other;
  io.body = given;
  EXPECT_EQ(import_clip(clip, io).mismatched.size(), 1u);
}

// One side's segment of no length (a map putting the left wrist on a joint at the left elbow's place, a
// clip whose left shank or foot has an offset of 0): the pooled median would halve the length silently;
// the scaling is refused, naming both landmarks.
TEST(Scale, ASegmentOfNoLengthOnOneSideIsRefused) {
  const Fitter source(source_body());
  const LandmarkClip clip = make_clip(source, Motion{}, 50, 1.0 / 120);
  EXPECT_NO_THROW(scale_to_clip(clip));
  for (const auto& [a, b] : {std::pair{Landmark::l_elbow, Landmark::l_wrist},
                             {Landmark::r_knee, Landmark::r_ankle},
                             {Landmark::l_ankle, Landmark::l_toe}}) {
    LandmarkClip bad = clip;
    for (auto& f : bad.frames) f[std::size_t(b)] = f[std::size_t(a)];
    try {
      scale_to_clip(bad);
      ADD_FAILURE() << landmark_names[std::size_t(b)] << " on " << landmark_names[std::size_t(a)] << " was accepted";
    } catch (const MotionError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(std::string(landmark_names[std::size_t(a)]) + " and " +
                       std::string(landmark_names[std::size_t(b)]) + " stand at one point"),
                std::string::npos)
          << m;
    }
  }
}

// A landmark a glitch put at 1e300 m, or every landmark 1e7 m away (a wrong unit): refused at its own
// frame before the filter spreads it (which reported a frame 11 earlier), 1e6 m still taken.
TEST(Scale, ALandmarkFarBeyondAnyCaptureVolumeIsRefusedAtItsFrame) {
  const Fitter source(source_body());
  const LandmarkClip clip = make_clip(source, Motion{}, 50, 1.0 / 120);
  for (const double far : {1e300, 1e7}) {
    LandmarkClip bad = clip;
    bad.frames[37][std::size_t(Landmark::pelvis)].x() = far;
    try {
      check_clip(bad);
      ADD_FAILURE() << far << " accepted";
    } catch (const MotionError& e) {
      EXPECT_NE(std::string(e.what()).find("frame 38: landmark 'pelvis' lies " + exact_number(far) + " m"),
                std::string::npos)
          << e.what();
    }
  }
  LandmarkClip moved = clip;
  for (auto& f : moved.frames)
    for (auto& p : f) p.y() += 1e6 - 5;
  EXPECT_NO_THROW(check_clip(moved));
}

TEST(Scale, TheToeDropOfAPlantedFoot) {
  // the body standing still, feet flat: the toe's drop below the ankle is measured
  ClipBody b = source_body();
  b.toe_drop = 0.035;
  const Fitter source(b);
  LandmarkClip clip;
  clip.frame_time = 0.01;
  clip.source = "standing";
  for (int k = 0; k < 20; ++k) clip.frames.push_back(source.landmarks(source.model().base_pose(), JointAngles::Zero()));
  EXPECT_NEAR(scale_to_clip(clip).toe_drop, 0.035, 1e-12);
  EXPECT_EQ(scale_to_clip(clip).planted_frames, 40);  // (both feet, every frame)
  // feet that never stand still (a treadmill): the toe on the sole, and the count says why
  for (std::size_t k = 0; k < clip.frames.size(); ++k)
    for (auto& p : clip.frames[k]) p.x() += 1.5 * double(k) * clip.frame_time * (p.z() < 0.2 ? -1 : 0);
  const ClipBody moving = scale_to_clip(clip);
  EXPECT_EQ(moving.planted_frames, 0);
  EXPECT_EQ(moving.toe_drop, moving.parameters.a16);
}

TEST(Fit, ClosedLoopGivesTheAnglesBack) {
  const Fitter source(source_body());
  const Motion motion;
  const double h = 1.0 / 120;
  const LandmarkClip clip = make_clip(source, motion, 240, h);
  const ClipBody body = scale_to_clip(clip, {.mass = 73});
  const Fitter fitter(body);
  ASSERT_TRUE(fitter.waist_pitch_fitted());
  const ClipFit fit = fitter.fit(clip);
  ASSERT_EQ(fit.frames.size(), clip.frames.size());
  double worst = 0, worst_R = 0, worst_residual = 0;
  for (std::size_t k = 0; k < fit.frames.size(); ++k) {
    const auto& f = fit.frames[k];
    worst = std::max(worst, (f.q - motion.q(double(k) * h)).cwiseAbs().maxCoeff());
    worst_R = std::max(worst_R, (f.base.R - motion.base(source.model(), double(k) * h).R).cwiseAbs().maxCoeff());
    for (double r : f.residual) worst_residual = std::max(worst_residual, r);
  }
  EXPECT_LT(worst, 1e-6) << "rad";
  EXPECT_LT(worst_R, 1e-6);
  EXPECT_LT(worst_residual, 1e-6) << "degrees";
}

TEST(Fit, WithoutALowerBackTheWaistPitchStaysAtZero) {
  const Fitter source(source_body(0.0));
  const Motion motion;
  const double h = 1.0 / 120;
  const LandmarkClip clip = make_clip(source, motion, 60, h, false);
  const Fitter fitter(scale_to_clip(clip));
  EXPECT_FALSE(fitter.waist_pitch_fitted());
  const ClipFit fit = fitter.fit(clip);
  for (std::size_t k = 0; k < fit.frames.size(); ++k) {
    EXPECT_LT((fit.frames[k].q - motion.q(double(k) * h, false)).cwiseAbs().maxCoeff(), 1e-6) << "frame " << k;
    EXPECT_EQ(fit.frames[k].residual[std::size_t(FitSegment::pelvis_up)], 0.0) << "no lower back, no residual";
    for (double r : fit.frames[k].residual) EXPECT_LT(r, 1e-6);
  }
}

// A given body with a lower back, on a clip that shows none (its lower back on the mid-hip point): the
// waist pitch is held at zero as for a body scaled to that clip. Fitted, its direction matched to no
// direction, it had drifted tens of radians with the hip pitches undoing it.
TEST(Fit, AGivenBodysLowerBackIsNotFittedOnAClipWithoutOne) {
  const Fitter source(source_body(0.0));
  const Motion motion;
  const double h = 1.0 / 120;
  const LandmarkClip clip = make_clip(source, motion, 60, h, false);
  ImportOptions options;
  options.body = scale_to_clip(clip);
  options.body->lower_back_length = 0.2;
  const ImportedClip m = import_clip(clip, options);
  EXPECT_FALSE(m.waist_pitch_fitted);
  EXPECT_EQ(m.body.lower_back_length, 0.2);  // (the body as given)
  for (std::size_t k = 0; k < m.fit.frames.size(); ++k)
    EXPECT_LT((m.fit.frames[k].q - motion.q(double(k) * h, false)).cwiseAbs().maxCoeff(), 1e-6) << "frame " << k;
  // the same clip with its lower back: fitted
  const LandmarkClip with_back = make_clip(Fitter(source_body()), motion, 60, h);
  EXPECT_TRUE(import_clip(with_back, options).waist_pitch_fitted);
}

// A segment whose ends come within 1 mm of each other in a few frames of the clip (a toe on its ankle):
// it has no direction there and is not fitted there (residual 0). The foot hangs on the ankle alone, so
// the ankle keeps the angle of the frame before; fitted to the direction of what is left (0.5 mm up), it
// turned the foot on end.
TEST(Fit, ASegmentOfNoLengthInAFrameIsNotFittedThere) {
  const Fitter source(source_body());
  const Motion motion;
  const double h = 1.0 / 120;
  LandmarkClip clip = make_clip(source, motion, 40, h);
  const Fitter fitter(scale_to_clip(clip));
  const ClipFit before = fitter.fit(clip);
  for (int k = 20; k < 23; ++k) {
    auto& f = clip.frames[std::size_t(k)];
    f[std::size_t(Landmark::r_toe)] = f[std::size_t(Landmark::r_ankle)] + Eigen::Vector3d(0, 0, 5e-4);
  }
  const ClipFit fit = fitter.fit(clip);
  const auto& joints = fitter.model().description().joints;
  const auto ankle =
      Eigen::Index(std::find_if(joints.begin(), joints.end(), [](const auto& j) { return j.link_name == "r_foot"; }) -
                   joints.begin());
  ASSERT_LT(ankle, 16);
  for (int k = 20; k < 23; ++k) {
    const FrameFit& f = fit.frames[std::size_t(k)];
    EXPECT_EQ(f.residual[std::size_t(FitSegment::r_foot)], 0.0) << "frame " << k;
    EXPECT_EQ(f.q[ankle], before.frames[19].q[ankle]) << "frame " << k;
  }
  EXPECT_LT((fit.frames[30].q - before.frames[30].q).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(Fit, HipRotationLandsInTheShankAndFootResiduals) {
  // the clip's right shank and foot turned 20 degrees about the thigh's axis (an internal hip rotation
  // the model does not have), the knee bent: the shank, foot and thigh take it; the pelvis and trunk,
  // weighted more, turn by less than half a degree; the other limbs hardly move
  const Fitter source(source_body());
  JointAngles q = JointAngles::Zero();
  const int knee = source.model().description().joints[2].name == "r_knee_pitch" ? 2 : -1;
  ASSERT_EQ(knee, 2);
  q[knee] = 0.8;  // bent (floating form: flexion = +q)
  const Pose<double> X = source.model().base_pose();
  LandmarkFrame f = source.landmarks(X, q);
  const Eigen::Vector3d hip = f[int(Landmark::r_hip)], axis = (f[int(Landmark::r_knee)] - hip).normalized();
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(20 * M_PI / 180, axis).toRotationMatrix();
  for (Landmark l : {Landmark::r_ankle, Landmark::r_toe}) f[int(l)] = hip + turn * (f[int(l)] - hip);
  const Fitter fitter(source_body());
  FrameFit start;
  start.base = X;
  start.q = q;
  const FrameFit fit = fitter.fit(f, start);
  const auto r = [&](FitSegment s) { return fit.residual[std::size_t(s)]; };
  EXPECT_GT(r(FitSegment::r_shank), 3.0);
  for (int s = 0; s < num_fit_segments; ++s) {
    if (FitSegment(s) == FitSegment::r_shank || FitSegment(s) == FitSegment::r_foot ||
        FitSegment(s) == FitSegment::r_thigh)
      continue;
    EXPECT_LT(fit.residual[std::size_t(s)], 0.5) << fit_segments[std::size_t(s)].name;
  }
  EXPECT_GT(r(FitSegment::r_shank), r(FitSegment::r_thigh));
}

TEST(Fit, ANonFiniteLandmarkIsAnErrorNamingFrameAndLandmark) {
  const Fitter source(source_body());
  LandmarkClip clip = make_clip(source, Motion{}, 10, 0.01);
  clip.source = "walk.bvh";
  clip.frames[7][int(Landmark::l_knee)].y() = std::nan("");
  try {
    (void)scale_to_clip(clip);
    FAIL() << "no error";
  } catch (const MotionError& e) {
    EXPECT_STREQ(e.what(), "walk.bvh: frame 8: landmark 'l_knee' is not finite");  // frames counted from 1
  }
  EXPECT_THROW((void)Fitter(source_body()).fit(clip), MotionError);
  // one frame at a time (a live capture, noexcept): a dropped or glitched marker leaves the frame unfitted,
  // the start held and the landmark named, where its segments once came out as fitted exactly
  const Fitter fitter(source_body());
  const FrameFit start = fitter.fit(clip.frames[6], fitter.initial_guess(clip.frames[6]));
  ASSERT_EQ(start.unusable_landmark, -1);
  for (const double glitch : {std::nan(""), std::numeric_limits<double>::infinity(), -2 * max_landmark_coordinate}) {
    LandmarkFrame f = clip.frames[6];
    f[int(Landmark::r_knee)].z() = glitch;
    const FrameFit held = fitter.fit(f, start);
    EXPECT_EQ(held.unusable_landmark, int(Landmark::r_knee)) << glitch;
    EXPECT_EQ(held.iterations, 0);
    EXPECT_EQ(held.q, start.q);
    EXPECT_EQ(held.base.p, start.base.p);
    EXPECT_EQ(held.residual, start.residual);
    // the next good frame is fitted again
    EXPECT_EQ(fitter.fit(clip.frames[8], held).unusable_landmark, -1);
    // a capture that starts on such a frame, at a landmark the guess takes: its guess is no pose, and the
    // first good frame starts afresh from its own
    f = clip.frames[6];
    f[int(Landmark::r_hip)].x() = glitch;
    EXPECT_FALSE(fitter.initial_guess(f).base.R.allFinite());
    const FrameFit first = fitter.fit(f, fitter.initial_guess(f));
    EXPECT_EQ(first.unusable_landmark, int(Landmark::r_hip));
    const FrameFit next = fitter.fit(clip.frames[8], first);
    EXPECT_EQ(next.unusable_landmark, -1);
    EXPECT_TRUE(next.q.allFinite() && next.base.R.allFinite());
    EXPECT_EQ(next.q, fitter.fit(clip.frames[8], fitter.initial_guess(clip.frames[8])).q);
  }
}

TEST(Fit, AFrameAllocatesNothingAndIsDeterministic) {
  const Fitter source(source_body());
  const LandmarkClip clip = make_clip(source, Motion{}, 3, 0.01);
  const Fitter fitter(source_body());
  const FrameFit start = fitter.initial_guess(clip.frames[0]);
  const FrameFit a = fitter.fit(clip.frames[1], start);
  Eigen::internal::set_is_malloc_allowed(false);
  const FrameFit b = fitter.fit(clip.frames[1], start);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_EQ(a.q, b.q);
  EXPECT_EQ(a.base.R, b.base.R);
}

}  // namespace test_fit
