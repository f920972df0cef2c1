// Model validation (model.hpp, builders.hpp): every invalid description is refused when the model is
// built, with a ModelError whose message names the joint or link at fault and says what is wrong.
#include "humandyn/humandyn.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <functional>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>

namespace test_model {

namespace {

using namespace humandyn;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// The message of the ModelError that building a model of shape M from `d` throws ("" if none).
template <class M>
std::string error_of(const ModelDescription<double>& d) {
  try {
    M model(d.template cast<typename M::scalar_type>());
    (void)model;
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

// Expects building to fail, for both shapes and both scalar types, with a message containing every
// one of `parts`.
void expect_refused(const ModelDescription<double>& d, std::initializer_list<std::string> parts,
                    bool static_too = true) {
  const auto check = [&](const std::string& message, const char* which) {
    ASSERT_FALSE(message.empty()) << which << " accepted the description";
    for (const auto& part : parts)
      EXPECT_NE(message.find(part), std::string::npos) << which << ": \"" << message << "\" lacks \"" << part << "\"";
  };
  check(error_of<AnyModel<double>>(d), "AnyModel<double>");
  check(error_of<AnyModel<float>>(d), "AnyModel<float>");
  if (static_too) {
    check(error_of<HumanModel<double>>(d), "HumanModel<double>");
    check(error_of<HumanModel<float>>(d), "HumanModel<float>");
  }
}

class Validation : public ::testing::Test {
 protected:
  ModelDescription<double> good{human_description(default_parameters())};
  // joint 2, the right knee, moves the right thigh
  ModelDescription<double> with_thigh(const std::function<void(RigidBodyInertia<double>&)>& edit) const {
    ModelDescription<double> d = good;
    edit(d.joints[1].body);
    return d;
  }
};

TEST_F(Validation, TheBuiltInModelsAreValid) {
  for (auto make : {default_parameters, female_parameters, paper_parameters}) {
    const auto d = human_description(make());
    EXPECT_EQ(error_of<HumanModel<double>>(d), "");
    EXPECT_EQ(error_of<HumanModel<float>>(d), "");
    EXPECT_EQ(error_of<AnyModel<double>>(d), "");
    EXPECT_EQ(error_of<AnyModel<float>>(d), "");
  }
}

TEST_F(Validation, NegativeMass) {
  expect_refused(with_thigh([](auto& b) { b.mass = -1.5; }),
                 {"joint 2", "r_knee_pitch", "r_thigh", "negative mass", "-1.5"});
}

TEST_F(Validation, NonFiniteMass) {
  expect_refused(with_thigh([](auto& b) { b.mass = kNaN; }), {"r_knee_pitch", "r_thigh", "mass is not finite"});
  expect_refused(with_thigh([](auto& b) { b.mass = kInf; }), {"r_thigh", "mass is not finite"});
}

TEST_F(Validation, NonFiniteCentreOfMassOrInertia) {
  expect_refused(with_thigh([](auto& b) { b.com.y() = kNaN; }), {"r_thigh", "centre of mass is not finite"});
  expect_refused(with_thigh([](auto& b) { b.inertia(2, 2) = kInf; }), {"r_thigh", "inertia is not finite"});
}

TEST_F(Validation, NonFiniteDhEntry) {
  for (int entry = 0; entry < 4; ++entry)
    for (double bad : {kNaN, kInf, -kInf}) {
      ModelDescription<double> d = good;
      auto& dh = d.joints[8].dh;  // joint 9, left elbow
      (entry == 0 ? dh.a : entry == 1 ? dh.alpha : entry == 2 ? dh.d : dh.theta) = bad;
      SCOPED_TRACE("entry " + std::to_string(entry) + " = " + std::to_string(bad));
      expect_refused(d, {"joint 9", "l_elbow_pitch", "l_forearm", "DH parameters are not finite"});
    }
}

// Sizes no body has, each an error naming its link, in both scalar types, rather than a model whose torques
// overflow: lengths beyond 1e7 m, masses beyond 1e9 kg, inertias beyond 1e21 kg m^2, gravity beyond 1e5 m/s^2
// (the values powers of two, the same in float); the largest allowed pass.
TEST_F(Validation, SizesBeyondAnyBody) {
  const double far = std::ldexp(1.0, 70), heavy = std::ldexp(1.0, 80);  // 1.2e21 m, 1.2e24 kg
  expect_refused(with_thigh([&](auto& b) { b.com.x() = far; }),
                 {"r_thigh", "centre of mass " + exact_number(far) + " m from the frame's origin is beyond 1e+07 m"});
  expect_refused(with_thigh([&](auto& b) { b.mass = heavy; }),
                 {"r_thigh", "mass " + exact_number(heavy) + " kg is beyond 1e+09 kg"});
  expect_refused(with_thigh([&](auto& b) { b.inertia *= std::ldexp(1.0, 80); }),
                 {"r_thigh", "inertia coefficient", "kg m^2 is beyond 1e+21 kg m^2"});
  ModelDescription<double> d = good;
  d.joints[8].dh.a = -far;
  expect_refused(d, {"joint 9", "l_forearm", "DH length a = " + exact_number(-far) + " m is beyond 1e+07 m"});
  d = good;
  d.joints[8].dh.d = std::ldexp(1.0, 24);
  expect_refused(d, {"joint 9", "DH length d = 16777216 m is beyond 1e+07 m"});
  d = good;
  d.joints[6].mounted = true;  // (a mount the seed shape does not have: runtime-shaped models only)
  d.joints[6].mount.p.x() = std::ldexp(1.0, 24);
  expect_refused(d, {"joint 7", "mount offset 16777216 m is beyond 1e+07 m"}, false);
  d = good;
  d.base_body.mass = std::ldexp(1.0, 31);
  expect_refused(d, {"base link", "mass 2147483648 kg is beyond 1e+09 kg"});
  d = good;
  d.base_pose.p.z() = std::ldexp(1.0, 24);
  expect_refused(d, {"base pose's position 16777216 m from the world's origin is beyond 1e+07 m"});
  d = good;
  d.gravity.z() = -std::ldexp(1.0, 20);
  expect_refused(d, {"gravity 1048576 m/s^2 is beyond 1e+05 m/s^2"});
  // angles a double no longer adds a joint angle to
  d = good;
  d.joints[4].dh.theta = 1.5e6;
  expect_refused(d, {"joint 5", "DH angle theta = 1500000 rad is beyond 1e+06 rad"});
  d = good;
  d.joints[4].dh.alpha = -4e6;
  expect_refused(d, {"joint 5", "DH angle alpha = -4e+06 rad is beyond 1e+06 rad"});
  // a message names the size given, however large (a norm that overflowed said inf)
  for (const auto& [edit, part] : std::vector<std::pair<std::function<void(ModelDescription<double>&)>, std::string>>{
           {[](auto& m) { m.joints[1].body.com.x() = 1e300; }, "centre of mass 1e+300 m"},
           {[](auto& m) { m.base_pose.p.y() = -1e300; }, "base pose's position 1e+300 m"},
           {[](auto& m) {
              m.joints[6].mounted = true;
              m.joints[6].mount.p.z() = 1e300;
            },
            "mount offset 1e+300 m"}}) {
    d = good;
    edit(d);
    const std::string message = error_of<AnyModel<double>>(d);
    EXPECT_NE(message.find(part), std::string::npos) << message;
  }
  d = good;
  d.joints[4].dh.theta = 1e6;
  d.gravity.z() = -1e5;
  d.joints[8].dh.a = 1e7;
  d.joints[1].body.inertia *= 1e9 / d.joints[1].body.mass;
  d.joints[1].body.mass = 1e9;
  EXPECT_EQ(error_of<HumanModel<double>>(d), "");
  EXPECT_EQ(error_of<AnyModel<float>>(d), "");
  // at the bounds, in float too (1e21 rounds up to a float above it)
  d.joints[1].body.inertia = 1e21 * Eigen::Matrix3d::Identity();
  d.joints[1].body.com.setZero();
  EXPECT_EQ(error_of<HumanModel<double>>(d), "");
  EXPECT_EQ(error_of<HumanModel<float>>(d), "");
  EXPECT_EQ(error_of<AnyModel<float>>(d), "");
}

TEST_F(Validation, InertiaNotSymmetric) {
  expect_refused(with_thigh([](auto& b) { b.inertia(0, 1) += 0.01; }), {"r_thigh", "not symmetric"});
}

TEST_F(Validation, InertiaNotPositiveSemidefinite) {
  expect_refused(with_thigh([](auto& b) { b.inertia = Eigen::Vector3d(0.1, 0.1, -0.01).asDiagonal(); }),
                 {"r_knee_pitch", "r_thigh", "not positive semidefinite"});
  // symmetric, positive diagonal, yet indefinite: a large product of inertia
  expect_refused(with_thigh([](auto& b) {
                   b.inertia = Eigen::Vector3d(0.1, 0.1, 0.15).asDiagonal();
                   b.inertia(0, 1) = b.inertia(1, 0) = 0.2;
                 }),
                 {"r_thigh", "not positive semidefinite"});
}

// A small body's faults, refused in float as in double: a float tolerance absolute below 1 kg m^2 (7.6e-6) had
// taken them for round-off, and a finger of moment -5e-6 kg m^2 gave a negative mass matrix
TEST_F(Validation, ASmallBodysFaultsAreRefusedInFloatToo) {
  const auto small = [&](const Eigen::Matrix3d& I) {
    return with_thigh([&](auto& b) {
      b.mass = 0.01;
      b.inertia = I;
    });
  };
  expect_refused(small(Eigen::Vector3d(1e-6, 1e-6, -5e-6).asDiagonal()), {"r_thigh", "not positive semidefinite"});
  expect_refused(small(Eigen::Vector3d(1e-6, 1e-6, 6e-6).asDiagonal()), {"r_thigh", "triangle inequality"});
  Eigen::Matrix3d skew = 1e-6 * Eigen::Matrix3d::Identity();
  skew(0, 1) = 5e-6;
  expect_refused(small(skew), {"r_thigh", "not symmetric"});
  // while a valid one, rounded to float, passes in both
  const ModelDescription<double> finger = small(Eigen::Vector3d(1.1e-6, 1.3e-6, 2.4e-6).asDiagonal());
  EXPECT_EQ(error_of<AnyModel<double>>(finger), "");
  EXPECT_EQ(error_of<AnyModel<float>>(finger), "");
  EXPECT_EQ(error_of<HumanModel<float>>(finger), "");
}

// A milligram body's faults too: the tolerance is relative to the tensor and to m times a square metre (an
// absolute one of 1 kg m^2's round-off had let a tensor of 1e-15 kg m^2 through whatever its signs, and the
// joint accelerated against its torque with a negative kinetic energy); its valid tensor passes
TEST_F(Validation, AMilligramBodysFaultsAreRefused) {
  const auto tiny = [&](const Eigen::Matrix3d& I, double mass = 1e-6) {
    return with_thigh([&](auto& b) {
      b.mass = mass;
      b.com = Eigen::Vector3d(0, 0, mass > 0 ? 1e-3 : 0);
      b.inertia = I;
    });
  };
  expect_refused(tiny(Eigen::Vector3d(1e-15, 1e-15, -1e-15).asDiagonal()), {"r_thigh", "not positive semidefinite"});
  expect_refused(tiny(Eigen::Vector3d(1e-16, 1e-16, 1e-14).asDiagonal()), {"r_thigh", "triangle inequality"});
  expect_refused(tiny(Eigen::Vector3d(1e-14, 1e-14, 1e-14).asDiagonal(), 0),
                 {"r_thigh", "massless link has rotational inertia"});
  const ModelDescription<double> grain = tiny(Eigen::Vector3d(1.1e-15, 1.3e-15, 2.4e-15).asDiagonal());
  EXPECT_EQ(error_of<AnyModel<double>>(grain), "");
  EXPECT_EQ(error_of<AnyModel<float>>(grain), "");
}

TEST_F(Validation, InertiaViolatingTheTriangleInequality) {
  // principal moments 0.01, 0.01, 0.05: no mass distribution has I3 > I1 + I2
  expect_refused(with_thigh([](auto& b) { b.inertia = Eigen::Vector3d(0.01, 0.01, 0.05).asDiagonal(); }),
                 {"r_thigh", "triangle inequality"});
  // the same, turned away from the link axes
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  expect_refused(
      with_thigh([&](auto& b) { b.inertia = R * Eigen::Vector3d(0.01, 0.05, 0.02).asDiagonal() * R.transpose(); }),
      {"r_thigh", "triangle inequality"});
  // a thin rod (I3 = I1 + I2 with I3 = 0... the equality case) is allowed
  EXPECT_EQ(error_of<AnyModel<double>>(
                with_thigh([](auto& b) { b.inertia = Eigen::Vector3d(0.02, 0.02, 0.0).asDiagonal(); })),
            "");
}

TEST_F(Validation, MasslessLinkWithInertia) {
  // a link the shape may load, given no mass but rotational inertia
  expect_refused(with_thigh([](auto& b) {
                   b.mass = 0;
                   b.com.setZero();
                 }),
                 {"r_thigh", "massless link has rotational inertia"});
  // a link the shape declares massless (joint 3, right hip roll)
  ModelDescription<double> d = good;
  d.joints[2].body.inertia = Eigen::Vector3d(0.01, 0.01, 0.01).asDiagonal();
  expect_refused(d, {"joint 3", "r_hip_roll", "massless link has rotational inertia"});
}

TEST_F(Validation, MassOnALinkTheShapeDeclaresMassless) {
  ModelDescription<double> d = good;
  d.joints[4].body.mass = 1.0;  // joint 5, waist pitch: its link is massless in the seed shape
  d.joints[4].body.inertia = Eigen::Vector3d(0.01, 0.01, 0.01).asDiagonal();
  EXPECT_NE(error_of<HumanModel<double>>(d).find("waist_pitch"), std::string::npos);
  EXPECT_NE(error_of<HumanModel<double>>(d).find("declares this link massless"), std::string::npos);
  EXPECT_EQ(error_of<AnyModel<double>>(d), "") << "a runtime shape may carry mass anywhere";
}

TEST_F(Validation, WrongJointCountForTheStaticShape) {
  ModelDescription<double> d = good;
  d.joints.pop_back();
  const std::string message = error_of<HumanModel<double>>(d);
  EXPECT_NE(message.find("15 joints"), std::string::npos) << message;
  EXPECT_NE(message.find("needs 16"), std::string::npos) << message;
  EXPECT_NE(message.find(d.name), std::string::npos) << message;
  EXPECT_EQ(error_of<AnyModel<double>>(d), "") << "any count suits a runtime shape";
}

// A description without joints moves nothing: refused (the steps' norms over q would have no entry).
TEST_F(Validation, NoJoints) {
  ModelDescription<double> d = good;
  d.joints.clear();
  expect_refused(d, {"no joints", d.name}, /*static_too=*/false);
  EXPECT_NE(error_of<HumanModel<double>>(d).find("0 joints, the shape needs 16"), std::string::npos);
}

TEST_F(Validation, WrongTwistForTheStaticShape) {
  ModelDescription<double> d = good;
  d.joints[1].dh.alpha = 0;  // joint 2 has alpha = 90 degrees in Table 1
  const std::string message = error_of<HumanModel<double>>(d);
  EXPECT_NE(message.find("r_knee_pitch"), std::string::npos) << message;
  EXPECT_NE(message.find("twist"), std::string::npos) << message;
  EXPECT_EQ(error_of<AnyModel<double>>(d), "");
  // float keeps 90 degrees within its own rounding, and no more
  d.joints[1].dh.alpha = 1.5707963267948966 + 1e-4;
  EXPECT_NE(error_of<HumanModel<float>>(d).find("twist"), std::string::npos);
}

TEST_F(Validation, ParentNotEarlier) {
  ModelDescription<double> d = good;
  d.joints[4].parent = 6;  // joint 5 hung from joint 7
  expect_refused(d, {"joint 5", "waist_pitch", "parent 6", "must name an earlier joint"});
  d.joints[4].parent = 4;  // from itself
  expect_refused(d, {"joint 5", "must name an earlier joint"});
  d.joints[4].parent = -2;
  expect_refused(d, {"joint 5", "must name an earlier joint"});
}

TEST_F(Validation, WrongParentForTheStaticShape) {
  ModelDescription<double> d = good;
  d.joints[12].parent = 5;  // the left leg hung from the upper torso
  const std::string message = error_of<HumanModel<double>>(d);
  EXPECT_NE(message.find("l_hip_pitch"), std::string::npos) << message;
  EXPECT_NE(message.find("the shape needs 4"), std::string::npos) << message;
}

TEST_F(Validation, DuplicateJointName) {
  ModelDescription<double> d = good;
  d.joints[10].name = d.joints[7].name;
  expect_refused(d, {"joint 11", "l_shoulder_roll", "used twice"});
}

// A joint without a name: joint_index("") found it and its columns would read q_, tau_ (once accepted when
// alone)
TEST_F(Validation, AJointWithoutAName) {
  ModelDescription<double> d = good;
  d.joints[3].name.clear();
  expect_refused(d, {"joint 4", "the joint has no name"});
  d.joints.resize(1);
  d.joints[0].name.clear();
  const std::string message = error_of<AnyModel<double>>(d);
  EXPECT_NE(message.find("joint 1 '' (link '" + d.joints[0].link_name + "'): the joint has no name"), std::string::npos)
      << message;
}

TEST_F(Validation, BadMountRotation) {
  ModelDescription<double> d = good;
  auto& j = d.joints[6];  // joint 7, left shoulder pitch
  j.mounted = true;
  j.mount.R = 1.01 * Eigen::Matrix3d::Identity();  // not orthonormal
  expect_refused(d, {"joint 7", "l_shoulder_pitch", "mount", "not orthonormal"}, false);
  j.mount.R = Eigen::Vector3d(1, 1, -1).asDiagonal();  // a reflection
  expect_refused(d, {"joint 7", "mount", "right-handed"}, false);
  j.mount.R = Eigen::Matrix3d::Identity();
  j.mount.p.x() = kNaN;
  expect_refused(d, {"joint 7", "mount is not finite"}, false);
  // a valid mount suits a runtime shape, not the seed shape (which has none)
  j.mount.p.setZero();
  EXPECT_EQ(error_of<AnyModel<double>>(d), "");
  EXPECT_NE(error_of<HumanModel<double>>(d).find("no mount"), std::string::npos);
}

TEST_F(Validation, BadBasePoseOrGravity) {
  ModelDescription<double> d = good;
  d.base_pose.R(0, 0) = 2;
  expect_refused(d, {"base pose", "not orthonormal"});
  d = good;
  d.gravity.z() = kNaN;
  expect_refused(d, {"gravity is not finite"});
  d = good;
  d.base_body.mass = -1;
  expect_refused(d, {"base link", "r_foot", "negative mass"});
}

// The error says where the fault lies as data, not only in words: the joint's entry (from 0), the base
// or the model as a whole, for every kind of fault and both shapes.
TEST_F(Validation, TheErrorSaysWhereAndWhichJointEntry) {
  using Where = ModelError::Where;
  const auto fault_of = [](const ModelDescription<double>& d, auto shape) -> std::pair<Where, int> {
    try {
      typename decltype(shape)::type model(d);
      (void)model;
    } catch (const ModelError& e) {
      return {e.where(), e.joint()};
    }
    return {Where::Model, -99};
  };
  const auto expect_at = [&](const ModelDescription<double>& d, Where where, int joint) {
    EXPECT_EQ(fault_of(d, std::type_identity<AnyModel<double>>{}), std::make_pair(where, joint));
    EXPECT_EQ(fault_of(d, std::type_identity<HumanModel<double>>{}), std::make_pair(where, joint));
  };
  ModelDescription<double> d = good;
  d.joints[3].body.mass = -1;  // a body's fault
  expect_at(d, Where::Joint, 3);
  d = good;
  d.joints[12].dh.a = kNaN;  // a DH row's
  expect_at(d, Where::Joint, 12);
  d = good;
  d.joints[10].name = d.joints[7].name;  // a name's
  expect_at(d, Where::Joint, 10);
  d = good;
  d.joints[6].mounted = true;  // a mount's
  d.joints[6].mount.R = 1.01 * Eigen::Matrix3d::Identity();
  expect_at(d, Where::Joint, 6);
  d = good;
  d.base_pose.R(0, 0) = 2;
  expect_at(d, Where::Base, -1);
  d = good;
  d.base_body.mass = -1;
  expect_at(d, Where::Base, -1);
  d = good;
  d.gravity.z() = kNaN;
  expect_at(d, Where::Gravity, -1);
  d.gravity.z() = -1e6;  // beyond 1e5 m/s^2
  expect_at(d, Where::Gravity, -1);
  EXPECT_EQ(ModelError("x", Where::Base, 4).joint(), -1);  // an index only for a joint
}

TEST_F(Validation, NonPositiveBuilderLengthHeightOrMass) {
  for (const auto& f : detail::dimensions) {
    for (double bad : {0.0, -0.3, kNaN}) {
      SeedParameters p = default_parameters();
      p.*f.member = bad;
      try {
        (void)human_description(p);
        ADD_FAILURE() << f.name << " = " << bad << " accepted";
      } catch (const ModelError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find(std::string("length ") + f.name + " "), std::string::npos) << m;
        EXPECT_NE(m.find("must be positive"), std::string::npos) << m;
      }
    }
  }
  // a segment's mass: 0 leaves its links empty; negative or not finite is an error naming a link it goes on
  // (never the segment left out, which would make a lighter body)
  for (double bad : {-5.0, kNaN, kInf}) {
    SeedParameters p = default_parameters();
    p.thigh.mass = bad;
    try {
      (void)human_model<double>(p);
      ADD_FAILURE() << "thigh mass " << bad << " accepted";
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find("link 'r_thigh'"), std::string::npos) << e.what();
    }
  }
  SeedParameters no_thighs = default_parameters();
  no_thighs.thigh = {};
  EXPECT_NEAR(human_model<double>(no_thighs).total_mass(), 73.0 - 2 * default_parameters().thigh.mass, 1e-12);
  // a person scaled from de Leva needs a positive, finite height and mass
  for (const auto& [height, mass] :
       {std::pair{0.0, 70.0}, {-1.7, 70.0}, {kNaN, 70.0}, {1.8, 0.0}, {1.8, -70.0}, {1.8, kInf}}) {
    try {
      (void)de_leva_parameters(height, mass, anthropometry::Sex::Female);
      ADD_FAILURE() << height << " m, " << mass << " kg accepted";
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find("must be positive and finite"), std::string::npos) << e.what();
    }
  }
}

// with_dimensions_of reads a body's lengths and base pose back from its DH rows: the built-in bodies'
// exactly; a description whose rows are not the seed's formula of any lengths names the joint at fault.
TEST(Dimensions, ReadBackFromTheDescription) {
  for (SeedParameters p : {default_parameters(), female_parameters(), paper_parameters()}) {
    p.base_pose.p = Eigen::Vector3d(0.1, -0.2, 0.3);
    const SeedParameters back = with_dimensions_of(human_description(p), SeedParameters{});
    for (const auto& f : detail::dimensions) EXPECT_EQ(back.*f.member, p.*f.member) << p.name << " " << f.name;
    EXPECT_EQ(back.base_pose.p, p.base_pose.p);
    EXPECT_EQ(back.name, p.name);
  }
  const auto refused = [](const ModelDescription<double>& d, const std::string& want) {
    try {
      (void)with_dimensions_of(d, default_parameters());
      ADD_FAILURE() << "accepted; wanted " << want;
    } catch (const ModelError& e) {
      EXPECT_NE(std::string(e.what()).find(want), std::string::npos) << e.what();
    }
  };
  const ModelDescription<double> d = human_description(default_parameters());
  ModelDescription<double> e = d;
  e.joints[14].dh.a *= 1.01;  // the left shank's a1 against the right's
  refused(e, "joint 15 'l_knee_pitch': its DH a gives a1 = ");
  e = d;
  e.joints[2].dh.d = 0.05;  // a length where the seed has none
  refused(e, "joint 3 'r_hip_roll': its DH d is not 0");
  e = d;
  e.joints[4].dh.alpha = 0.3;
  refused(e, "joint 5 'waist_pitch': its DH twist");
  e = d;
  e.joints[7].name = "l_shoulder_abduction";
  refused(e, "joint 8 'l_shoulder_abduction': the body's joint 8 is 'l_shoulder_roll'");
  e = d;
  e.joints.pop_back();
  refused(e, "15 joints, where the body has 16");
}

}  // namespace

}  // namespace test_model
