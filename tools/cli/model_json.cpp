#include "cli/model_json.hpp"

namespace humandyn::cli {

namespace {

constexpr const char* format_name = "humandyn-model";
constexpr int format_version = 1;

// ---- writing ---------------------------------------------------------------------------------------

json::Value vec(const Vec3<double>& v) { return json::Array{v.x(), v.y(), v.z()}; }

json::Value mat(const Mat3<double>& m) {
  json::Array rows;
  for (int r = 0; r < 3; ++r) rows.push_back(json::Array{m(r, 0), m(r, 1), m(r, 2)});
  return rows;
}

json::Value pose(const Pose<double>& X) {
  json::Value out;
  out.set("R", mat(X.R));
  out.set("p", vec(X.p));
  return out;
}

json::Value link(const std::string& name, const RigidBodyInertia<double>& body) {
  json::Value out;
  out.set("name", name);
  out.set("mass", body.mass);
  out.set("com", vec(body.com));
  out.set("inertia", mat(body.inertia));
  return out;
}

json::Value conventions() {
  json::Value c;
  c.set("units", "SI: lengths m, angles rad, masses kg, inertias kg m^2, gravity m/s^2; joint torques N m");
  c.set("world", "z up, x forward, y left; gravity is given in the world frame");
  c.set("tree",
        "joints are listed parents first; 'parent' is the index (from 0) of the parent joint in this list, -1 for the "
        "base; joint i moves link i");
  c.set("dh",
        "standard Denavit-Hartenberg: frame of link i = frame of the parent link * mount * Rz(theta + q_i) * Tz(d) * "
        "Tx(a) * Rx(alpha); joint i turns about the z axis of its parent's (mounted) frame, positive "
        "counter-clockwise; q = 0 is the home pose");
  c.set("pose", "R (3x3, listed by rows) and p (m) map child-frame coordinates into the parent frame: x_parent = R x_child + p");
  c.set("mount", "optional fixed pose of the joint's DH base frame in the parent link's frame; identity when absent");
  c.set("link", "mass, centre of mass 'com' and inertia tensor about the centre of mass, both in the link's own frame");
  c.set("base", "the base link (the stance foot) is fixed in the world at 'pose'; its mass counts for the centre of mass only");
  return c;
}

// ---- reading ---------------------------------------------------------------------------------------

Vec3<double> read_vec(const json::Value& v, const std::string& what) {
  const auto& a = v.as_array(what);
  if (a.size() != 3) v.fail(what + " must hold 3 numbers, not " + std::to_string(a.size()));
  return Vec3<double>(a[0].as_number(what + "[0]"), a[1].as_number(what + "[1]"), a[2].as_number(what + "[2]"));
}

Mat3<double> read_mat(const json::Value& v, const std::string& what) {
  const auto& rows = v.as_array(what);
  if (rows.size() != 3) v.fail(what + " must be a 3x3 matrix: 3 rows of 3 numbers, not " + std::to_string(rows.size()) + " rows");
  Mat3<double> m;
  for (int r = 0; r < 3; ++r) m.row(r) = read_vec(rows[std::size_t(r)], what + " row " + std::to_string(r)).transpose();
  return m;
}

// {"R": 3x3, "p": [3]} (either may be left out) or a 4x4 homogeneous matrix.
Pose<double> read_pose(const json::Value& v, const std::string& what) {
  Pose<double> X;
  if (v.is_array()) {
    const auto& rows = v.as_array();
    if (rows.size() != 4) v.fail(what + " as a matrix must be 4x4, not " + std::to_string(rows.size()) + " rows");
    for (int r = 0; r < 4; ++r) {
      const auto& row = rows[std::size_t(r)];
      const auto& cells = row.as_array(what + " row " + std::to_string(r));
      if (cells.size() != 4) row.fail(what + " row " + std::to_string(r) + " must hold 4 numbers");
      for (int c = 0; c < 4; ++c) {
        const double x = cells[std::size_t(c)].as_number(what);
        if (r < 3 && c < 3) X.R(r, c) = x;
        else if (r < 3) X.p(r) = x;
        else if (x != (c == 3 ? 1.0 : 0.0)) row.fail(what + ": the last row of a homogeneous matrix must be [0, 0, 0, 1]");
      }
    }
    return X;
  }
  v.as_object(what);
  v.reject_unknown_keys({"R", "p"});
  if (const auto* R = v.find("R")) X.R = read_mat(*R, what + " R");
  if (const auto* p = v.find("p")) X.p = read_vec(*p, what + " p");
  return X;
}

// {"name", "mass", "com", "inertia"}: mass, com and inertia default to zero.
void read_link(const json::Value& v, const std::string& what, std::string& name, RigidBodyInertia<double>& body) {
  v.as_object(what);
  v.reject_unknown_keys({"name", "mass", "com", "inertia"});
  name = v.at("name").as_string(what + " 'name'");
  if (name.empty()) v.at("name").fail(what + " 'name' is empty");
  body = {};
  if (const auto* m = v.find("mass")) body.mass = m->as_number(what + " 'mass'");
  if (const auto* c = v.find("com")) body.com = read_vec(*c, what + " 'com'");
  if (const auto* I = v.find("inertia")) body.inertia = read_mat(*I, what + " 'inertia'");
}

}  // namespace

json::Value model_to_json(const ModelDescription<double>& model) {
  json::Value doc;
  doc.set("format", format_name);
  doc.set("version", format_version);
  doc.set("name", model.name);
  doc.set("conventions", conventions());
  doc.set("gravity", vec(model.gravity));
  json::Value base;
  base.set("pose", pose(model.base_pose));
  base.set("link", link(model.base_link_name, model.base_body));
  doc.set("base", std::move(base));
  json::Array joints;
  for (std::size_t i = 0; i < model.joints.size(); ++i) {
    const auto& jd = model.joints[i];
    json::Value j;
    j.set("index", int(i));
    j.set("name", jd.name);
    j.set("parent", jd.parent);
    if (jd.mounted) j.set("mount", pose(jd.mount));
    json::Value dh;
    dh.set("a", jd.dh.a);
    dh.set("alpha", jd.dh.alpha);
    dh.set("d", jd.dh.d);
    dh.set("theta", jd.dh.theta);
    j.set("dh", std::move(dh));
    j.set("link", link(jd.link_name, jd.body));
    joints.push_back(std::move(j));
  }
  doc.set("joints", std::move(joints));
  return doc;
}

ModelDescription<double> model_from_json(const json::Value& doc) {
  doc.as_object("a model file");
  doc.reject_unknown_keys({"format", "version", "name", "conventions", "gravity", "base", "joints"});

  // what the file says it is
  const auto& format = doc.at("format");
  if (format.as_string("'format'") != format_name)
    format.fail("'format' is '" + format.as_string() + "', expected '" + format_name + "'");
  const auto& version = doc.at("version");
  if (version.as_int("'version'") != format_version)
    version.fail("'version' " + std::to_string(version.as_int()) + " is not supported (this program reads version " +
                 std::to_string(format_version) + ")");

  ModelDescription<double> model;
  model.name = doc.find("name") ? doc.at("name").as_string("'name'") : std::string("model");
  if (const auto* c = doc.find("conventions")) c->as_object("'conventions'");
  if (const auto* g = doc.find("gravity")) model.gravity = read_vec(*g, "'gravity'");

  // the base: its pose in the world and the body fixed to it
  if (const auto* base = doc.find("base")) {
    base->as_object("'base'");
    base->reject_unknown_keys({"pose", "link"});
    if (const auto* p = base->find("pose")) model.base_pose = read_pose(*p, "base 'pose'");
    if (const auto* l = base->find("link")) read_link(*l, "base 'link'", model.base_link_name, model.base_body);
  }

  // the joints, parents first
  const auto& joints = doc.at("joints").as_array("'joints'");
  if (joints.empty()) doc.at("joints").fail("'joints' is empty: a model needs at least one joint");
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const auto& j = joints[i];
    const std::string who = "joint " + std::to_string(i);
    j.as_object(who);
    j.reject_unknown_keys({"index", "name", "parent", "mount", "dh", "link"});
    if (const auto* index = j.find("index"); index && index->as_int(who + " 'index'") != int(i))
      index->fail(who + " 'index' is " + std::to_string(index->as_int()) + " but the joint stands at position " +
                  std::to_string(i) + " of the list");
    JointDescription<double> jd;
    jd.name = j.at("name").as_string(who + " 'name'");
    if (jd.name.empty()) j.at("name").fail(who + " 'name' is empty");
    const std::string named = who + " '" + jd.name + "'";
    const auto& parent = j.at("parent");
    jd.parent = parent.as_int(named + " 'parent'");
    if (jd.parent < -1 || jd.parent >= int(i))
      parent.fail(named + " 'parent' " + std::to_string(jd.parent) +
                  " must be -1 (the base) or the index of an earlier joint (parents come first)");
    if (const auto* mount = j.find("mount")) {
      jd.mounted = true;
      jd.mount = read_pose(*mount, named + " 'mount'");
    }
    const auto& dh = j.at("dh");
    dh.as_object(named + " 'dh'");
    dh.reject_unknown_keys({"a", "alpha", "d", "theta"});
    jd.dh.a = dh.at("a").as_number(named + " dh 'a'");
    jd.dh.alpha = dh.at("alpha").as_number(named + " dh 'alpha'");
    jd.dh.d = dh.at("d").as_number(named + " dh 'd'");
    jd.dh.theta = dh.at("theta").as_number(named + " dh 'theta'");
    read_link(j.at("link"), named + " 'link'", jd.link_name, jd.body);
    model.joints.push_back(std::move(jd));
  }
  return model;
}

ModelDescription<double> read_model_json(const std::string& path) { return model_from_json(json::read_file(path)); }

}  // namespace humandyn::cli
