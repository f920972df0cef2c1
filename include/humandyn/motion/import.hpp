// The motion pipeline in one call: a clip of landmarks scaled, fitted, filtered, split into contact
// phases and carried to the stance-rooted form frame by frame (docs/motion.md).
//
//   ImportOptions options;
//   options.scale.mass = 70;      // kg
//   options.filter.cutoff = 6;    // Hz
//   const ImportedClip m = import_clip(clip, options);
//   m.motion.frames[k]   // floating form: X, v_b, a_b, q, qd, qdd
//   m.stance[k]          // stance-rooted form: foot, BaseMotion, q, qd, qdd
//   m.phases.phase[k], m.phases.right_share[k], m.fit.frames[k].residual
#pragma once

#include "humandyn/motion/contact.hpp"
#include "humandyn/motion/filter.hpp"
#include "humandyn/motion/fit.hpp"

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace humandyn::motion {

struct ImportOptions {
  ScaleOptions scale;
  FilterOptions filter;
  ContactOptions contact;
  FitOptions fit;
  std::optional<ClipBody> body;  ///< the body to fit the clip with; none: the seed body scaled to the clip (scale)
};

/// Everything the pipeline finds in a clip, frame by frame.
struct ImportedClip {
  ClipBody body;                    ///< the body scaled to the clip (or the one the options give)
  ClipFit fit;                      ///< the unfiltered fit and its residuals
  FloatingTrajectory motion;        ///< filtered floating-form states
  Phases phases;                    ///< contact, phase, stance foot, right share
  std::vector<StanceFrame> stance;  ///< the stance-rooted state on each frame's stance foot
  /// with a given body (ImportOptions::body): its lengths more than 5 % off the clip's own
  /// (length_mismatches), a sign that the clip was fitted with another person's body; else empty
  std::vector<LengthMismatch> mismatched;
  /// whether the fit fitted the waist pitch: false when the clip's lower back stands within
  /// ScaleOptions::min_lower_back of the mid-hip point (median over the frames), whatever the given body's
  /// lower_back_length says, and when that length is 0; the waist pitch is then held at zero (docs/motion.md,
  /// "Without a lower back")
  bool waist_pitch_fitted = true;
};

namespace detail {

// The first quantity of a frame that is not finite (its name), or nullptr.
inline const char* non_finite(const FloatingFrame& f, const StanceFrame& s) noexcept {
  const std::pair<const char*, bool> checks[] = {
      {"base pose", f.base.R.allFinite() && f.base.p.allFinite()},
      {"base velocity", f.v_b.allFinite()},
      {"base acceleration", f.a_b.allFinite()},
      {"q", f.q.allFinite()},
      {"qd", f.qd.allFinite()},
      {"qdd", f.qdd.allFinite()},
      {"stance base motion", s.base.pose.R.allFinite() && s.base.pose.p.allFinite() && s.base.w.allFinite() &&
                                 s.base.wd.allFinite() && s.base.a.allFinite()},
      {"stance q, qd, qdd", s.q.allFinite() && s.qd.allFinite() && s.qdd.allFinite()}};
  for (const auto& [name, ok] : checks)
    if (!ok) return name;
  return nullptr;
}

}  // namespace detail

/// Scales (or takes the given body), fits, filters, finds the contact phases and maps each frame to its stance-rooted
/// form. \throws MotionError naming the clip (and the frame and landmark or quantity) for a clip that cannot be used,
/// among them a clip whose states or frame times come out not finite (coordinates or a frame time at the ends of
/// double's range).
inline ImportedClip import_clip(const LandmarkClip& clip, const ImportOptions& options = {}) {
  ImportedClip out;
  out.body = options.body ? *options.body : scale_to_clip(clip, options.scale);
  ClipBody fitted = out.body;
  if (options.body) {
    out.mismatched = length_mismatches(clip, out.body.parameters);
    out.body.planted_frames = int(detail::planted_toe_drops(clip).size());  // (its toe_drop is the body's)
    // a body's lower back the clip does not show: its direction would be matched to none
    if (!(detail::median_from_mid_hip(clip, Landmark::lower_back) >= options.scale.min_lower_back))
      fitted.lower_back_length = 0;
  }
  const Fitter fitter(fitted, options.fit);
  out.waist_pitch_fitted = fitter.waist_pitch_fitted();
  out.fit = fitter.fit(clip);
  try {
    out.motion = filter_fit(out.fit, options.filter);
  } catch (const MotionError& e) {
    throw MotionError(clip.source + ": " + e.what());
  }
  out.phases = contact_phases(clip, options.contact);
  const StanceForms forms(out.body.parameters);
  out.stance.resize(clip.frames.size());
  for (std::size_t k = 0; k < clip.frames.size(); ++k) {
    if (!std::isfinite(double(k) * clip.frame_time))  // the frame's time, the states' first column
      throw MotionError(clip.source + ": frame " + std::to_string(clip.frame_number(k)) + ": its time, " +
                        std::to_string(k) + " frame times of " + exact_number(clip.frame_time) +
                        " s, is beyond double's range");
    forms.stance_state(out.phases.stance[k], out.motion.frames[k], out.stance[k]);
    if (const char* what = detail::non_finite(out.motion.frames[k], out.stance[k]))
      throw MotionError(clip.source + ": frame " + std::to_string(clip.frame_number(k)) + ": the " + what +
                        " came out not finite (frame time " + exact_number(clip.frame_time) +
                        " s; coordinates or rates beyond double's range?)");
  }
  return out;
}

}  // namespace humandyn::motion
