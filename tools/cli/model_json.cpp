#include "cli/model_json.hpp"

#include "cli/errors.hpp"
#include "text/names.hpp"
#include "text/shown.hpp"

#include <fmt/format.h>

namespace humandyn::cli {

namespace {

using json::Json;
using json::Node;

constexpr const char* format_name = "humandyn-model";
constexpr int format_version = 1;

// ---- writing ---------------------------------------------------------------------------------------

Json vec(const Vec3<double>& v) { return Json::array({v.x(), v.y(), v.z()}); }

Json mat(const Mat3<double>& m) {
  Json rows = Json::array();
  for (int r = 0; r < 3; ++r) rows.push_back(Json::array({m(r, 0), m(r, 1), m(r, 2)}));
  return rows;
}

Json pose(const Pose<double>& X) { return {{"R", mat(X.R)}, {"p", vec(X.p)}}; }

Json link(const std::string& name, const RigidBodyInertia<double>& body) {
  return {{"name", name}, {"mass", body.mass}, {"com", vec(body.com)}, {"inertia", mat(body.inertia)}};
}

Json conventions(bool floating) {
  Json c = {
      {"units", "SI: lengths m, angles rad, masses kg, inertias kg m^2, gravity m/s^2; joint torques N m"},
      {"world", "z up, x forward, y left; gravity is given in the world frame"},
      {"tree",
       "joints are listed parents first; 'parent' is the index (from 0) of the parent joint in this list, -1 for the "
       "base; joint i moves link i"},
      {"dh",
       "standard Denavit-Hartenberg: frame of link i = frame of the parent link * mount * Rz(theta + q_i) * Tz(d) * "
       "Tx(a) * Rx(alpha); joint i turns about the z axis of its parent's (mounted) frame, positive "
       "counter-clockwise; q = 0 is the home pose"},
      {"pose",
       "R (3x3, listed by rows) and p (m) map child-frame coordinates into the parent frame: x_parent = R x_child + p"},
      {"mount", "optional fixed pose of the joint's DH base frame in the parent link's frame; identity when absent"},
      {"link", "mass, centre of mass 'com' and inertia tensor about the centre of mass, both in the link's own frame"},
      {"base",
       "the base link (the stance foot) is fixed in the world at 'pose'; its mass counts for the centre of mass only"},
  };
  if (floating) {
    c["base"] =
        "'joint': 'floating': the base link (the pelvis) is free (6-DOF, a free flyer); 'pose' is its pose in the "
        "world at the home state (all q = 0)";
    c["state"] =
        "the floating state: the base pose X in the world, its velocity v_b = (angular; linear of the base origin) and "
        "its acceleration a_b = d(v_b)/dt, both in base-frame coordinates (Pinocchio's free flyer takes them as "
        "(linear; angular)), and the joints' q, qd, qdd; inverse dynamics gives the joint torques and the base "
        "wrench (moment about the base origin; force, base frame)";
  }
  return c;
}

// ---- reading ---------------------------------------------------------------------------------------

Vec3<double> read_vec(const Node& v) {
  if (v.size() != 3) v.fail(fmt::format("must hold 3 numbers, not {}", v.size()));
  return Vec3<double>(v[0].number(), v[1].number(), v[2].number());
}

Mat3<double> read_mat(const Node& v) {
  if (v.size() != 3) v.fail(fmt::format("must be a 3x3 matrix: 3 rows of 3 numbers, not {} rows", v.size()));
  Mat3<double> m;
  for (std::size_t r = 0; r < 3; ++r) m.row(int(r)) = read_vec(v[r]).transpose();
  return m;
}

// {"R": 3x3, "p": [3]} (either may be left out) or a 4x4 homogeneous matrix.
Pose<double> read_pose(const Node& v) {
  Pose<double> X;
  if (v.value().is_array()) {
    if (v.size() != 4) v.fail(fmt::format("as a matrix must be 4x4, not {} rows", v.size()));
    for (std::size_t r = 0; r < 4; ++r) {
      const Node row = v[r];
      if (row.size() != 4) row.fail("must hold 4 numbers");
      for (std::size_t c = 0; c < 4; ++c) {
        const double x = row[c].number();
        if (r < 3 && c < 3)
          X.R(int(r), int(c)) = x;
        else if (r < 3)
          X.p(int(r)) = x;
        else if (x != (c == 3 ? 1.0 : 0.0))
          row.fail("the last row of a homogeneous matrix must be [0, 0, 0, 1]");
      }
    }
    return X;
  }
  v.reject_unknown_keys({"R", "p"});
  X.R = read_mat(v.at("R"));
  X.p = read_vec(v.at("p"));
  return X;
}

// {"name", "mass", "com", "inertia"}, every one required: no inertial number is taken as zero unsaid (a
// massless link says mass 0, com and inertia zero).
void read_link(const Node& v, std::string& name, RigidBodyInertia<double>& body) {
  v.reject_unknown_keys({"name", "mass", "com", "inertia"});
  const Node name_node = v.at("name");
  name = name_node.string();
  if (const std::string fault = text::label_fault(name); !fault.empty()) name_node.fail(fault);
  body.mass = v.at("mass").number();
  body.com = read_vec(v.at("com"));
  body.inertia = read_mat(v.at("inertia"));
}

// The library's validation of a description read from `source`, its message naming the file and the
// entry at fault as the reader's messages do, /joints/K (the library's message counts joints from 1).
void validate(const ModelDescription<double>& model, const std::string& source) {
  try {
    (void)Model<double, DynamicShape>(model);
  } catch (const ModelError& e) {
    std::string entry;
    if (e.where() == ModelError::Where::Joint) entry = fmt::format(" /joints/{}:", e.joint());
    if (e.where() == ModelError::Where::Base) entry = " /base:";
    if (e.where() == ModelError::Where::Gravity) entry = " /gravity:";
    throw InputError(fmt::format("{}:{} invalid model: {}", source, entry, text::shown(e.what())));
  }
}

}  // namespace

json::Json model_to_json(const ModelDescription<double>& model, bool floating) {
  Json joints = Json::array();
  for (std::size_t i = 0; i < model.joints.size(); ++i) {
    const auto& jd = model.joints[i];
    Json j{{"index", i}, {"name", jd.name}, {"parent", jd.parent}};
    if (jd.mounted) j["mount"] = pose(jd.mount);
    j["dh"] = {{"a", jd.dh.a}, {"alpha", jd.dh.alpha}, {"d", jd.dh.d}, {"theta", jd.dh.theta}};
    j["link"] = link(jd.link_name, jd.body);
    joints.push_back(std::move(j));
  }
  Json base = {{"pose", pose(model.base_pose)}, {"link", link(model.base_link_name, model.base_body)}};
  if (floating) base["joint"] = "floating";
  return {{"format", format_name},
          {"version", format_version},
          {"name", model.name},
          {"conventions", conventions(floating)},
          {"gravity", vec(model.gravity)},
          {"base", std::move(base)},
          {"joints", std::move(joints)}};
}

ModelDescription<double> model_from_json(const json::Json& document, const std::string& source, bool* floating) {
  if (floating) *floating = false;
  const Node doc(document, source);
  doc.reject_unknown_keys({"format", "version", "name", "conventions", "gravity", "base", "joints", "landmarks"});

  // what the file says it is
  const Node format = doc.at("format");
  if (format.string() != format_name) format.fail(fmt::format("'{}' is not '{}'", format.string(), format_name));
  const Node version = doc.at("version");
  if (version.whole() != format_version)
    version.fail(
        fmt::format("version {} is not supported (this program reads version {})", version.whole(), format_version));

  ModelDescription<double> model;
  model.name = "model";
  if (const auto name = doc.find("name")) {
    model.name = name->string();
    // (empty is allowed: a URDF's robot may have no name)
    if (const std::string fault = text::label_fault(model.name); !model.name.empty() && !fault.empty())
      name->fail(fault);
  }
  if (const auto c = doc.find("conventions")) c->expect_object();
  model.gravity = read_vec(doc.at("gravity"));
  if (const auto l = doc.find("landmarks")) {  // for the motion commands: its form only
    l->reject_unknown_keys({landmark_keys.begin(), landmark_keys.end()});
    for (const std::string_view key : landmark_keys) (void)l->at(std::string(key)).number();
  }

  // the base: its pose in the world and the body fixed to it
  const Node base = doc.at("base");
  base.reject_unknown_keys({"joint", "pose", "link"});
  if (const auto joint = base.find("joint")) {
    const std::string kind = joint->string();
    if (kind != "fixed" && kind != "floating") joint->fail("'" + kind + "' is not 'fixed' or 'floating'");
    if (kind == "floating" && !floating) joint->fail("the model has a floating base, which this command does not read");
    if (floating) *floating = kind == "floating";
  }
  model.base_pose = read_pose(base.at("pose"));
  read_link(base.at("link"), model.base_link_name, model.base_body);

  // the joints, parents first
  const Node joints = doc.at("joints");
  if (joints.size() == 0) joints.fail("is empty: a model needs at least one joint");
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const Node j = joints[i];
    j.reject_unknown_keys({"index", "name", "parent", "mount", "dh", "link"});
    if (const auto index = j.find("index"); index && index->whole() != int(i))
      index->fail(fmt::format("is {} but the joint stands at position {} of the list", index->whole(), i));
    JointDescription<double> jd;
    const Node name = j.at("name");
    jd.name = name.string();
    if (const std::string fault = text::name_fault(jd.name); !fault.empty())
      name.fail(fault + ", so no CSV column can name the joint");
    const Node parent = j.at("parent");
    jd.parent = parent.whole();
    if (jd.parent < -1 || jd.parent >= int(i))
      parent.fail(
          fmt::format("{} (joint '{}') must be -1 (the base) or the index of an earlier joint (parents "
                      "come first)",
                      jd.parent, text::shown(jd.name)));
    if (const auto mount = j.find("mount")) {
      jd.mounted = true;
      jd.mount = read_pose(*mount);
    }
    const Node dh = j.at("dh");
    dh.reject_unknown_keys({"a", "alpha", "d", "theta"});
    jd.dh.a = dh.at("a").number();
    jd.dh.alpha = dh.at("alpha").number();
    jd.dh.d = dh.at("d").number();
    jd.dh.theta = dh.at("theta").number();
    read_link(j.at("link"), jd.link_name, jd.body);
    model.joints.push_back(std::move(jd));
  }
  validate(model, source);
  return model;
}

ModelDescription<double> parse_model_json(std::string_view text, const std::string& source, bool* floating) {
  return model_from_json(json::parse(text, source), source, floating);
}

ModelDescription<double> read_model_json(const std::string& path, bool* floating) {
  return model_from_json(json::read_file(path), text::shown(path), floating);
}

std::string write_model_json(const ModelDescription<double>& model, bool floating) {
  return json::write(model_to_json(model, floating));
}

}  // namespace humandyn::cli
