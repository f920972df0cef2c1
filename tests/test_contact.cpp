// Contact phases on synthetic foot motions, the split of the ground reaction in double support, and
// the stance-rooted form of a floating motion: exact for a foot at rest, and the moving foot's motion
// equal to its pose differentiated.
#include "humandyn/motion/contact.hpp"
#include "humandyn/motion/import.hpp"
#include "support/floating_motion.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace test_contact {

using namespace humandyn;
using namespace humandyn::motion;

namespace {

// A foot either planted at x (toe 2 cm, ankle 8 cm above the floor at 0.01 m) or swinging forward at
// 1.5 m/s 30 cm up.
void foot(LandmarkFrame& f, Landmark ankle, Landmark toe, bool planted, double x, double t) {
  const double lift = planted ? 0 : 0.3, ahead = planted ? x : x + 1.5 * t;
  f[std::size_t(ankle)] = Eigen::Vector3d(ahead, 0, 0.09 + lift);
  f[std::size_t(toe)] = Eigen::Vector3d(ahead + 0.15, 0, 0.03 + lift);
}

// right 0-29, double 30-39, left 40-69, flight 70-79, right 80-99 (each foot planted one frame longer
// at either end: the frame next to a swinging one moves fast by central differences)
LandmarkClip walk() {
  LandmarkClip clip;
  clip.frame_time = 0.01;
  clip.source = "synthetic walk";
  for (int k = 0; k < 100; ++k) {
    LandmarkFrame f;
    for (auto& p : f) p.setZero();
    const double t = k * 0.01;
    const bool right = k <= 40 || k >= 79, left = k >= 29 && k <= 70;
    foot(f, Landmark::r_ankle, Landmark::r_toe, right, 0.0, t);
    foot(f, Landmark::l_ankle, Landmark::l_toe, left, 0.5, t);
    clip.frames.push_back(f);
  }
  return clip;
}

}  // namespace

TEST(ContactPhases, AWalkWithADoubleSupportAndAFlight) {
  const Phases p = contact_phases(walk());
  for (double floor : p.floor) EXPECT_NEAR(floor, 0.03, 1e-15);  // the lowest toe within a second
  for (int k = 0; k < 100; ++k) {
    const Phase want = k < 30   ? Phase::right
                       : k < 40 ? Phase::double_support
                       : k < 70 ? Phase::left
                       : k < 80 ? Phase::flight
                                : Phase::right;
    EXPECT_EQ(p.phase[std::size_t(k)], want) << "frame " << k;
  }
  // the reaction moves from the right foot to the left across the double support, smoothly
  for (int k = 0; k < 30; ++k) EXPECT_EQ(p.right_share[std::size_t(k)], 1.0);
  for (int k = 30; k < 40; ++k) {
    const double tau = (k - 29) / 11.0;
    EXPECT_NEAR(p.right_share[std::size_t(k)], 0.5 * (1 + std::cos(M_PI * tau)), 1e-15);
    EXPECT_LT(p.right_share[std::size_t(k)], p.right_share[std::size_t(k - 1)]);
    EXPECT_EQ(p.stance[std::size_t(k)], k < 35 ? Foot::right : Foot::left) << k;
  }
  for (int k = 40; k < 80; ++k) EXPECT_EQ(p.right_share[std::size_t(k)], 0.0) << "left, then flight after it";
  for (int k = 80; k < 100; ++k) EXPECT_EQ(p.stance[std::size_t(k)], Foot::right);
}

TEST(ContactPhases, ThresholdsAreOverridable) {
  // a floor given by hand is used as it is
  ContactOptions o;
  o.floor = -1.0;  // far below: nothing is low enough
  const Phases p = contact_phases(walk(), o);
  for (double floor : p.floor) EXPECT_EQ(floor, -1.0);
  for (Phase ph : p.phase) EXPECT_EQ(ph, Phase::flight);
  // a foot low but sliding faster than max_speed is not on the ground
  o = {};
  o.max_speed = 1e-3;
  o.ankle_height = 1.0;
  o.toe_height = 1.0;
  const Phases q = contact_phases(walk(), o);
  EXPECT_EQ(q.phase[50], Phase::left);
}

TEST(ContactPhases, TheFloorFollowsTheClipAndBlipsAreIgnored) {
  // the same walk on a floor that rises 5 cm a second, with the left foot lifted for one frame in its
  // stance and the right foot touching down for one frame in its swing
  LandmarkClip clip = walk();
  for (std::size_t k = 0; k < clip.frames.size(); ++k)
    for (auto& p : clip.frames[k]) p.z() += 0.05 * double(k) * clip.frame_time;
  for (Landmark l : {Landmark::l_ankle, Landmark::l_toe}) clip.frames[55][std::size_t(l)].z() += 0.3;
  for (Landmark l : {Landmark::r_ankle, Landmark::r_toe})
    clip.frames[60][std::size_t(l)].z() = clip.frames[59][std::size_t(Landmark::l_toe)].z();
  ContactOptions o;
  o.max_speed = 1e9;  // heights only: the blips move fast
  o.floor_window = 0.1;
  const Phases p = contact_phases(clip, o);
  EXPECT_NEAR(p.floor[90], 0.03 + 0.05 * 0.8, 1e-12) << "the lowest toe within 0.1 s";
  for (int k = 45; k < 65; ++k) EXPECT_EQ(p.phase[std::size_t(k)], Phase::left) << k;
  // with no blip filter, both blips show
  o.min_frames = 1;
  const Phases raw = contact_phases(clip, o);
  EXPECT_EQ(raw.phase[55], Phase::flight);
  EXPECT_EQ(raw.phase[60], Phase::double_support);
}

TEST(SplitReaction, TheTwoFeetAddUpToTheTotal) {
  GroundReaction<double> total;
  total.force = Eigen::Vector3d(30, -12, 700);
  total.moment = Eigen::Vector3d(5, -40, 3);
  total.origin = Eigen::Vector3d(0.1, -0.05, 0.08);
  const Eigen::Vector3d R(0.0, -0.1, 0.0), L(0.4, 0.1, 0.0), P(1, 2, 3);
  for (double s : {0.0, 0.3, 0.5, 1.0}) {
    const auto w = split_reaction(total, s, R, L);
    EXPECT_LT((w[0].force + w[1].force - total.force).norm(), 1e-12);
    const Eigen::Vector3d about_P = w[0].moment + (R - P).cross(w[0].force) + w[1].moment + (L - P).cross(w[1].force);
    EXPECT_LT((about_P - total.moment_about(P)).norm(), 1e-10) << s;
    EXPECT_LT((w[0].force - s * total.force).norm(), 1e-12);
  }
  const auto all_right = split_reaction(total, 1.0, R, L);
  EXPECT_LT((all_right[0].moment - total.moment_about(R)).norm(), 1e-12);
  EXPECT_EQ(all_right[1].force.norm(), 0.0);
}

namespace {

// a smooth motion of a stance-rooted model, its foot at rest
HumanModel<double>::JointVector stance_q(double t, int d = 0) {
  HumanModel<double>::JointVector q;
  for (int i = 0; i < 16; ++i) {
    const double w = 2.0 + 0.1 * i, ph = 0.5 * i;
    q[i] = d == 0   ? 0.3 * std::sin(w * t + ph)
           : d == 1 ? 0.3 * w * std::cos(w * t + ph)
                    : -0.3 * w * w * std::sin(w * t + ph);
  }
  return q;
}

}  // namespace

TEST(StanceForms, AFootAtRestComesBackExactlyOnEitherFoot) {
  const SeedParameters p = default_parameters();
  const StanceForms forms(p);
  for (Foot foot : {Foot::right, Foot::left}) {
    const HumanModel<double>& stance = forms.model(foot);
    const FloatingMap<HumanModel<double>, FloatingModel> map(stance, forms.floating());
    Data<HumanModel<double>> ws(stance);
    for (int k = 0; k < 50; ++k) {
      const double t = 0.037 * k;
      const auto q = stance_q(t), qd = stance_q(t, 1), qdd = stance_q(t, 2);
      FloatingState<FloatingModel> x(forms.floating());
      map.state(stance, forms.floating(), ws, q, qd, x);
      FloatingFrame f;
      f.base = x.base, f.v_b = x.v_b, f.q = x.q, f.qd = x.qd;
      map.acceleration(stance, ws, q, qd, qdd, f.a_b, f.qdd);
      StanceFrame s;
      Eigen::internal::set_is_malloc_allowed(false);
      forms.stance_state(foot, f, s);
      Eigen::internal::set_is_malloc_allowed(true);
      for (int i = 0; i < 16; ++i) EXPECT_NEAR(std::remainder(s.q[i] - q[i], 2 * M_PI), 0, 1e-12) << i;
      EXPECT_LT((s.qd - qd).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_LT((s.qdd - qdd).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_LT((s.base.pose.R - stance.base_pose().R).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_LT((s.base.pose.p - stance.base_pose().p).norm(), 1e-12);
      EXPECT_LT(s.base.w.norm(), 1e-10);
      EXPECT_LT(s.base.wd.norm(), 1e-9);
      EXPECT_LT(s.base.a.norm(), 1e-9);
    }
  }
}

TEST(StanceForms, AMovingFootsMotionIsItsPoseDifferentiated) {
  // a floating motion (base turning and travelling, joints moving): the stance foot's angular velocity,
  // angular acceleration and origin acceleration equal its pose differentiated (fourth-order differences)
  const StanceForms forms(default_parameters());
  const auto frame = [&](double t) {
    FloatingFrame f;
    const Eigen::Vector3d axis = Eigen::Vector3d(0.3, 0.2, 1).normalized();
    const double th = 0.4 * t + 0.2 * t * t, thd = 0.4 + 0.4 * t, thdd = 0.4;
    f.base.R = Eigen::AngleAxisd(th, axis).toRotationMatrix() * forms.floating().base_pose().R;
    f.base.p = Eigen::Vector3d(t, 0.1 * t * t, 0.9 + 0.05 * std::sin(3 * t));
    const Eigen::Vector3d pd(1, 0.2 * t, 0.15 * std::cos(3 * t)), pdd(0, 0.2, -0.45 * std::sin(3 * t));
    const Eigen::Vector3d wb = f.base.R.transpose() * axis * thd, wdb = f.base.R.transpose() * axis * thdd;
    const Eigen::Vector3d vb = f.base.R.transpose() * pd;
    f.v_b << wb, vb;
    f.a_b << wdb, f.base.R.transpose() * pdd - wb.cross(vb);  // d/dt (R^T p') = R^T p'' - w_b x v_b
    f.q = stance_q(t), f.qd = stance_q(t, 1), f.qdd = stance_q(t, 2);
    return f;
  };
  for (Foot foot : {Foot::right, Foot::left})
    for (double t : {0.1, 0.7}) {
      const double h = 1e-3;
      StanceFrame s, m2, m1, p1, p2;
      forms.stance_state(foot, frame(t), s);
      forms.stance_state(foot, frame(t - 2 * h), m2);
      forms.stance_state(foot, frame(t - h), m1);
      forms.stance_state(foot, frame(t + h), p1);
      forms.stance_state(foot, frame(t + 2 * h), p2);
      const auto d1 = [&](const auto& a, const auto& b, const auto& c, const auto& d) {
        return ((a - d) - 8 * (b - c)) / (12 * h);  // a: t-2h, b: t-h, c: t+h, d: t+2h
      };
      const Eigen::Vector3d pdd =
          (-m2.base.pose.p + 16 * m1.base.pose.p - 30 * s.base.pose.p + 16 * p1.base.pose.p - p2.base.pose.p) /
          (12 * h * h);
      EXPECT_LT((s.base.a - pdd).norm(), 1e-5) << "origin acceleration";
      const Eigen::Matrix3d Rd = d1(m2.base.pose.R, m1.base.pose.R, p1.base.pose.R, p2.base.pose.R);
      const Eigen::Matrix3d W = Rd * s.base.pose.R.transpose();  // [w]x
      EXPECT_LT((Eigen::Vector3d(W(2, 1), W(0, 2), W(1, 0)) - s.base.w).norm(), 1e-8) << "angular velocity";
      EXPECT_LT((d1(m2.base.w, m1.base.w, p1.base.w, p2.base.w) - s.base.wd).norm(), 1e-8) << "angular acceleration";
    }
}

TEST(Pipeline, ClosedLoopTorquesWithinTheFiltersError) {
  // a slow whole-body motion (0.4-0.875 Hz) known in closed form: its landmarks by forward kinematics,
  // scaled, fitted, filtered at 6 Hz and differentiated; the floating form's torques and base wrench
  // equal those of the exact motion to what the filter (a gain of 1 - 4.4e-4 at 0.875 Hz) and the
  // central differences ((h w)^2 / 12 = 1.8e-4 on accelerations) explain: 1e-3 of the largest (it is
  // 1.1e-4 for the torques, 6e-5 for the base wrench)
  const Fitter source(humandyn::testing::closed_loop_body());
  const FloatingModel& model = source.model();
  const double h = 1.0 / 120, T = 4.0;
  const auto exact = [&](double t) { return humandyn::testing::turning_walk(model, t); };
  LandmarkClip clip;
  clip.frame_time = h;
  clip.source = "closed loop";
  for (int k = 0; k * h <= T; ++k) {
    const FloatingFrame f = exact(k * h);
    clip.frames.push_back(source.landmarks(f.base, f.q));
  }
  ImportOptions options;
  options.scale.mass = 73;
  options.filter.cutoff = 6;
  const ImportedClip imported = import_clip(clip, options);
  const FloatingTrajectory& motion = imported.motion;
  const FloatingModel fitted = floating_model(imported.body.parameters);
  FloatingData<FloatingModel> a(model), b(fitted);
  double largest = 0, worst = 0, largest_w = 0, worst_w = 0;
  for (std::size_t k = 60; k + 60 < motion.frames.size(); ++k) {  // 0.5 s in from either end
    const FloatingFrame e = exact(double(k) * h), &m = motion.frames[k];
    const JointAngles tau_e = floating_rnea(model, a, e.base, e.v_b, e.a_b, e.q, e.qd, e.qdd);
    const JointAngles tau_m = floating_rnea(fitted, b, m.base, m.v_b, m.a_b, m.q, m.qd, m.qdd);
    largest = std::max(largest, tau_e.cwiseAbs().maxCoeff());
    worst = std::max(worst, (tau_m - tau_e).cwiseAbs().maxCoeff());
    largest_w = std::max(largest_w, a.base_wrench.cwiseAbs().maxCoeff());
    worst_w = std::max(worst_w, (b.base_wrench - a.base_wrench).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-3 * largest) << worst << " of " << largest << " N m";
  EXPECT_LT(worst_w, 1e-3 * largest_w) << worst_w << " of " << largest_w;
  // the stance-rooted frames are the floating ones carried to each frame's stance foot
  ASSERT_EQ(imported.stance.size(), clip.frames.size());
  const StanceForms forms(imported.body.parameters);
  StanceFrame s;
  forms.stance_state(imported.phases.stance[100], motion.frames[100], s);
  EXPECT_EQ(s.q, imported.stance[100].q);
  EXPECT_EQ(s.base.a, imported.stance[100].base.a);
}

TEST(ContactPhases, AFloorWindowLongerThanTheClipIsTheWholeClip) {
  // a frame time of 1e-12 s: the 1-s window is 1e12 frames, the whole clip (it overflowed an int)
  LandmarkClip clip = walk();
  clip.frame_time = 1e-12;
  const Phases p = contact_phases(clip);
  for (double floor : p.floor) EXPECT_NEAR(floor, 0.03, 1e-15);
}

TEST(Pipeline, StatesBeyondDoublesRangeAreRefusedNamingTheFrame) {
  // the closed-loop body's landmarks with one coordinate at 1e308: differences overflow to infinity
  const ClipBody body = humandyn::testing::closed_loop_body();
  const Fitter source(body);
  LandmarkClip clip;
  clip.frame_time = 1.0 / 120;
  clip.source = "far.bvh";
  for (int k = 0; k < 40; ++k) {
    const FloatingFrame f = humandyn::testing::turning_walk(source.model(), k / 120.0);
    clip.frames.push_back(source.landmarks(f.base, f.q));
  }
  ImportOptions options;
  options.body = body;
  {  // a coordinate of 1e308: refused at its own frame, before the filter spreads it
    LandmarkClip far = clip;
    for (auto& p : far.frames[20]) p.x() += 1e308;
    try {
      import_clip(far, options);
      ADD_FAILURE() << "a clip with a coordinate of 1e308 imported";
    } catch (const MotionError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("far.bvh: frame 21: landmark 'pelvis' lies 1e+308 m from the origin", 0), 0u) << what;
    }
  }
  {  // a frame time of 1e-300 s, unfiltered: the accelerations overflow
    LandmarkClip fast = clip;
    fast.frame_time = 1e-300;
    ImportOptions unfiltered = options;
    unfiltered.filter.cutoff = 0;
    try {
      import_clip(fast, unfiltered);
      ADD_FAILURE() << "a clip of frame time 1e-300 s imported";
    } catch (const MotionError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("far.bvh: frame ", 0), 0u) << what;
      EXPECT_NE(what.find("came out not finite"), std::string::npos) << what;
    }
  }
  {  // frame times of 1e306 s: 40 frames end at 3.9e307 s; of 4.7e306 s, frame 40 would come 1.8e308 s after
     // the first, beyond double's range: named
    LandmarkClip slow = clip;
    slow.frame_time = 1e306;
    ImportOptions unfiltered = options;
    unfiltered.filter.cutoff = 0;
    EXPECT_NO_THROW(import_clip(slow, unfiltered));
    slow.frame_time = 4.7e306;
    try {
      import_clip(slow, unfiltered);
      ADD_FAILURE() << "a clip whose last frame's time is beyond double's range imported";
    } catch (const MotionError& e) {
      EXPECT_EQ(std::string(e.what()),
                "far.bvh: frame 40: its time, 39 frame times of 4.7e+306 s, is beyond double's range");
    }
  }
  // and the filter's refusals name the clip too
  clip.frames.resize(9);
  try {
    import_clip(clip, options);
    ADD_FAILURE() << "9 frames filtered";
  } catch (const MotionError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("far.bvh: filter: the clip has 9 frames", 0), 0u) << e.what();
  }
}

}  // namespace test_contact
