// Motion capture in BVH (Biovision hierarchy) files: library humandyn::bvh, compiled, on Eigen only.
//
//   read_bvh_file(path) / parse_bvh(text)   a BVH file as a BvhClip: the hierarchy and every frame's channel values,
//                                           in the file's own units and axes
//   to_bvh(clip)                            a clip as BVH text that reads back to the same clip, bit for bit
//   joint_positions(clip, frame, world)     forward kinematics: every joint's position in humandyn's world
//   parse_landmark_map / read_landmark_map  which BVH joints are the body's landmarks (built-in: CMU and Mixamo names)
//   to_landmarks(clip, options)             the clip as landmark positions per frame (LandmarkClip, defined in
//                                           humandyn/motion/landmarks.hpp), for fitting
//
// docs/motion.md describes the format as read, the conversion into humandyn's world and the map's grammar.
#pragma once

#include "humandyn/detail/component_abi.hpp"
#include "humandyn/motion/landmarks.hpp"

#include <Eigen/Core>

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

// (files that include this header link humandyn::bvh built for the same Eigen alignment: component_abi.hpp)
HUMANDYN_COMPONENT_ABI_CHECK(bvh)

namespace humandyn::motion {

/// A BVH file, a landmark map or a clip that cannot be used. The message starts with "file:line:column: "
/// (or "file: " when the fault has no place in the text) and says what was expected.
class BvhError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One channel of a BVH joint: a translation (file units) or a rotation (degrees) about a parent-frame axis.
enum class Channel : unsigned char { Xposition, Yposition, Zposition, Xrotation, Yrotation, Zrotation };

/// The channel's name as BVH spells it ("Xposition", ..., "Zrotation").
std::string_view channel_name(Channel c);

/// One joint of the hierarchy, or an End Site (a joint without channels or children that only marks a bone's end).
struct BvhJoint {
  std::string name;                 ///< unique among the joints; "" for an End Site
  int parent = -1;                  ///< index of the parent joint; -1 for a root
  Eigen::Vector3d offset{0, 0, 0};  ///< OFFSET: the joint in its parent's frame at rest (file units)
  std::vector<Channel> channels;    ///< CHANNELS in the order listed; none for an End Site
  bool end_site = false;            ///< an End Site
  int line = 0;                     ///< line of its ROOT / JOINT / End Site keyword (0: built in code)
};

/// A BVH clip as written: the hierarchy (joints in file order, each after its parent) and every frame's channel
/// values, in the file's units (offsets, positions) and degrees (rotations), axes as in the file.
struct BvhClip {
  std::vector<BvhJoint> joints;
  double frame_time = 0;       ///< s between frames (> 0)
  std::vector<double> values;  ///< frame-major: frame f's channels start at f * channel_count()
  std::string source;          ///< file name, for messages

  /// Channels per frame: the sum over the joints.
  int channel_count() const;
  /// Number of frames: values.size() / channel_count().
  int frame_count() const;
  /// Index of a joint by name (End Sites have none), or -1.
  int find(std::string_view name) const;
};

/// Parses BVH text (`source` names it in messages). Accepts LF, CRLF or lone CR line ends, a UTF-8 byte-order mark, any
/// number of ROOTs, channels of any kind in any order on any joint (each at most once), End Sites, and joint names
/// with blanks (the rest of the line); a keyword's values stand on its line. Throws BvhError with line and column
/// for anything else: a missing or misplaced keyword, brace or number, a value that is not a finite number, an
/// unknown or repeated channel, a CHANNELS count that differs from the names listed, a duplicate joint name, a
/// missing `Frames:` or `Frame Time:`, a frame time that is not positive, a motion line with more or fewer values
/// than the hierarchy has channels, fewer or more motion lines than `Frames:` says.
/// \param text   the whole file
/// \param source the file's name, for messages
/// \return the clip, values unconverted
BvhClip parse_bvh(std::string_view text, const std::string& source = "<bvh>");
/// parse_bvh on the file at `path`, its name as messages show it (invisible characters made visible) for
/// `source`. BvhError "PATH: cannot open: <reason>" (or "is a folder, not a file") if it cannot be read.
BvhClip read_bvh_file(const std::string& path);

/// The clip as BVH text: tabs for indentation, LF line ends, every number in the shortest form that reads back to
/// the same double, so parse_bvh(to_bvh(c)) == c (joints, offsets, channels, frame time and values exactly).
/// Writing it to a file all or nothing is the caller's part (the command line's atomic file).
/// \param clip the clip: joints depth first, each after its parent, as parse_bvh gives them
/// \return the whole file's text
/// \throws BvhError if the clip is not one a BVH file can hold (a bad parent index, an empty, repeated or
///         multi-line joint name, an End Site with channels or children, a non-finite number, a non-positive
///         frame time, values not a whole number of frames, no channels)
std::string to_bvh(const BvhClip& clip);

/// The up axis of a BVH file. BVH files are usually Y-up.
enum class UpAxis { y, z };

/// Metres per file unit of the CMU database's files: (1/0.45) x 2.54 cm (the CMU FAQ).
inline constexpr double cmu_metres_per_unit = 0.0254 / 0.45;

/// How file coordinates become humandyn's world (z up, right-handed, metres):
///   Y-up: (x, y, z)_file -> s * (z, x, y)   (file z forward -> world x, file x -> world y (left), file y -> up)
///   Z-up: (x, y, z)_file -> s * (x, y, z)
/// with s = metres_per_unit. Both maps are proper rotations (determinant +1) times s, so handedness is kept.
struct WorldOptions {
  double metres_per_unit = 1.0;  ///< > 0 and finite; cmu_metres_per_unit for CMU's files
  UpAxis up = UpAxis::y;
};

/// The world's coordinates of a point (or offset) given in file units and axes.
Eigen::Vector3d to_world(const Eigen::Vector3d& file_point, const WorldOptions& world);

/// Forward kinematics of the BVH skeleton at one frame. Each joint's frame relative to its parent's is
/// translation (OFFSET + its position channels, a missing axis 0) then rotation R = R_1 R_2 ... R_k, the product of
/// its rotation channels' elementary rotations in the order listed, acting on column vectors (so the last listed
/// acts first). Joint positions: p_j = p_parent + R_parent,global (OFFSET_j + position channels_j).
/// \param clip  the clip
/// \param frame 0 <= frame < clip.frame_count()
/// \param world the unit and up axis
/// \return per joint of clip.joints (End Sites included): its position in the world (m)
/// \throws BvhError if frame is out of range or world's unit is not positive
std::vector<Eigen::Vector3d> joint_positions(const BvhClip& clip, int frame, const WorldOptions& world = {});

/// The same for every frame: [frame][joint], faster than frame by frame.
std::vector<std::vector<Eigen::Vector3d>> all_joint_positions(const BvhClip& clip, const WorldOptions& world = {});

/// The landmark of that name (landmark_names), or none.
std::optional<Landmark> landmark_named(std::string_view name);

/// Which BVH joints give each landmark: the mean of their positions (one joint: its position).
struct LandmarkMap {
  std::array<std::vector<std::string>, int(Landmark::count)> joints;  ///< per landmark, >= 1 BVH joint name
  std::array<int, int(Landmark::count)> lines{};                      ///< where each was set (0: built in)
  std::string source = "built-in landmark map";                       ///< file name, for messages
};

/// The built-in map, for the CMU skeleton and the Mixamo-like naming (Hips, LeftUpLeg, LeftLeg, LeftFoot,
/// LeftToeBase, Spine, Neck, Head, LeftArm, LeftForeArm, LeftHand and the Right... ones):
/// pelvis = mean of LeftUpLeg and RightUpLeg (the hip centres), hips LeftUpLeg, knees LeftLeg, ankles LeftFoot,
/// toes LeftToeBase, lower_back Spine, neck Neck, head Head, shoulders LeftArm, elbows LeftForeArm, wrists
/// LeftHand. A name also matches a joint named "prefix:name" (mixamorig:LeftUpLeg) when exactly one does.
LandmarkMap default_landmark_map();

/// Parses a landmark map over the built-in one: each line `landmark = joint[, joint ...]` replaces that landmark's
/// joints (the landmark is their mean); `#` starts a comment; blanks around names are ignored, a joint name may
/// contain blanks but not `,` or `#`. LF, CRLF or a lone CR, an optional UTF-8 byte-order mark.
/// \throws BvhError naming source, line and column for an unknown landmark, a landmark set twice, a missing `=`,
///         an empty joint name
LandmarkMap parse_landmark_map(std::string_view text, const std::string& source = "landmark map");
/// parse_landmark_map on the file at `path` (named as messages show it); BvhError "PATH: cannot open: <reason>"
/// (or "is a folder, not a file") if it cannot be read.
LandmarkMap read_landmark_map(const std::string& path);
/// The map as a file parse_landmark_map reads back to the same joints (every landmark listed).
std::string to_text(const LandmarkMap& map);

struct LandmarkOptions {
  WorldOptions world;  ///< unit and up axis of the file
  LandmarkMap map = default_landmark_map();
  /// Drop the clip's first frame: true for CMU's files in Hahne's BVH conversion, whose frame 1 is an added
  /// T-pose, not captured motion.
  bool drop_first_frame = false;
};

/// The clip's landmarks per frame, in the world: forward kinematics of every frame, each landmark the mean of its
/// map's joints.
/// \param clip    the clip
/// \param options unit and up axis (the default: metres, Y up), the map, whether the first frame is dropped
/// \return frame_time and source of the clip; frames: the clip's frames (from its second if the first is dropped),
///         each landmark's position in the world (m)
/// \throws BvhError naming the clip, the landmark and where its map entry stands when a joint it names is not in
///         the hierarchy (or is matched by more than one "prefix:name" joint), or when no frame is left
LandmarkClip to_landmarks(const BvhClip& clip, const LandmarkOptions& options = {});

}  // namespace humandyn::motion
