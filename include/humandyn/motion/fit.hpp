// Fitting a clip of landmarks (motion/landmarks.hpp) with the seed body: the body scaled to the
// clip's segment lengths, then per frame the pose of the floating form (the pelvis in the world and the
// 16 joint angles) whose segments point where the clip's do, in a least-squares sense.
//
//   const ClipBody body = scale_to_clip(clip, {.mass = 70});  // lengths from the clip, de Leva's masses
//   const Fitter fitter(body);
//   const ClipFit fit = fitter.fit(clip);  // per frame: base pose, q, residual per segment (degrees)
//
// The fit matches directions, not positions: a segment's direction is what a joint angle sets, and a
// direction does not care whether the clip's bones are a little longer or shorter than the model's. The
// base's position is the clip's mid-hip point. What the model cannot do (it has no hip or humeral
// rotation, no ankle roll, no trunk side-bend, no neck) stays in the residuals (docs/motion.md).
#pragma once

#include "humandyn/builders.hpp"
#include "humandyn/floating.hpp"
#include "humandyn/motion/landmarks.hpp"
#include "humandyn/stance.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace humandyn::motion {

/// Thrown for a clip the pipeline cannot use; the message names the clip, the frame and the landmark.
class MotionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline constexpr int num_landmarks = int(Landmark::count);
using LandmarkFrame = std::array<Eigen::Vector3d, num_landmarks>;

/// A landmark's name (its enumerator), for messages and CSV headers (landmark_names holds string literals).
inline const char* landmark_name(Landmark l) { return landmark_names[std::size_t(l)].data(); }

/// The largest landmark coordinate a clip may hold (m): a capture volume is metres across; beyond this a
/// value is a glitch (a marker's 1e300) or a wrong unit, which filtering would spread to other frames.
inline constexpr double max_landmark_coordinate = 1e6;

/// The first landmark of a frame that is not finite or lies beyond max_landmark_coordinate of the origin
/// along an axis (a dropped or glitched marker, a wrong unit), or -1: what no fit takes.
inline int first_unusable_landmark(const LandmarkFrame& f) noexcept {
  for (int l = 0; l < num_landmarks; ++l)
    if (!f[std::size_t(l)].allFinite() || f[std::size_t(l)].cwiseAbs().maxCoeff() > max_landmark_coordinate) return l;
  return -1;
}

/// Checks that a clip can be fitted: a positive frame time, at least one frame, no unusable landmark
/// (first_unusable_landmark). Throws MotionError naming the clip, the frame (LandmarkClip::frame_number)
/// and the landmark.
inline void check_clip(const LandmarkClip& clip) {
  if (!(clip.frame_time > 0) || !std::isfinite(clip.frame_time))
    throw MotionError(clip.source + ": frame time " + exact_number(clip.frame_time) + " s must be positive");
  if (clip.frames.empty()) throw MotionError(clip.source + ": the clip has no frames");
  for (std::size_t f = 0; f < clip.frames.size(); ++f) {
    const int l = first_unusable_landmark(clip.frames[f]);
    if (l < 0) continue;
    const Eigen::Vector3d& p = clip.frames[f][std::size_t(l)];
    const std::string landmark = clip.source + ": frame " + std::to_string(clip.frame_number(f)) + ": landmark '" +
                                 landmark_name(Landmark(l)) + "'";
    if (!p.allFinite()) throw MotionError(landmark + " is not finite");
    throw MotionError(landmark + " lies " + exact_number(p.cwiseAbs().maxCoeff()) +
                      " m from the origin along an axis, beyond " + exact_number(max_landmark_coordinate) +
                      " m (a glitch in the capture, or a wrong unit)");
  }
}

/// What the scaling needs beside the clip.
struct ScaleOptions {
  double mass = 70.0;                                 ///< total body mass (kg)
  anthropometry::Sex sex = anthropometry::Sex::Male;  ///< de Leva's reference subject for the segments
  double min_lower_back = 0.02;                       ///< shortest usable mid-hip to lower-back distance (m)
};

/// A body scaled to a clip, and the clip's landmark geometry the fit needs.
struct ClipBody {
  SeedParameters parameters;     ///< the seed body's lengths (m) and segments
  double stature = 0;            ///< estimated stature (m): from the leg's length, de Leva's proportions
  double foot_length = 0;        ///< median ankle-to-toe distance (m)
  double toe_drop = 0;           ///< how far the toe lies below the ankle with the foot flat (m)
  int planted_frames = 0;        ///< the clip's frames of a planted foot (a frame counts once for each planted
                                 ///< foot), which toe_drop is measured on (fewer than 10: toe_drop is a16, not
                                 ///< measured); import_clip counts them for a given body too
  double head_length = 0;        ///< median neck-to-head distance (m)
  double lower_back_length = 0;  ///< median mid-hip-to-lower-back distance (m); 0 when below min_lower_back
};

namespace detail {

inline Eigen::Vector3d at(const LandmarkFrame& f, Landmark l) { return f[std::size_t(l)]; }

// The clip's mid-hip point: the model's pelvis origin.
inline Eigen::Vector3d mid_hip(const LandmarkFrame& f) {
  return 0.5 * (at(f, Landmark::r_hip) + at(f, Landmark::l_hip));
}

inline double median(std::vector<double> v) {
  const auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  double m = *mid;
  if (v.size() % 2 == 0) m = 0.5 * (m + *std::max_element(v.begin(), mid));
  return m;
}

// median over the frames of the distance between two landmarks (of either pair, times factor)
inline double median_distance(const LandmarkClip& clip, std::initializer_list<std::pair<Landmark, Landmark>> pairs,
                              double factor = 1.0) {
  std::vector<double> v;
  v.reserve(clip.frames.size() * pairs.size());
  for (const auto& f : clip.frames)
    for (const auto& [a, b] : pairs) v.push_back(factor * (at(f, a) - at(f, b)).norm());
  return median(std::move(v));
}

// median over the frames of a landmark's distance from the mid-hip point
inline double median_from_mid_hip(const LandmarkClip& clip, Landmark l) {
  std::vector<double> v;
  v.reserve(clip.frames.size());
  for (const auto& f : clip.frames) v.push_back((at(f, l) - mid_hip(f)).norm());
  return median(std::move(v));
}

}  // namespace detail

/// One seed length as a clip shows it: the median over the frames of a landmark distance (m).
struct ClipLength {
  Dim dim;              ///< the seed dimension (builders.hpp), e.g. Dim::a2, the thigh
  const char* between;  ///< the landmarks measured, e.g. "hip-knee"
  double length;        ///< m
};

namespace detail {

// The shortest distance a clip shows as a length (m): two landmarks closer lie on one joint.
inline constexpr double min_clip_length = 1e-3;

// The seed lengths a clip measures, none checked (clip_lengths)
inline std::array<ClipLength, 7> measured_lengths(const LandmarkClip& clip) {
  using enum Landmark;
  return {{
      {Dim::a1, "knee-ankle", median_distance(clip, {{r_knee, r_ankle}, {l_knee, l_ankle}})},
      {Dim::a2, "hip-knee", median_distance(clip, {{r_hip, r_knee}, {l_hip, l_knee}})},
      {Dim::d4, "half hip-hip", median_distance(clip, {{r_hip, l_hip}}, 0.5)},
      {Dim::d6, "mid-hip-neck", median_from_mid_hip(clip, neck)},
      {Dim::d7, "half shoulder-shoulder", median_distance(clip, {{r_shoulder, l_shoulder}}, 0.5)},
      {Dim::a8, "shoulder-elbow", median_distance(clip, {{r_shoulder, r_elbow}, {l_shoulder, l_elbow}})},
      {Dim::a9, "elbow-wrist", median_distance(clip, {{r_elbow, r_wrist}, {l_elbow, l_wrist}})},
  }};
}

}  // namespace detail

/// The seed lengths a clip measures (a1, a2, d4, d6, d7, a8, a9: shank, thigh, half the hip width,
/// mid-hip to neck, half the shoulder width, upper arm, forearm), each the median over the frames of
/// its landmark distance (both sides pooled).
/// \throws MotionError for a clip check_clip refuses or a distance that comes out 1 mm or less (its value said),
///   on either side alone too (and the ankle-toe distances, the feet's length): two landmarks at one
///   point, as where a map puts them on two joints of the clip that coincide, would halve the pooled
///   median silently.
inline std::array<ClipLength, 7> clip_lengths(const LandmarkClip& clip) {
  check_clip(clip);
  const auto out = detail::measured_lengths(clip);
  for (const ClipLength& l : out)
    if (!(l.length > detail::min_clip_length))
      throw MotionError(clip.source + ": the " + std::string(l.between) + " distance is " + exact_number(l.length) +
                        " m, 1 mm or less: two landmarks at one point, or the clip read in too small a unit");
  using enum Landmark;
  for (const auto& [a, b] : {std::pair{r_knee, r_ankle},
                             {l_knee, l_ankle},
                             {r_hip, r_knee},
                             {l_hip, l_knee},
                             {r_shoulder, r_elbow},
                             {l_shoulder, l_elbow},
                             {r_elbow, r_wrist},
                             {l_elbow, l_wrist},
                             {r_ankle, r_toe},
                             {l_ankle, l_toe}})
    if (!(detail::median_distance(clip, {{a, b}}) > detail::min_clip_length))
      throw MotionError(clip.source + ": landmarks " + std::string(landmark_names[std::size_t(a)]) + " and " +
                        std::string(landmark_names[std::size_t(b)]) +
                        " stand at one point (1 mm apart or less in most frames): the segment between them "
                        "has no length");
  return out;
}

/// A length of a given body that differs from the clip's own (clip_lengths).
struct LengthMismatch {
  ClipLength clip;  ///< the clip's length (m)
  double body;      ///< the body's (m)
};

/// The seed lengths of `body` that differ from what `clip` measures by more than `tolerance` (relative
/// to the clip's): a clip fitted with a body that is not its own (its angles absorb the difference). A
/// length the clip does not show (1 mm or less: two landmarks on one joint) is not compared.
/// \throws MotionError for a clip check_clip refuses.
inline std::vector<LengthMismatch> length_mismatches(const LandmarkClip& clip, const SeedParameters& body,
                                                     double tolerance = 0.05) {
  check_clip(clip);
  std::vector<LengthMismatch> out;
  for (const ClipLength& l : detail::measured_lengths(clip)) {
    if (!(l.length > detail::min_clip_length)) continue;
    const double b = body.*humandyn::detail::dimension(l.dim).member;
    if (!(std::abs(b - l.length) <= tolerance * l.length)) out.push_back({l, b});
  }
  return out;
}

namespace detail {

// The toe's drop below the ankle (m) on every frame where a foot is planted (its ankle slower than 0.5 m/s
// and its toe than 0.3 m/s, central differences), a frame once for each planted foot.
inline std::vector<double> planted_toe_drops(const LandmarkClip& clip) {
  using enum Landmark;
  std::vector<double> drop;
  const int n = int(clip.frames.size());
  const auto speed = [&](int k, Landmark l) {
    const int a = std::max(k - 1, 0), b = std::min(k + 1, n - 1);
    return b == a ? 0.0
                  : (at(clip.frames[std::size_t(b)], l) - at(clip.frames[std::size_t(a)], l)).norm() /
                        ((b - a) * clip.frame_time);
  };
  for (int k = 0; k < n; ++k)
    for (const auto& [ankle, toe] : {std::pair{r_ankle, r_toe}, {l_ankle, l_toe}})
      if (speed(k, ankle) <= 0.5 && speed(k, toe) <= 0.3)
        drop.push_back(at(clip.frames[std::size_t(k)], ankle).z() - at(clip.frames[std::size_t(k)], toe).z());
  return drop;
}

}  // namespace detail

/// The seed body scaled to a clip: its lengths are clip_lengths's (a1 knee-ankle, a2 hip-knee, d4 half
/// the hip-hip distance, d6 mid-hip-neck, d7 half the shoulder-shoulder distance, a8 shoulder-elbow, a9
/// elbow-wrist). The stature is found from the leg: (a1 + a2) over de Leva's (shank + thigh) fraction of
/// the reference subject's stature; the ankle's height a16 is Drillis and Contini's 0.039 of that stature.
/// The segments are de Leva's person of that stature and `mass`, each stretched along its axis to the
/// clip's length (mass kept, centre of mass and radii of gyration scaled): the masses are de Leva's
/// fractions of `mass` exactly.
/// \throws MotionError for a clip check_clip refuses or a length that comes out zero.
inline ClipBody scale_to_clip(const LandmarkClip& clip, const ScaleOptions& options = {}) {
  using enum Landmark;
  const auto lengths = clip_lengths(clip);
  const auto length = [&](std::initializer_list<std::pair<Landmark, Landmark>> pairs) {
    return detail::median_distance(clip, pairs);
  };
  const auto from_mid_hip = [&](Landmark l) { return detail::median_from_mid_hip(clip, l); };
  const auto measured = [&](Dim d) {
    return std::find_if(lengths.begin(), lengths.end(), [&](const ClipLength& l) { return l.dim == d; })->length;
  };
  const double a1 = measured(Dim::a1), a2 = measured(Dim::a2), d4 = measured(Dim::d4), d6 = measured(Dim::d6),
               d7 = measured(Dim::d7), a8 = measured(Dim::a8), a9 = measured(Dim::a9);
  if (!(options.mass > 0) || !std::isfinite(options.mass))
    throw MotionError(clip.source + ": body mass " + exact_number(options.mass) + " kg must be positive");

  using namespace anthropometry;
  const Reference ref = options.sex == Sex::Male ? reference_male : reference_female;
  const double leg_fraction =
      (row("shank", "KJC-AJC", options.sex).length + row("thigh", "HJC-KJC", options.sex).length) / ref.height;
  ClipBody body;
  body.stature = (a1 + a2) / leg_fraction;
  SeedParameters p = de_leva_parameters(body.stature, options.mass, options.sex);
  const SeedParameters person = p;
  p.name = clip.source + " (scaled to the clip, " + exact_number(options.mass) + " kg)";
  p.a1 = a1, p.a2 = a2, p.d4 = d4, p.d6 = d6, p.d7 = d7, p.a8 = a8, p.a9 = a9;
  p.shank = humandyn::detail::rescale(person.shank, a1 / person.a1);
  p.thigh = humandyn::detail::rescale(person.thigh, a2 / person.a2);
  p.pelvis = humandyn::detail::rescale(person.pelvis, d6 / person.d6);
  p.upper_body = humandyn::detail::rescale(person.upper_body, d6 / person.d6);
  p.upper_arm = humandyn::detail::rescale(person.upper_arm, a8 / person.a8);
  p.forearm = humandyn::detail::rescale(person.forearm, a9 / person.a9);
  p.base_pose = standing_base_pose(p);
  body.parameters = p;
  body.foot_length = length({{r_ankle, r_toe}, {l_ankle, l_toe}});
  // the foot flat: the toe's drop on the frames of a planted foot; without ten, the toe on the sole (a16
  // below the ankle)
  std::vector<double> drop = detail::planted_toe_drops(clip);
  body.planted_frames = int(drop.size());
  body.toe_drop = drop.size() >= 10 ? detail::median(std::move(drop)) : p.a16;
  if (!(body.foot_length > std::abs(body.toe_drop)))
    throw MotionError(clip.source + ": the ankle-toe distance " + exact_number(body.foot_length) +
                      " m is not longer than the toe's drop below the ankle " + exact_number(body.toe_drop) + " m");
  body.head_length = length({{neck, head}});
  const double lb = from_mid_hip(lower_back);
  body.lower_back_length = lb >= options.min_lower_back ? lb : 0.0;
  return body;
}

/// The segments whose directions the fit matches, each from one landmark to another (the clip's pelvis
/// point is taken as the mid-hip point). `head` is reported and not fitted (the model has no neck);
/// `pelvis_up` is fitted when the clip's lower back stands clear of the mid-hip point.
enum class FitSegment : int {
  pelvis,
  pelvis_up,
  r_thigh,
  r_shank,
  r_foot,
  l_thigh,
  l_shank,
  l_foot,
  trunk,
  shoulders,
  r_upper_arm,
  r_forearm,
  l_upper_arm,
  l_forearm,
  head,
  count
};
inline constexpr int num_fit_segments = int(FitSegment::count);

struct FitSegmentSpec {
  const char* name;
  Landmark from, to;
};
inline constexpr std::array<FitSegmentSpec, num_fit_segments> fit_segments{{
    {"pelvis", Landmark::r_hip, Landmark::l_hip},  // the hip line, right to left
    {"pelvis_up", Landmark::pelvis, Landmark::lower_back},
    {"r_thigh", Landmark::r_hip, Landmark::r_knee},
    {"r_shank", Landmark::r_knee, Landmark::r_ankle},
    {"r_foot", Landmark::r_ankle, Landmark::r_toe},
    {"l_thigh", Landmark::l_hip, Landmark::l_knee},
    {"l_shank", Landmark::l_knee, Landmark::l_ankle},
    {"l_foot", Landmark::l_ankle, Landmark::l_toe},
    {"trunk", Landmark::pelvis, Landmark::neck},
    {"shoulders", Landmark::r_shoulder, Landmark::l_shoulder},  // the shoulder line, right to left
    {"r_upper_arm", Landmark::r_shoulder, Landmark::r_elbow},
    {"r_forearm", Landmark::r_elbow, Landmark::r_wrist},
    {"l_upper_arm", Landmark::l_shoulder, Landmark::l_elbow},
    {"l_forearm", Landmark::l_elbow, Landmark::l_wrist},
    {"head", Landmark::neck, Landmark::head},
}};

using FloatingModel = FloatingHumanModel<double>;
using JointAngles = FloatingModel::JointVector;

/// One frame's fit: the floating form's pose and how far each segment's direction misses the clip's.
struct FrameFit {
  Pose<double> base;                    ///< the pelvis frame in the world (floating base)
  JointAngles q = JointAngles::Zero();  ///< joint angles of the floating form (rad)
  std::array<double, num_fit_segments>
      residual{};      ///< angle between model and clip direction (degrees); 0 for a segment of zero length
                       ///< (in the model, or within 1 mm in the clip's frame: not fitted there)
  int iterations = 0;  ///< Levenberg–Marquardt iterations taken
  /// The first landmark of the frame that is not finite or lies beyond max_landmark_coordinate (a dropped
  /// or glitched marker), or -1. Such a frame is not fitted: the result is the `start` given (its base
  /// pose, q and residuals held), with iterations 0 and this set.
  int unusable_landmark = -1;
};

/// A whole clip's fit, frame by frame.
struct ClipFit {
  double frame_time = 0;
  std::vector<FrameFit> frames;
};

/// The fit's stopping rule: a step below `step_tolerance` (rad), a step that could lower the cost by no
/// more than rounding, or `max_iterations`.
struct FitOptions {
  int max_iterations = 100;
  double step_tolerance = 1e-10;
};

/// Fits frames of a clip with the floating form of a ClipBody. Built once (allocates); fitting a frame
/// allocates nothing.
class Fitter {
 public:
  explicit Fitter(const ClipBody& body, FitOptions options = {})
      : options_(options), model_(floating_model(body.parameters)), data_(model_) {
    const auto& d = model_.description();
    const auto link = [&](const char* name) {
      for (int i = 0; i < FloatingModel::nj; ++i)
        if (d.joints[std::size_t(i)].link_name == name) return i;
      throw ModelError(std::string("fit: the floating form has no link '") + name + "'");
    };
    forward_kinematics(model_, data_, JointAngles::Zero());
    const Pose<double>& X0 = model_.base_pose();
    const auto frame = [&](int l) -> const Pose<double>& { return l < 0 ? X0 : data_.oMi[std::size_t(l)]; };
    // each landmark: a link (-1: the base) and a point on it; at home, the point stands at the link's
    // origin plus a world offset
    const auto place = [&](Landmark lm, int l, const Eigen::Vector3d& offset = Eigen::Vector3d::Zero()) {
      link_[std::size_t(lm)] = l;
      point_[std::size_t(lm)] = frame(l).inverse() * (frame(l).p + offset);
    };
    using enum Landmark;
    const SeedParameters& p = body.parameters;
    const double toe_ahead = std::sqrt(body.foot_length * body.foot_length - body.toe_drop * body.toe_drop);
    const int r_foot = link("r_foot"), l_foot = link("l_foot"), upper = link("upper_body");
    place(pelvis, -1);
    place(r_hip, link("r_hip_link"));
    place(r_knee, link("r_thigh"));
    place(r_ankle, link("r_shank"));
    // the foot frame sits on the sole, a16 under the ankle; the toe is toe_drop under the ankle
    place(r_toe, r_foot, Eigen::Vector3d(toe_ahead, 0, p.a16 - body.toe_drop));
    place(l_hip, link("l_hip_link"));
    place(l_knee, link("l_thigh"));
    place(l_ankle, link("l_shank"));
    place(l_toe, l_foot, Eigen::Vector3d(toe_ahead, 0, p.a16 - body.toe_drop));
    place(lower_back, -1, Eigen::Vector3d(0, 0, body.lower_back_length));
    place(neck, upper);
    place(head, upper, Eigen::Vector3d(0, 0, body.head_length));
    place(r_shoulder, link("r_shoulder_link"));
    place(r_elbow, link("r_upper_arm"));
    place(r_wrist, link("r_forearm"));
    place(l_shoulder, link("l_shoulder_link"));
    place(l_elbow, link("l_upper_arm"));
    place(l_wrist, link("l_forearm"));
    // which joints move which link: joint j moves link l when j is l or one of its ancestors
    for (int l = 0; l < FloatingModel::nj; ++l)
      for (int k = l; k >= 0; k = d.joints[std::size_t(k)].parent) moved_by_[std::size_t(l)] |= 1u << k;
    // the pelvis and the trunk weigh more than a limb segment, so that what a limb cannot do stays in
    // that limb's residuals instead of turning the pelvis
    weight_.fill(1.0);
    for (FitSegment s : {FitSegment::pelvis, FitSegment::pelvis_up, FitSegment::trunk, FitSegment::shoulders})
      weight_[std::size_t(s)] = trunk_weight;
    weight_[std::size_t(FitSegment::head)] = 0.0;
    if (body.lower_back_length == 0) {
      // without a pelvis-up direction the pelvis's tilt and the waist pitch are one motion (the hip and
      // waist pitch axes are one line): the waist pitch stays at zero, the tilt goes to the pelvis
      weight_[std::size_t(FitSegment::pelvis_up)] = 0.0;
      free_[std::size_t(3 + waist_pitch_index())] = false;
    }
  }

  const FloatingModel& model() const noexcept { return model_; }

  /// The model's landmarks (world, m) for the floating state (X, q): where the fit puts the clip's.
  LandmarkFrame landmarks(const Pose<double>& X, const JointAngles& q) const noexcept {
    LandmarkFrame out;
    const Pose<double> T = X * model_.base_pose().inverse();
    forward_kinematics(model_, data_, q);
    for (int m = 0; m < num_landmarks; ++m) out[std::size_t(m)] = T * world_point(m);
    return out;
  }

  /// A first guess for a frame with no previous one: the pelvis turned as the clip's (hip line, trunk),
  /// every joint at zero. For a frame fit() would not fit (first_unusable_landmark), no pose: base NaN,
  /// unusable_landmark set; fit() given it as its start begins the next frame it fits from that frame's own guess.
  FrameFit initial_guess(const LandmarkFrame& f) const noexcept {
    using enum Landmark;
    FrameFit g;
    if (const int l = first_unusable_landmark(f); l >= 0) {
      g.base.R.setConstant(std::numeric_limits<double>::quiet_NaN());
      g.base.p.setConstant(std::numeric_limits<double>::quiet_NaN());
      g.unusable_landmark = l;
      return g;
    }
    const Eigen::Vector3d y = (detail::at(f, l_hip) - detail::at(f, r_hip)).normalized();
    Eigen::Vector3d z = detail::at(f, neck) - detail::mid_hip(f);
    z = (z - z.dot(y) * y).normalized();
    Eigen::Matrix3d A;  // pelvis axes in the world: x forward, y left, z up
    A << y.cross(z), y, z;
    g.base.R = A * model_.base_pose().R;  // the base frame's home rotation, turned with the pelvis
    g.base.p = detail::mid_hip(f);
    return g;
  }

  /// Fits one frame, starting from `start` (the previous frame's fit): Levenberg–Marquardt on the
  /// direction residuals over the base's rotation and the joint angles; the base's position is the
  /// frame's mid-hip point. Deterministic; no allocation. A frame with a landmark check_clip would
  /// refuse is not fitted: `start` comes back, held, with FrameFit::unusable_landmark naming it.
  FrameFit fit(const LandmarkFrame& f, const FrameFit& start) const noexcept {
    constexpr int n = 3 + FloatingModel::nj;
    using Vec = Eigen::Matrix<double, n, 1>;
    using Mat = Eigen::Matrix<double, n, n>;
    FrameFit x = start;
    x.unusable_landmark = first_unusable_landmark(f);
    if (x.unusable_landmark >= 0) {
      x.iterations = 0;
      return x;
    }
    // a start that is no pose (the initial guess of an unusable frame) is replaced by this frame's guess
    if (!(x.base.R.allFinite() && x.q.allFinite())) x = initial_guess(f);
    x.base.p = detail::mid_hip(f);
    std::array<Eigen::Vector3d, num_fit_segments> target;
    for (int s = 0; s < num_fit_segments; ++s) target[std::size_t(s)] = clip_direction(f, s);

    Mat JtJ;
    Vec Jtr;
    double cost = linearise(x, target, JtJ, Jtr);
    double lambda = 1e-6;
    int it = 0;
    for (; it < options_.max_iterations; ++it) {
      Mat A = JtJ;
      for (int i = 0; i < n; ++i) A(i, i) += lambda * (1.0 + JtJ(i, i));
      const Vec step = A.ldlt().solve(-Jtr);
      if (-step.dot(Jtr) <= 1e-15 * cost) break;  // no decrease left above rounding
      FrameFit trial = x;
      trial.base.R =
          Eigen::AngleAxisd(step.head<3>().norm(), step.head<3>().normalized()).toRotationMatrix() * x.base.R;
      if (step.head<3>().norm() == 0) trial.base.R = x.base.R;
      trial.q += step.tail<FloatingModel::nj>();
      Mat JtJ2;
      Vec Jtr2;
      const double cost2 = linearise(trial, target, JtJ2, Jtr2);
      if (cost2 <= cost) {
        x = trial, cost = cost2, JtJ = JtJ2, Jtr = Jtr2;
        lambda = std::max(lambda / 10, 1e-12);
        if (step.norm() < options_.step_tolerance) break;
      } else {
        lambda *= 10;
        if (lambda > 1e8) break;
      }
    }
    x.iterations = it;
    residuals(x, target, x.residual);
    return x;
  }

  /// Fits every frame of a clip, each warm-started from the one before (the first from initial_guess).
  /// \throws MotionError for a clip check_clip refuses.
  ClipFit fit(const LandmarkClip& clip) const {
    check_clip(clip);
    ClipFit out;
    out.frame_time = clip.frame_time;
    out.frames.reserve(clip.frames.size());
    FrameFit prev = initial_guess(clip.frames.front());
    for (const auto& f : clip.frames) {
      prev = fit(f, prev);
      out.frames.push_back(prev);
    }
    return out;
  }

  /// Whether the waist pitch is fitted (false: held at zero, the clip has no usable lower back).
  bool waist_pitch_fitted() const noexcept { return free_[std::size_t(3 + waist_pitch_index())]; }

 private:
  static constexpr double trunk_weight = 100.0;
  static constexpr int waist_pitch_index() { return seed_body.index("waist_pitch"); }

  // the world position of landmark m after forward_kinematics with the model's own base pose
  Eigen::Vector3d world_point(int m) const noexcept {
    const int l = link_[std::size_t(m)];
    return (l < 0 ? model_.base_pose() : data_.oMi[std::size_t(l)]) * point_[std::size_t(m)];
  }

  static Eigen::Vector3d clip_direction(const LandmarkFrame& f, int s) noexcept {
    const auto& spec = fit_segments[std::size_t(s)];
    const auto point = [&](Landmark l) { return l == Landmark::pelvis ? detail::mid_hip(f) : detail::at(f, l); };
    const Eigen::Vector3d v = point(spec.to) - point(spec.from);
    return v.norm() > detail::min_clip_length ? v.normalized() : Eigen::Vector3d::Zero();
  }

  // the model's segment directions at x, and optionally their Jacobians (3 x (3 + nj) each): columns
  // for a small rotation of the base (world axes, about the base origin) and for each joint
  template <class F>
  void directions(const FrameFit& x, F&& each) const noexcept {
    constexpr int nj = FloatingModel::nj;
    const Pose<double> T = x.base * model_.base_pose().inverse();
    forward_kinematics(model_, data_, x.q);
    // every joint's axis and a point on it, in the world
    const auto& d = model_.description();
    std::array<Eigen::Vector3d, nj> z, o;
    for (int j = 0; j < nj; ++j) {
      const int parent = d.joints[std::size_t(j)].parent;
      const Pose<double>& P = parent < 0 ? model_.base_pose() : data_.oMi[std::size_t(parent)];
      z[std::size_t(j)] = T.R * P.R.col(2);
      o[std::size_t(j)] = T * P.p;
    }
    Eigen::Matrix<double, 3, 3 + nj> J;
    for (int s = 0; s < num_fit_segments; ++s) {
      const auto& spec = fit_segments[std::size_t(s)];
      const int a = int(spec.from), b = int(spec.to);
      const Eigen::Vector3d pa = T * world_point(a), pb = T * world_point(b);
      const Eigen::Vector3d v = pb - pa;
      const double len = v.norm();
      J.setZero();
      if (len == 0) {  // a segment the model does not show (no lower back): no direction, no residual
        each(s, Eigen::Vector3d::Zero().eval(), J);
        continue;
      }
      const Eigen::Vector3d u = v / len;
      J.leftCols<3>() << 0, v.z(), -v.y(), -v.z(), 0, v.x(), v.y(), -v.x(), 0;  // d v / d(base rotation) = -[v]x
      const int la = link_[std::size_t(a)], lb = link_[std::size_t(b)];
      const unsigned ma = la >= 0 ? moved_by_[std::size_t(la)] : 0u, mb = lb >= 0 ? moved_by_[std::size_t(lb)] : 0u;
      for (int j = 0; j < nj; ++j) {
        const auto k = std::size_t(j);
        if (mb >> j & 1u) J.col(3 + j) += z[k].cross(pb - o[k]);
        if (ma >> j & 1u) J.col(3 + j) -= z[k].cross(pa - o[k]);
      }
      J = ((Eigen::Matrix3d::Identity() - u * u.transpose()) / len * J).eval();
      for (int c = 0; c < 3 + nj; ++c)
        if (!free_[std::size_t(c)]) J.col(c).setZero();
      each(s, u, J);
    }
  }

  template <class Mat, class Vec>
  double linearise(const FrameFit& x, const std::array<Eigen::Vector3d, num_fit_segments>& target, Mat& JtJ,
                   Vec& Jtr) const noexcept {
    JtJ.setZero();
    Jtr.setZero();
    double cost = 0;
    directions(x, [&](int s, const Eigen::Vector3d& u, const auto& J) {
      // (a segment the clip's frame does not show, its ends within 1 mm: no direction to match, no
      // residual; matched to nothing, the joints it hangs on would drift)
      const double w = weight_[std::size_t(s)];
      if (w == 0 || target[std::size_t(s)].isZero(0)) return;
      const Eigen::Vector3d r = u - target[std::size_t(s)];
      cost += w * r.squaredNorm();
      JtJ.noalias() += w * J.transpose() * J;
      Jtr.noalias() += w * J.transpose() * r;
    });
    return cost;
  }

  void residuals(const FrameFit& x, const std::array<Eigen::Vector3d, num_fit_segments>& target,
                 std::array<double, num_fit_segments>& out) const noexcept {
    constexpr double deg = 57.29577951308232;
    directions(x, [&](int s, const Eigen::Vector3d& u, const auto&) {
      const Eigen::Vector3d& t = target[std::size_t(s)];
      out[std::size_t(s)] = deg * std::atan2(u.cross(t).norm(), u.dot(t));
    });
  }

  FitOptions options_;
  FloatingModel model_;
  mutable Data<FloatingModel> data_;  // forward kinematics' workspace (a Fitter serves one thread)
  std::array<int, num_landmarks> link_{};
  std::array<Eigen::Vector3d, num_landmarks> point_{};
  std::array<unsigned, FloatingModel::nj> moved_by_{};
  std::array<double, num_fit_segments> weight_{};
  std::array<bool, 3 + FloatingModel::nj> free_ = [] {
    std::array<bool, 3 + FloatingModel::nj> a{};
    a.fill(true);
    return a;
  }();
};

}  // namespace humandyn::motion
