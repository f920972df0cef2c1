// The compiled-in de Leva table (anthropometry.hpp) against its source file, and the anthropometric
// builders: total masses, and how the model scales with a person's height and mass.
#include "humandyn/humandyn.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace test_anthropometry {

namespace {

using namespace humandyn;
using anthropometry::Sex;
using humandyn::testing::random_states;

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) cells.push_back(cell);
  return cells;
}

// The table as the CSV file gives it: percentages and millimetres.
TEST(DeLevaTable, EqualsTheCsvFileRowByRow) {
  const std::filesystem::path file = std::filesystem::path(HUMANDYN_SHARED_DATA) / "anthropometry" / "de_leva_1996.csv";
  if (!std::filesystem::exists(file))
    GTEST_SKIP() << "the shared data folder is absent (" << file << "): nothing to compare the compiled-in table with";
  std::ifstream in(file);
  ASSERT_TRUE(in) << file;
  std::string line;
  std::vector<std::vector<std::string>> rows;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      EXPECT_EQ(line, "segment,endpoints,sex,length_mm,mass_pct,com_pct,r_sag,r_trans,r_long");
      header = false;
      continue;
    }
    rows.push_back(split(line));
  }
  ASSERT_EQ(rows.size(), anthropometry::de_leva_1996.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& csv = rows[i];
    const auto& r = anthropometry::de_leva_1996[i];
    SCOPED_TRACE("row " + std::to_string(i + 1) + ": " + csv[0] + " " + csv[1] + " " + csv[2]);
    ASSERT_EQ(csv.size(), 9u);
    EXPECT_EQ(csv[0], r.segment);
    EXPECT_EQ(csv[1], r.endpoints);
    EXPECT_EQ(csv[2], r.sex == Sex::Male ? "male" : "female");
    // each number as printed, to the rounding of a decimal conversion
    EXPECT_NEAR(std::stod(csv[3]) / 1000, r.length, 1e-15);
    EXPECT_NEAR(std::stod(csv[4]) / 100, r.mass_fraction, 1e-15);
    EXPECT_NEAR(std::stod(csv[5]) / 100, r.com, 1e-15);
    EXPECT_NEAR(std::stod(csv[6]) / 100, r.r_sag, 1e-15);
    EXPECT_NEAR(std::stod(csv[7]) / 100, r.r_trans, 1e-15);
    EXPECT_NEAR(std::stod(csv[8]) / 100, r.r_long, 1e-15);
  }
}

// The main rows (head, trunk, two of each limb segment) make a whole body: 100 % within the
// rounding of the printed percentages (two decimals: 0.005 % on each of 14 entries). As printed the
// male rows sum to 100.00 %, the female ones to 99.99 %.
TEST(DeLevaTable, MainRowsSumToAWholeBody) {
  for (Sex sex : {Sex::Male, Sex::Female}) {
    const double sum = anthropometry::whole_body_mass_fraction(sex);
    EXPECT_NEAR(sum, 1.0, 14 * 0.00005) << (sex == Sex::Male ? "male" : "female");
  }
  EXPECT_NEAR(anthropometry::whole_body_mass_fraction(Sex::Male), 1.0000, 1e-12);
  EXPECT_NEAR(anthropometry::whole_body_mass_fraction(Sex::Female), 0.9999, 1e-12);
}

// The builders' models weigh what the person weighs: the moving links and the stance foot.
TEST(DeLevaModels, TotalMasses) {
  EXPECT_NEAR(default_model<double>().total_mass(), 73.0, 1e-12);
  EXPECT_NEAR(human_model<double>(female_parameters()).total_mass(), 61.9, 1e-12);
  EXPECT_NEAR(human_model<double>(paper_parameters()).total_mass(), 73.0, 1e-12);
  EXPECT_NEAR(human_model<double>(de_leva_parameters(1.62, 55.5, Sex::Female)).total_mass(), 55.5, 1e-12);
  EXPECT_NEAR(default_model<float>().total_mass(), 73.0f, 1e-4f);
}

// Each link carries the de Leva segments documented in builders.hpp, at their fraction of the mass.
TEST(DeLevaModels, SegmentsOnTheLinks) {
  const auto m = default_model<double>();
  const auto& d = m.description();
  const auto pct = [](double p) { return p / 100 * 73.0; };
  EXPECT_NEAR(d.joints[0].body.mass, pct(4.33), 1e-12);                  // right shank
  EXPECT_NEAR(d.joints[1].body.mass, pct(14.16), 1e-12);                 // right thigh
  EXPECT_NEAR(d.joints[3].body.mass, pct(11.17), 1e-12);                 // pelvis: lower trunk
  EXPECT_NEAR(d.joints[5].body.mass, pct(15.96 + 16.33 + 6.94), 1e-12);  // upper and middle trunk, head and neck
  EXPECT_NEAR(d.joints[7].body.mass, pct(2.71), 1e-12);                  // left upper arm
  EXPECT_NEAR(d.joints[8].body.mass, pct(1.62 + 0.61), 1e-12);           // left forearm and hand
  EXPECT_NEAR(d.joints[10].body.mass, pct(2.71), 1e-12);                 // right upper arm
  EXPECT_NEAR(d.joints[11].body.mass, pct(1.62 + 0.61), 1e-12);          // right forearm and hand
  EXPECT_NEAR(d.joints[13].body.mass, pct(14.16), 1e-12);                // left thigh
  EXPECT_NEAR(d.joints[14].body.mass, pct(4.33), 1e-12);                 // left shank
  EXPECT_NEAR(d.joints[15].body.mass, pct(1.37), 1e-12);                 // left foot
  EXPECT_NEAR(d.base_body.mass, pct(1.37), 1e-12);                       // the stance foot
  for (int i : {2, 4, 6, 9, 12}) EXPECT_EQ(d.joints[std::size_t(i)].body.mass, 0.0) << "joint " << i + 1;
  // Table 1's lengths: de Leva's segment lengths
  const SeedParameters p = default_parameters();
  EXPECT_NEAR(p.a1, 0.4403, 1e-12);  // shank, knee to ankle joint centre
  EXPECT_NEAR(p.a2, 0.4222, 1e-12);  // thigh
  EXPECT_NEAR(p.d6, 0.5319, 1e-12);  // trunk, suprasternale to mid-hip
  EXPECT_NEAR(p.a8, 0.2817, 1e-12);  // upper arm
  EXPECT_NEAR(p.a9, 0.2689, 1e-12);  // forearm
}

// The body's name gives its height and mass as given, in the shortest form that reads back.
TEST(DeLevaScaling, TheNameGivesHeightAndMassAsGiven) {
  EXPECT_EQ(de_leva_parameters(1.80, 70.0, Sex::Male).name, "de Leva male 1.8 m 70 kg");
  EXPECT_EQ(de_leva_parameters(1.625, 61.99, Sex::Female).name, "de Leva female 1.625 m 61.99 kg");
}

// Twice the mass, same height: every segment twice as heavy, same geometry, so every torque doubles
// (inertial, velocity-product and gravity terms alike).
TEST(DeLevaScaling, DoubleMassDoublesTorques) {
  const auto m1 = human_model<double>(de_leva_parameters(1.80, 70.0, Sex::Male));
  const auto m2 = human_model<double>(de_leva_parameters(1.80, 140.0, Sex::Male));
  Data<HumanModel<double>> d1(m1), d2(m2);
  double worst = 0, largest = 0;
  for (const auto& s : random_states(16, 200, 41)) {
    const Eigen::VectorXd t1 = rnea(m1, d1, s.q, s.qd, s.qdd);
    const Eigen::VectorXd t2 = rnea(m2, d2, s.q, s.qd, s.qdd);
    worst = std::max(worst, (t2 - 2 * t1).cwiseAbs().maxCoeff());
    largest = std::max(largest, t1.cwiseAbs().maxCoeff());
  }
  EXPECT_GT(largest, 100.0);
  EXPECT_LE(worst, 1e-12 * largest);
}

// Height scaled by k, same mass: lengths and centres of mass scale by k, inertias by k^2. Gravity
// torques (mass x g x lever) scale by k; the torques of accelerations and velocities (inertia and
// mass x lever^2 terms) by k^2.
TEST(DeLevaScaling, HeightScalesLeversAndInertias) {
  const double k = 1.25;
  const SeedParameters p1 = de_leva_parameters(1.60, 65.0, Sex::Female);
  const SeedParameters p2 = de_leva_parameters(1.60 * k, 65.0, Sex::Female);
  for (auto [a, b] : {std::pair{p1.a1, p2.a1},
                      {p1.a2, p2.a2},
                      {p1.d4, p2.d4},
                      {p1.d6, p2.d6},
                      {p1.d7, p2.d7},
                      {p1.a8, p2.a8},
                      {p1.a9, p2.a9},
                      {p1.a16, p2.a16}})
    EXPECT_NEAR(b, k * a, 1e-12);
  EXPECT_NEAR(p2.forearm.mass, p1.forearm.mass, 1e-12);

  const auto m1 = human_model<double>(p1);
  const auto m2 = human_model<double>(p2);
  Data<HumanModel<double>> d1(m1), d2(m2);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(16);
  double worst_gravity = 0, worst_motion = 0, largest = 0;
  for (const auto& s : random_states(16, 200, 42)) {
    const Eigen::VectorXd g1 = gravity_torques(m1, d1, s.q), g2 = gravity_torques(m2, d2, s.q);
    worst_gravity = std::max(worst_gravity, (g2 - k * g1).cwiseAbs().maxCoeff());
    const Eigen::VectorXd a1 = Eigen::VectorXd(rnea(m1, d1, s.q, s.qd, s.qdd)) - g1;
    const Eigen::VectorXd a2 = Eigen::VectorXd(rnea(m2, d2, s.q, s.qd, s.qdd)) - g2;
    worst_motion = std::max(worst_motion, (a2 - k * k * a1).cwiseAbs().maxCoeff());
    largest = std::max(largest, a1.cwiseAbs().maxCoeff());
  }
  EXPECT_GT(largest, 100.0);
  EXPECT_LE(worst_gravity, 1e-12 * largest);
  EXPECT_LE(worst_motion, 1e-12 * largest);
}

// Sex picks the reference subject: the female model differs from the male one of the same size.
TEST(DeLevaScaling, SexPicksTheReference) {
  const SeedParameters male = de_leva_parameters(1.70, 65.0, Sex::Male);
  const SeedParameters female = de_leva_parameters(1.70, 65.0, Sex::Female);
  EXPECT_NEAR(female.a2, 0.3685 * 1.70 / 1.735, 1e-12);  // the female thigh, scaled
  EXPECT_NEAR(male.a2, 0.4222 * 1.70 / 1.741, 1e-12);
  EXPECT_GT(female.thigh.mass, male.thigh.mass);  // 14.78 % against 14.16 %
}

}  // namespace

}  // namespace test_anthropometry
