// The URDF importer and exporter (library humandyn::urdf, compiled; needs urdfdom).
//
//   import_urdf_file(path, options)   a URDF tree as DH chains: a ModelDescription<double> plus where
//                                     every URDF link sits on the model's links
//   read_joint_map(path)              which URDF joints become model joints; the others are locked
//   to_urdf(description)              any model (the built-in human included) as a URDF document
//   try_human_model(description)      the same model with the seed's compile-time shape, when it has it
//
// The importer splits the URDF tree into serial chains at its branch points and places standard DH
// frames on each chain; fixed transforms (mounts) appear only where a chain starts off its parent
// link's z axis. Any link can be the base: the joints on the path to it are reversed, keeping their
// URDF names and the sign of their angles. docs/urdf.md describes the conventions.
//
// This header exposes only humandyn types: no XML or urdfdom header is included.
#pragma once

#include "humandyn/detail/component_abi.hpp"
#include "humandyn/model.hpp"

#include <Eigen/Core>

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

// (files that include this header link humandyn::urdf built for the same Eigen alignment: component_abi.hpp)
HUMANDYN_COMPONENT_ABI_CHECK(urdf)

namespace humandyn::urdf {

// A URDF document or a joint map the importer cannot use. The message names the file, the line and
// the element (link or joint) at fault.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One line of a joint map: a URDF joint that becomes a model joint, or one locked at an angle.
struct JointMapEntry {
  std::string urdf_joint;  // the joint's name in the URDF
  std::string model_name;  // its name in the model (defaults to urdf_joint)
  bool locked = false;     // locked: merged into a rigid body at `value`
  double value = 0;        // locked angle (rad), or displacement (m) of a locked prismatic joint
  int line = 0;            // where the entry stands in its file, for messages
};

// Which URDF joints become model joints. Listed active joints become model joints (at a branch point,
// chains follow the order of this list); every joint not listed as active is locked, at its listed
// value or at 0.
struct JointMap {
  std::string source = "joint map";  // file name, for messages
  std::vector<JointMapEntry> entries;
};

// Parses the joint map format (docs/urdf.md gives its grammar): one joint per line, `#` starts a comment,
//   urdf_joint [model_name]        a model joint
//   urdf_joint = value             a locked joint (radians; metres for a prismatic joint); the blanks
//                                  around `=` are optional
// Throws Error naming source, line and column for any malformed line, and for a model name that
// name_fault refuses.
JointMap parse_joint_map(const std::string& text, const std::string& source = "joint map");
// parse_joint_map on the file at `path` (named as messages show it: invisible characters made visible); Error
// "PATH: cannot open: <reason>" (or "is a folder, not a file") if it cannot be read.
JointMap read_joint_map(const std::string& path);

// Why `name` cannot be a model joint's name, or "" when it can. Joint names head CSV columns
// (q_<name>, tau_<name>, ...), so a name must be non-empty UTF-8 without a comma, a double quote, a
// control character (U+0000-U+001F, U+007F-U+009F) or an invisible one (a byte-order mark U+FEFF, a
// zero-width or direction mark U+200B-U+200F, U+202A-U+202E, U+2060-U+2064, a soft hyphen U+00AD,
// line and paragraph separators U+2028, U+2029), and must neither start nor end with a blank (a space
// or U+00A0). The importer applies this one rule to every name that becomes a model joint's.
std::string name_fault(const std::string& name);

// The gravity vector in the base link's frame for an up axis "x", "y", "z", "-x", "-y" or "-z"
// (9.81 m/s^2 against it). Throws std::invalid_argument for anything else.
Eigen::Vector3d gravity_for_up(const std::string& axis, double g = 9.81);

struct ImportOptions {
  std::string root;                          // the base link; empty: the URDF's root link
  std::optional<JointMap> joints;            // none: every revolute and continuous joint is a model joint
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};  // gravity in the base link's frame (URDF says nothing of it)
  // A link whose principal moments violate the triangle inequality (A + B >= C) is an error unless
  // this is set: then, as MuJoCo's `balanceinertia`, all three are replaced by their mean (the link's
  // inertia becomes isotropic about its centre of mass) and Import::warnings records the change.
  bool balance_inertia = false;
};

// Where one URDF link sits in the imported model: its frame in the frame of model link `joint`
// (the DH link frame; -1: the base frame, which is the base link's URDF frame).
struct LinkPlacement {
  std::string link;
  int joint = -1;
  Pose<double> pose;
};

// The imported model and its bookkeeping.
struct Import {
  ModelDescription<double> model;
  std::vector<LinkPlacement> links;      // every URDF link, in document order
  std::vector<std::string> urdf_joints;  // per model joint: its URDF joint name
  std::vector<bool> reversed;            // per model joint: reversed by re-rooting (its URDF parent moves)
  std::vector<std::string> warnings;     // what the importer changed, one line each ("file:line: link ...")
};

// Imports a URDF document (`source` names it in messages). The model's world is the base link's frame
// turned so that gravity points down its z axis (base_pose), with gravity (0, 0, -|g|).
Import import_urdf(const std::string& xml, const ImportOptions& options = {}, const std::string& source = "<urdf>");
// import_urdf on the file at `path` (named as messages show it); Error "PATH: cannot open: <reason>" (or "is a
// folder, not a file") if it cannot be read.
Import import_urdf_file(const std::string& path, const ImportOptions& options = {});

// The model as a URDF document: one continuous joint per model joint (URDF name = model name), each
// link's frame on its joint axis, inertias about the centres of mass, a fixed "<link>_tip" frame at the
// DH frame of each chain's last link (its joint "<joint>_tip", unique among the joints). Importing it at
// its base link gives back the same DH table. ModelError if the description is invalid; Error if a name
// holds a control character that XML cannot carry (a tab, line feed or carriage return is written as a
// character reference and read back).
std::string to_urdf(const ModelDescription<double>& description);

// The model with the seed's compile-time shape (16 joints, the seed's parents, twist classes and
// massless links, no mounts), or nothing; `why` receives the reason it does not fit.
std::optional<HumanModel<double>> try_human_model(const ModelDescription<double>& description,
                                                  std::string* why = nullptr);

}  // namespace humandyn::urdf
