// The command line: the CSV and JSON formats (JSON: strict syntax, errors with line and column or path), the model as
// JSON (rebuilt from the file alone it gives the same torques as the built-in model and as KDL), `humandyn id` against
// the library's rnea, `humandyn demo`'s exact zeros, and clear errors with non-zero exit codes for bad input.
#include "cli/csv.hpp"
#include "cli/json.hpp"
#include "cli/model_json.hpp"
#include "humandyn/humandyn.hpp"
#include "support/cli_run.hpp"
#include "support/kdl_tree.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace test_cli {

namespace {

using namespace humandyn;
using namespace humandyn::cli;
namespace fs = std::filesystem;
using humandyn::testing::CliRun;
using humandyn::testing::humandyn_cli;
using humandyn::testing::input_error;
using humandyn::testing::joint_names;
using humandyn::testing::read_text;
using humandyn::testing::Scratch;
using humandyn::testing::states_csv;
using humandyn::testing::write_text;

constexpr double pi = 3.14159265358979323846;

// ---- helpers ---------------------------------------------------------------------------------------

// ---- CSV -------------------------------------------------------------------------------------------

TEST(Csv, ReadsHeaderAndRowsSkippingBlankLinesWithCrlfAndPadding) {
  const CsvTable t = parse_csv("\n q_a , q_b\r\n1,+2.5\r\n\n  -0 ,1e-3 \n", "s.csv");
  ASSERT_EQ(t.header, (std::vector<std::string>{"q_a", "q_b"}));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0], (std::vector<double>{1.0, 2.5}));
  EXPECT_EQ(t.rows[1], (std::vector<double>{-0.0, 0.001}));
  EXPECT_EQ(t.lines, (std::vector<int>{3, 5}));  // the file's own line numbers, blank lines counted
  EXPECT_EQ(t.column("q_b"), 1);
  EXPECT_EQ(t.column("q_c"), -1);
  // a header without rows is a valid, empty table
  EXPECT_TRUE(parse_csv("q_a\n", "h.csv").rows.empty());
}

TEST(Csv, EveryBadInputNamesFileLineAndColumn) {
  struct Case {
    const char* text;
    const char* message;  // the whole message, so that file, line, column and reason are all checked
  };
  const Case cases[] = {
      {"", "s.csv: line 1: empty file: expected a header row of column names"},
      {"\n  \n",
       "s.csv: line 1: no header row: the file holds nothing but blank lines (expected a header row of column names)"},
      {"a,b\n1,x\n", "s.csv: line 2, column 2 'b': 'x' is not a number"},
      {"a,b\n1,2\n3,nan\n", "s.csv: line 3, column 2 'b': 'nan' is not a finite number"},
      {"a,b\n1,2\n-inf,0\n", "s.csv: line 3, column 1 'a': '-inf' is not a finite number"},
      {"a,b\n1e999,0\n", "s.csv: line 2, column 1 'a': '1e999' is out of the range of a double: too large"},
      {"a,b\n1,\n", "s.csv: line 2, column 2 'b': empty cell, expected a number"},
      {"a,b,c\n1,2\n", "s.csv: line 2, column 3 'c': missing cell: the row has 2 cells, the header 3 columns"},
      {"a,b\n1,2,3\n", "s.csv: line 2, column 3: extra cell: the row has 3 cells, the header 2 columns"},
      {"a,b\n1,2\n\n4,5,\n", "s.csv: line 4, column 3: extra cell: the row has 3 cells, the header 2 columns"},
      {"a,,b\n", "s.csv: line 1, column 2: empty column name in the header"},
      {"a,b,a\n", "s.csv: line 1, column 3 'a': column name repeated (first at column 1)"},
      {"a\n0x10\n", "s.csv: line 2, column 1 'a': '0x10' is not a number"},
      {"a\n+-1\n", "s.csv: line 2, column 1 'a': '+-1' is not a number"},
      {"a\n1.5.2\n", "s.csv: line 2, column 1 'a': '1.5.2' is not a number"},
      {"a\n\"1x\"\n", "s.csv: line 2, column 1 'a': '1x' is not a number"},  // a quoted cell is read unquoted
  };
  for (const auto& c : cases) EXPECT_EQ(input_error([&] { parse_csv(c.text, "s.csv"); }), c.message) << c.text;
}

TEST(Csv, MissingAndUnknownColumnsAreReportedBeforeAnyRow) {
  const std::vector<std::string> allowed{"q_a", "q_b", "qd_a"};
  const auto check = [&](const CsvTable& t) {
    t.reject_unknown_columns(allowed);
    require_columns(t, joint_columns({"a", "b"}, "q_"));
  };
  // the bad cell on line 2 is never reached: the header's error comes first
  EXPECT_EQ(input_error([&] { parse_csv("q_a,q_b,qd_z\nx,1,2\n", "s.csv", check); }),
            "s.csv: line 1, column 3 'qd_z': unknown column");
  EXPECT_EQ(input_error([&] { parse_csv("q_a,qd_a\nx,1\n", "s.csv", check); }), "s.csv: line 1: missing column 'q_b'");
  EXPECT_EQ(input_error([&] { parse_csv("q_b,q_a\n1,2\n", "s.csv", check); }), "");
  const CsvTable t = parse_csv("q_b,q_a\n1,2\n", "s.csv");
  EXPECT_EQ(require_columns(t, joint_columns({"a", "b"}, "q_")), (std::vector<int>{1, 0}));
  EXPECT_EQ(input_error([&] { t.fail_at(0, 1, "too far"); }), "s.csv: line 2, column 2 'q_a': too far");
}

TEST(Csv, ReadingAFileThatIsNotThereSaysSo) {
  const std::string message = input_error([] { read_csv("/nonexistent/states.csv"); });
  EXPECT_NE(message.find("/nonexistent/states.csv: cannot open"), std::string::npos) << message;
}

TEST(Csv, NumbersRoundTripExactly) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> e(-300, 300);
  for (int k = 0; k < 10000; ++k) {
    const double x = u(rng) * std::pow(10.0, e(rng));
    const std::string s = format_number(x);
    double y = 0;
    std::from_chars(s.data(), s.data() + s.size(), y);
    ASSERT_EQ(x, y) << s;
    const CsvTable t = parse_csv("a\n" + s + "\n", "n.csv");
    ASSERT_EQ(t.rows[0][0], x) << s;
  }
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(-1), "-1");
}

TEST(Csv, WriterReplacesTheFileOnlyOnCommit) {
  Scratch dir;
  const fs::path path = dir / "out.csv";
  write_text(path, "old\n");
  {
    CsvWriter w(path.string(), {"a", "b"});
    w.row({1, 2});
    // abandoned without commit: an error half-way
  }
  EXPECT_EQ(read_text(path), "old\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.dir()), fs::directory_iterator()), 1) << "temporary file left";
  {
    CsvWriter w(path.string(), {"a", "b"});
    w.row({1, 0.25});
    EXPECT_THROW(w.row({1}), InputError);
    EXPECT_THROW(w.row({1, std::nan("")}), InputError);
    w.row({-3, 1e-300});
    w.commit();
  }
  EXPECT_EQ(read_text(path), "a,b\n1,0.25\n-3,1e-300\n");
  EXPECT_THROW(CsvWriter("/nonexistent/out.csv", {"a"}), InputError);
}

// ---- JSON ------------------------------------------------------------------------------------------

TEST(Json, ReadsWhatItWritesAndWritesNonFiniteNumbersAsNull) {
  json::Json doc{{"name", "a \"quoted\" \\ name\twith\ncontrol \x01 chars"},
                 {"n", 0.1},
                 {"big", -1.7976931348623157e308},
                 {"tiny", 5e-324},
                 {"flags", {true, false, nullptr}},
                 {"inner", {{"x", 1}}},
                 {"empty", json::Json::object()}};
  const std::string text = json::write(doc);
  const json::Json back = json::parse(text, "t.json");
  EXPECT_EQ(back, doc);
  EXPECT_EQ(back["n"].get<double>(), 0.1);
  EXPECT_EQ(back["tiny"].get<double>(), 5e-324);
  EXPECT_EQ(json::write(back), text);
  // escapes, including a surrogate pair, become UTF-8
  EXPECT_EQ(json::parse(R"("\u00e9\ud83d\ude00\/")", "u.json").get<std::string>(), "\xc3\xa9\xf0\x9f\x98\x80/");
  // JSON has no NaN or infinity: every writer of ours puts null there
  EXPECT_EQ(json::write(json::Json::array({std::nan(""), INFINITY, 1.5})), "[\n  null,\n  null,\n  1.5\n]\n");
}

// The line and column are those of the last character the parser read (one past the end at the end).
TEST(Json, SyntaxErrorsNameLineAndColumn) {
  struct Case {
    const char* text;
    const char* message;
  };
  const Case cases[] = {
      {"", "j.json: line 1, column 1: syntax error while parsing value - unexpected end of input"},
      {"{\n  \"a\": 1,\n}", "j.json: line 3, column 1: syntax error while parsing object key - unexpected '}'"},
      {"{\"a\": 1 \"b\": 2}",
       "j.json: line 1, column 11: syntax error while parsing object - unexpected string literal"},
      {"[1, 2", "j.json: line 1, column 6: syntax error while parsing array - unexpected end of input"},
      {"[1.]", "j.json: line 1, column 4: syntax error while parsing value - invalid number"},
      {"[NaN]", "j.json: line 1, column 2: syntax error while parsing value - invalid literal"},
      {"\n\n  \"abc",
       "j.json: line 3, column 7: syntax error while parsing value - invalid string: missing closing quote"},
      {"{} x", "j.json: line 1, column 4: syntax error while parsing value - invalid literal"},
      {"// c\n{}", "j.json: line 1, column 1: syntax error while parsing value - invalid literal"},
  };
  for (const auto& c : cases) {
    const std::string message = input_error([&] { json::parse(c.text, "j.json"); });
    EXPECT_EQ(message.substr(0, std::string(c.message).size()), c.message) << c.text << "\n" << message;
  }
  // a byte that is not UTF-8 is shown as messages show it; a NUL byte, which the parser would take for the
  // end of its input (passing over what follows), is an error where it stands
  EXPECT_EQ(input_error([] { json::parse("[\"de\xFF\"]", "j.json"); }),
            "j.json: line 1, column 5: syntax error while parsing value - invalid string: ill-formed UTF-8 byte; "
            "last read: '\"de<0xFF>'");
  // (the parser's own advice keeps its backslashes; a UTF-16 file is said to be one, not to hold NULs)
  EXPECT_EQ(input_error([] { json::parse("[\"a\tb\"]", "j.json"); }),
            "j.json: line 1, column 4: syntax error while parsing value - invalid string: control character U+0009 "
            "(HT) must be escaped to \\u0009 or \\t; last read: '\"a<U+0009>'");
  EXPECT_EQ(input_error([] { json::parse(std::string("\xFF\xFE{\0}\0", 6), "j.json"); }),
            "j.json: line 1: the file is UTF-16 (it starts with a UTF-16 byte-order mark): save it as UTF-8");
  EXPECT_EQ(input_error([] { json::parse(std::string("{}\0{ garbage", 12), "j.json"); }),
            "j.json: line 1, column 3: a NUL byte, which JSON text cannot hold (\\u0000 inside a string)");
  EXPECT_EQ(input_error([] { json::parse(std::string("{\n \"a\":\0 1}", 11), "j.json"); }),
            "j.json: line 2, column 6: a NUL byte, which JSON text cannot hold (\\u0000 inside a string)");
  // what the parser itself lets through: repeated keys and deep nesting, named by their path
  EXPECT_EQ(input_error([] { json::parse("{\"j\": [{\"a\": 1, \"a\": 2}]}", "j.json"); }),
            "j.json: /j/0: key 'a' repeated in an object");
  EXPECT_EQ(input_error([] { json::parse("{\"a\": 1, \"a\": 2}", "j.json"); }),
            "j.json: the top level: key 'a' repeated in an object");
  EXPECT_NE(input_error([] { json::parse(std::string(1000, '['), "deep.json"); }).find("nested deeper than 200"),
            std::string::npos);
  // a number beyond a double's range: its line and column and the entry it was to be
  EXPECT_EQ(
      input_error([] { json::parse("{\"s\": \"1e400\",\n \"j\": [{\"dh\": {\"d\": 1, \"a\": 1e400}}]}", "j.json"); }),
      "j.json: line 2, column 29: /j/0/dh/a: number overflow parsing '1e400'");
  EXPECT_EQ(input_error([] { json::parse("{\r\"a\":\r\r [1, 1e999]}", "j.json"); }),  // old Mac OS line ends
            "j.json: line 4, column 6: /a/1: number overflow parsing '1e999'");
  EXPECT_EQ(
      input_error([] { json::parse("{\r\n  \"a\": 1,\r\n}", "j.json"); }),
      "j.json: line 3, column 1: syntax error while parsing object key - unexpected '}'; expected string literal");
  EXPECT_EQ(input_error([] { json::parse("[2, -1e999]", "j.json"); }),
            "j.json: line 1, column 5: /1: number overflow parsing '-1e999'");
  // one a double holds only as 0, which the parser reads as 0 without a word: its line and column (in a
  // string, it is text; a subnormal number reads as itself)
  EXPECT_EQ(input_error([] { json::parse("{\"s\": \"1e-400\", \"a\": [1,\n 8.5e-400]}", "j.json"); }),
            "j.json: line 2, column 2: '8.5e-400' is out of the range of a double: too small, it would read as 0");
  EXPECT_EQ(input_error([] { json::parse("[-1E-999]", "j.json"); }),
            "j.json: line 1, column 2: '-1E-999' is out of the range of a double: too small, it would read as 0");
  EXPECT_EQ(json::parse("[5e-324, 0, 0.0, -0e-999]", "j.json")[0].get<double>(), 5e-324);
}

TEST(Json, MeaningErrorsNameThePath) {
  const json::Json doc =
      json::parse("{\n  \"mass\": \"heavy\",\n  \"n\": 2.5,\n  \"typo\": 1, \"a/b\": [1]\n}", "m.json");
  const json::Node root(doc, "m.json");
  EXPECT_EQ(input_error([&] { root.at("mass").number(); }), "m.json: /mass: must be a number, not a string");
  EXPECT_EQ(input_error([&] { root.at("n").whole(); }), "m.json: /n: must be a whole number, not 2.5");
  EXPECT_EQ(input_error([&] { root.at("missing"); }), "m.json: the top level: missing key 'missing'");
  EXPECT_EQ(input_error([&] {
              root.reject_unknown_keys({"mass", "n", "a/b"});
            }),
            "m.json: the top level: unknown key 'typo' (expected: mass, n, a/b)");
  EXPECT_EQ(input_error([&] { root.at("a/b")[0].string(); }), "m.json: /a~1b/0: must be a string, not a number");
  // a key is shown as messages show names (an invisible or a control character by its code point)
  const json::Json odd = json::parse("{\"ty\\u0001po\": 1}", "m.json");
  EXPECT_EQ(input_error([&] { json::Node(odd, "m.json").reject_unknown_keys({"mass"}); }),
            "m.json: the top level: unknown key 'ty<U+0001>po' (expected: mass)");
}

// ---- the model as JSON -----------------------------------------------------------------------------

// A small tree with every feature of the format: mounts, a branch, general and special twists.
ModelDescription<double> mounted_model() {
  ModelDescription<double> d;
  d.name = "mounted";
  d.base_link_name = "foot";
  d.base_pose.R = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  d.base_pose.p = Eigen::Vector3d(0.1, -0.2, 0.3);
  d.base_body.mass = 1.1;
  d.base_body.com = Eigen::Vector3d(0.01, 0.02, 0.03);
  d.base_body.inertia = Eigen::Vector3d(0.01, 0.02, 0.025).asDiagonal();
  d.gravity = Eigen::Vector3d(0.1, 0.2, -9.8);
  for (int i = 0; i < 5; ++i) {
    JointDescription<double> j;
    j.name = "j" + std::to_string(i);
    j.link_name = "link" + std::to_string(i);
    j.parent = i == 0 ? -1 : i == 3 ? 1 : i - 1;
    j.dh = {0.1 * (i + 1), i % 2 ? pi / 2 : 0.37 * i, 0.05 * i, -0.2 * i};
    if (i % 2 == 0) {
      j.mounted = true;
      j.mount.R = Eigen::AngleAxisd(0.5 + i, Eigen::Vector3d(0.3, -1, 0.2).normalized()).toRotationMatrix();
      j.mount.p = Eigen::Vector3d(0.02 * i, 0.01, -0.03);
    }
    j.body.mass = 0.5 + i;
    j.body.com = Eigen::Vector3d(0.01 * i, -0.02, 0.03);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.2 * i, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    j.body.inertia = R * Eigen::Vector3d(0.02, 0.03, 0.04).asDiagonal() * R.transpose();
    d.joints.push_back(j);
  }
  return d;
}

void expect_same_description(const ModelDescription<double>& a, const ModelDescription<double>& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.base_link_name, b.base_link_name);
  EXPECT_EQ(a.base_pose.R, b.base_pose.R);
  EXPECT_EQ(a.base_pose.p, b.base_pose.p);
  EXPECT_EQ(a.base_body.mass, b.base_body.mass);
  EXPECT_EQ(a.base_body.com, b.base_body.com);
  EXPECT_EQ(a.base_body.inertia, b.base_body.inertia);
  EXPECT_EQ(a.gravity, b.gravity);
  ASSERT_EQ(a.joints.size(), b.joints.size());
  for (std::size_t i = 0; i < a.joints.size(); ++i) {
    const auto &x = a.joints[i], &y = b.joints[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.link_name, y.link_name);
    EXPECT_EQ(x.parent, y.parent);
    EXPECT_EQ(x.mounted, y.mounted);
    if (x.mounted) {
      EXPECT_EQ(x.mount.R, y.mount.R);
      EXPECT_EQ(x.mount.p, y.mount.p);
    }
    EXPECT_EQ(x.dh.a, y.dh.a);
    EXPECT_EQ(x.dh.alpha, y.dh.alpha);
    EXPECT_EQ(x.dh.d, y.dh.d);
    EXPECT_EQ(x.dh.theta, y.dh.theta);
    EXPECT_EQ(x.body.mass, y.body.mass);
    EXPECT_EQ(x.body.com, y.body.com);
    EXPECT_EQ(x.body.inertia, y.body.inertia);
  }
}

TEST(ModelJson, RoundTripIsBitExactWithMountsAndBranches) {
  const auto d = mounted_model();
  const auto back = parse_model_json(write_model_json(d), "m.json");
  expect_same_description(d, back);
  // and the rebuilt model moves like the original under KDL's solver
  const AnyModel<double> model(back);
  Data<AnyModel<double>> data(model);
  humandyn::testing::KdlTreeDynamics kdl(d);
  for (const auto& s : humandyn::testing::random_states(5, 200, 11)) {
    const Eigen::VectorXd tau = rnea(model, data, s.q, s.qd, s.qdd);
    EXPECT_LT((tau - kdl.torques(s)).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(ModelJson, AMountMayBeAHomogeneousMatrixAndEveryInertialNumberIsRequired) {
  const std::string base = R"("gravity": [0, 0, -9.81],
    "base": {"pose": {"R": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "p": [0, 0, 0]},
             "link": {"name": "foot", "mass": 1, "com": [0, 0, 0], "inertia": [[0.01, 0, 0], [0, 0.01, 0], [0, 0, 0.01]]}},)";
  const std::string text = R"({"format": "humandyn-model", "version": 1, )" + base + R"( "joints": [
    {"name": "a", "parent": -1, "dh": {"a": 0.5, "alpha": 0, "d": 0, "theta": 0},
     "mount": [[0, -1, 0, 0.1], [1, 0, 0, 0.2], [0, 0, 1, 0.3], [0, 0, 0, 1]],
     "link": {"name": "arm", "mass": 2, "com": [0.25, 0, 0], "inertia": [[0.01, 0, 0], [0, 0.04, 0], [0, 0, 0.04]]}}]})";
  const auto d = parse_model_json(text, "h.json");
  ASSERT_EQ(d.joints.size(), 1u);
  EXPECT_TRUE(d.joints[0].mounted);
  EXPECT_EQ(d.joints[0].mount.R, (Eigen::Matrix3d() << 0, -1, 0, 1, 0, 0, 0, 0, 1).finished());
  EXPECT_EQ(d.joints[0].mount.p, Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(d.joints[0].body.inertia(1, 1), 0.04);
  EXPECT_EQ(d.base_body.mass, 1);
  // each inertial number, the base's pose and link and gravity: a missing one is an error, never a zero
  const std::pair<std::string, std::string> cut[] = {
      {R"("inertia": [[0.01, 0, 0], [0, 0.04, 0], [0, 0, 0.04]])", "/joints/0/link: missing key 'inertia'"},
      {R"("mass": 2, )", "/joints/0/link: missing key 'mass'"},
      {R"("com": [0.25, 0, 0], )", "/joints/0/link: missing key 'com'"},
      {R"("gravity": [0, 0, -9.81],)", "the top level: missing key 'gravity'"},
      {R"("p": [0, 0, 0])", "/base/pose: missing key 'p'"},
  };
  for (const auto& [part, message] : cut) {
    std::string t = text;
    const std::size_t at = t.find(part);
    ASSERT_NE(at, std::string::npos) << part;
    t.erase(at, part.size());
    if (const std::size_t dangling = t.find(", }"); dangling != std::string::npos) t.erase(dangling, 1);
    if (const std::size_t dangling = t.find(",}"); dangling != std::string::npos) t.erase(dangling, 1);
    const std::string got = input_error([&] { parse_model_json(t, "h.json"); });
    EXPECT_NE(got.find(message), std::string::npos) << part << "\n" << got;
  }
}

TEST(ModelJson, TheLibrarysRefusalNamesTheFileAndTheEntry) {
  // a negative mass and a link name given twice: the file and the joint's entry (counted from 0) named
  auto d = human_description(default_parameters());
  d.joints[3].body.mass = -1;
  std::string message = input_error([&] { parse_model_json(write_model_json(d), "neg.json"); });
  EXPECT_EQ(message.rfind("neg.json: /joints/3: invalid model: joint 4 '" + d.joints[3].name + "'", 0), 0u) << message;
  EXPECT_NE(message.find("negative mass -1 kg"), std::string::npos) << message;
  d = human_description(default_parameters());
  d.joints[1].link_name = d.joints[2].link_name;
  message = input_error([&] { parse_model_json(write_model_json(d), "dup.json"); });
  EXPECT_EQ(message.rfind("dup.json: /joints/2: invalid model: joint 3", 0), 0u) << message;
  EXPECT_NE(message.find("link name used twice (also joint 2's)"), std::string::npos) << message;
  // the base's faults name its entry; names show their invisible characters
  d = human_description(default_parameters());
  d.base_body.mass = -1;
  d.base_link_name += "\u200B";
  message = input_error([&] { parse_model_json(write_model_json(d), "base.json"); });
  EXPECT_EQ(message.rfind("base.json: /base: invalid model: base link '", 0), 0u) << message;
  EXPECT_NE(message.find("<U+200B>': negative mass"), std::string::npos) << message;
  // and gravity's (it named none)
  d = human_description(default_parameters());
  d.gravity.z() = -1e308;
  message = input_error([&] { parse_model_json(write_model_json(d), "g.json"); });
  EXPECT_EQ(message.rfind("g.json: /gravity: invalid model: model '", 0), 0u) << message;
  EXPECT_NE(message.find("m/s^2 is beyond 1e+05 m/s^2"), std::string::npos) << message;
  // a joint's name follows the rule of every joint name: a CSV header must be able to carry it
  for (const char* bad : {"a,b", "knee\u200B", " knee", ""}) {
    d = human_description(default_parameters());
    d.joints[5].name = bad;
    message = input_error([&] { parse_model_json(write_model_json(d), "name.json"); });
    EXPECT_EQ(message.rfind("name.json: /joints/5/name: ", 0), 0u) << message;
    EXPECT_NE(message.find(std::string(bad).empty() ? "the name is empty" : "so no CSV column can name the joint"),
              std::string::npos)
        << message;
  }
  // a link's and the model's names: UTF-8 with no control character but those XML carries (tab, line ends)
  d = human_description(default_parameters());
  d.joints[2].link_name = "thigh\x07x";
  message = input_error([&] { parse_model_json(write_model_json(d), "link.json"); });
  EXPECT_EQ(message, "link.json: /joints/2/link/name: the name holds a control character, <U+0007>") << message;
  d.joints[2].link_name = "thigh\nx";
  EXPECT_EQ(parse_model_json(write_model_json(d), "link.json").joints[2].link_name, "thigh\nx");
  d = human_description(default_parameters());
  d.name = "body\x1b[31m";
  message = input_error([&] { parse_model_json(write_model_json(d), "model.json"); });
  EXPECT_EQ(message.rfind("model.json: /name: the name holds a control character, <U+001B>", 0), 0u) << message;
  d.name = "body\xEF\xBF\xBF";  // U+FFFF, no character: XML cannot carry it either
  message = input_error([&] { parse_model_json(write_model_json(d), "model.json"); });
  EXPECT_EQ(message.rfind("model.json: /name: the name holds a noncharacter, <U+FFFF>", 0), 0u) << message;
  d.name = "";  // (a URDF's robot may have none, and the file written from it reads back)
  EXPECT_EQ(parse_model_json(write_model_json(d), "model.json").name, "");
}

TEST(ModelJson, ReaderErrorsNameTheEntry) {
  const std::string head =
      "{\"format\": \"humandyn-model\", \"version\": 1, \"gravity\": [0, 0, -9.81], \"base\": {\"pose\": "
      "{\"R\": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], \"p\": [0, 0, 0]}, \"link\": {\"name\": \"foot\", \"mass\": 0, "
      "\"com\": [0, 0, 0], \"inertia\": [[0, 0, 0], [0, 0, 0], [0, 0, 0]]}},\n\"joints\": [\n";
  const std::string dh = "\"dh\": {\"a\": 1, \"alpha\": 0, \"d\": 0, \"theta\": 0}";
  struct Case {
    std::string text, message;
  };
  const Case cases[] = {
      {"[]", "bad.json: the top level: must be an object, not an array"},
      {"{\"format\": \"other\", \"version\": 1, \"joints\": []}", "bad.json: /format: 'other' is not 'humandyn-model'"},
      {"{\"format\": \"humandyn-model\", \"version\": 2, \"joints\": []}",
       "bad.json: /version: version 2 is not supported (this program reads version 1)"},
      {head + "]}", "bad.json: /joints: is empty: a model needs at least one joint"},
      {head + "{\"name\": \"a\", \"parent\": 0, " + dh + ", \"link\": {\"name\": \"l\"}}]}",
       "bad.json: /joints/0/parent: 0 (joint 'a') must be -1 (the base) or the index of an earlier joint "
       "(parents come first)"},
      {head + "{\"name\": \"a\", \"parent\": -1, " + dh +
           ", \"link\": {\"name\": \"l\", \"mass\": 1, \"com\": [1, 2]}}]}",
       "bad.json: /joints/0/link/com: must hold 3 numbers, not 2"},
      {head + "{\"name\": \"a\", \"parent\": -1, " + dh + ", \"link\": {\"name\": \"l\", \"mass\": \"2\"}}]}",
       "bad.json: /joints/0/link/mass: must be a number, not a string"},
      {head + "{\"name\": \"a\", \"parent\": -1, \"dh\": {\"a\": 1, \"alpha\": 0, \"d\": 0}, \"link\": {\"name\": "
              "\"l\"}}]}",
       "bad.json: /joints/0/dh: missing key 'theta'"},
      {head + "{\"name\": \"a\", \"parent\": -1, \"mass\": 1, " + dh + ", \"link\": {\"name\": \"l\"}}]}",
       "bad.json: /joints/0: unknown key 'mass' (expected: index, name, parent, mount, dh, link)"},
      {head + "{\"index\": 3, \"name\": \"a\", \"parent\": -1, " + dh + ", \"link\": {\"name\": \"l\"}}]}",
       "bad.json: /joints/0/index: is 3 but the joint stands at position 0 of the list"},
      {head +
           "{\"name\": \"a\", \"parent\": -1, \"mount\": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 2]], " +
           dh + ", \"link\": {\"name\": \"l\"}}]}",
       "bad.json: /joints/0/mount/3: the last row of a homogeneous matrix must be [0, 0, 0, 1]"},
      {head + "{\"name\": \"a\", \"parent\": -1, " + dh + ", \"link\": {\"name\": \"l\", \"mass\": null}}]}",
       "bad.json: /joints/0/link/mass: must be a number, not null"},
      {head + "{\"name\": \"a\", \"parent\": -1, " + dh + ",\n \"link\": {\"name\": \"l\", \"mass\": 1,}}]}",
       "bad.json: line 4, column 34: syntax error while parsing object key - unexpected '}'"},
  };
  for (const auto& c : cases) {
    const std::string message = input_error([&] { parse_model_json(c.text, "bad.json"); });
    EXPECT_EQ(message.substr(0, c.message.size()), c.message) << c.text << "\n" << message;
  }
}

// ---- humandyn model ----------------------------------------------------------------------------------

// Someone with only `humandyn model --json` rebuilds the model: the same torques as the built-in model
// (bit for bit, the numbers round-trip exactly) and as KDL's tree solver built from the parsed file.
TEST(CliModel, JsonAloneRebuildsTheModel) {
  Scratch dir;
  const std::pair<const char*, SeedParameters> builtins[] = {
      {"default", default_parameters()}, {"female", female_parameters()}, {"paper", paper_parameters()}};
  for (const auto& [name, params] : builtins) {
    SCOPED_TRACE(name);
    const CliRun run = humandyn_cli(dir, std::string("model --json --model ") + name);
    ASSERT_EQ(run.exit_code, 0) << run.err;
    EXPECT_EQ(run.err, "");
    const ModelDescription<double> parsed = parse_model_json(run.out, "model.json");
    expect_same_description(human_description(params), parsed);

    const AnyModel<double> rebuilt(parsed);
    const HumanModel<double> builtin = human_model<double>(params);
    Data<AnyModel<double>> data_rebuilt(rebuilt);
    Data<HumanModel<double>> data_builtin(builtin);
    humandyn::testing::KdlTreeDynamics kdl(parsed);
    double worst_kdl = 0, worst_builtin = 0;
    for (const auto& s : humandyn::testing::random_states(16, 1000, 2024)) {
      const Eigen::VectorXd tau = rnea(rebuilt, data_rebuilt, s.q, s.qd, s.qdd);
      const Eigen::VectorXd tau_builtin = rnea(builtin, data_builtin, s.q, s.qd, s.qdd);
      worst_builtin =
          std::max(worst_builtin, (tau - tau_builtin).cwiseAbs().maxCoeff() / (1 + tau.cwiseAbs().maxCoeff()));
      worst_kdl = std::max(worst_kdl, (tau - kdl.torques(s)).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(worst_builtin, 1e-12) << "the rebuilt model against the built-in one (relative)";
    EXPECT_LT(worst_kdl, 1e-9) << "the rebuilt model against KDL built from the parsed file (N m)";
  }
}

TEST(CliModel, LoadsItsOwnJsonBackAndPrintsATable) {
  Scratch dir;
  const CliRun first = humandyn_cli(dir, "model --model paper --json");
  ASSERT_EQ(first.exit_code, 0) << first.err;
  // the ending read in any case, as a clip's: PAPER.JSON is a model file (it was an unknown model name)
  for (const std::string file : {"paper.json", "PAPER.JSON"}) {
    write_text(dir / file, first.out);
    const CliRun again = humandyn_cli(dir, "model --model " + file + " --json");
    ASSERT_EQ(again.exit_code, 0) << again.err;
    EXPECT_EQ(again.out, first.out);
  }

  const CliRun table = humandyn_cli(dir, "model --model paper.json");
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("l_shoulder_pitch"), std::string::npos);
  EXPECT_NE(table.out.find("total mass 73.000 kg"), std::string::npos) << table.out;
  const CliRun demo = humandyn_cli(dir, "demo --model PAPER.JSON --out o");
  ASSERT_EQ(demo.exit_code, 0) << demo.err;
  EXPECT_TRUE(fs::exists(dir / "o" / "PAPER_standing.csv"));
  // the ending alone is no file's name
  const CliRun bare = humandyn_cli(dir, "model --model .JSON");
  EXPECT_EQ(bare.exit_code, 2);
  EXPECT_NE(bare.err.find("unknown model '.JSON'"), std::string::npos) << bare.err;
}

// ---- a URDF model ----------------------------------------------------------------------------------

const char* two_joint_urdf = R"(<?xml version="1.0"?>
<robot name="t">
<link name="base"/>
<link name="a"><inertial><mass value="2"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial></link>
<link name="b"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
<joint name="j1" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 1 0"/><limit effort="1" velocity="1"/></joint>
<joint name="j2" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit effort="1" velocity="1"/></joint>
</robot>
)";

// Whatever urdf2dh --json writes, model --model reads back: a map that locks every joint writes nothing
TEST(CliUrdf, AJointMapThatLocksEveryJointWritesNoModel) {
#ifndef HUMANDYN_CLI_READS_URDF
  GTEST_SKIP() << "the command line is built without the URDF importer";
#endif
  Scratch dir;
  write_text(dir / "t.urdf", two_joint_urdf);
  write_text(dir / "empty.map", "");
  write_text(dir / "one.map", "j2\n");
  const CliRun one = humandyn_cli(dir, "urdf2dh t.urdf --joints one.map --json");
  ASSERT_EQ(one.exit_code, 0) << one.err;
  write_text(dir / "one.json", one.out);
  const CliRun back = humandyn_cli(dir, "model --model one.json");
  EXPECT_EQ(back.exit_code, 0) << back.err;
  // (a URDF file's ending is read in any case, as a model file's)
  write_text(dir / "T.Urdf", two_joint_urdf);
  const CliRun urdf = humandyn_cli(dir, "model --model T.Urdf --joints one.map");
  EXPECT_EQ(urdf.exit_code, 0) << urdf.err;
  EXPECT_NE(urdf.out.find("j2"), std::string::npos) << urdf.out;
  const CliRun none = humandyn_cli(dir, "urdf2dh t.urdf --joints empty.map --json");
  EXPECT_EQ(none.exit_code, 1);
  EXPECT_NE(none.err.find("empty.map: the joint map leaves no model joint"), std::string::npos) << none.err;
  EXPECT_EQ(none.out, "");
}

// urdf2dh's table: the name columns widen to the longest name (here 30 characters and a non-ASCII one),
// so that every row's numbers stand under their heading
TEST(CliUrdf, TheDhTableLinesUpUnderLongNames) {
#ifndef HUMANDYN_CLI_READS_URDF
  GTEST_SKIP() << "the command line is built without the URDF importer";
#endif
  Scratch dir;
  std::string urdf = two_joint_urdf;
  const auto rename = [&](const std::string& from, const std::string& to) {
    for (std::size_t at = urdf.find(from); at != std::string::npos; at = urdf.find(from, at + to.size()))
      urdf.replace(at, from.size(), to);
  };
  rename("\"j1\"", "\"right_shoulder_flexion_joint_1\"");
  rename("\"b\"", "\"forearm_\xC3\xA9tendu\"");
  write_text(dir / "t.urdf", urdf);
  const CliRun run = humandyn_cli(dir, "urdf2dh t.urdf");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // the column where "mass" ends in the heading is where every row's mass ends, in characters
  const auto characters = [](const std::string& s) {
    return std::size_t(
        std::count_if(s.begin(), s.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
  };
  std::istringstream lines(run.out);
  std::size_t width = 0, rows = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.find("   #  joint") == 0) width = characters(line);
    if (line.find("   1  ") == 0 || line.find("   2  ") == 0) {
      EXPECT_EQ(characters(line), width) << run.out;
      ++rows;
    }
  }
  EXPECT_GT(width, 0U) << run.out;
  EXPECT_EQ(rows, 2U) << run.out;
  EXPECT_NE(run.out.find("right_shoulder_flexion_joint_1"), std::string::npos) << run.out;
}

// A model name given twice in a joint map: the message names the map and the line
TEST(CliUrdf, AJointMapGivingOneNameTwiceNamesTheMapLine) {
#ifndef HUMANDYN_CLI_READS_URDF
  GTEST_SKIP() << "the command line is built without the URDF importer";
#endif
  Scratch dir;
  write_text(dir / "t.urdf", two_joint_urdf);
  write_text(dir / "dup.map", "j1 x\nj2 x\n");
  const CliRun run = humandyn_cli(dir, "urdf2dh t.urdf --joints dup.map");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("dup.map:2: joint 'j2': model name 'x' is already given to joint 'j1' (line 1)"),
            std::string::npos)
      << run.err;
}

// --fd chooses the explicit integrators' forward dynamics: with the implicit steps, which solve their own
// equations, it is a usage error rather than an option silently ignored
TEST(CliSimulate, FdIsTheExplicitIntegratorsOption) {
  Scratch dir;
  for (const char* integrator : {"implicit", "backward-euler"}) {
    const CliRun run = humandyn_cli(
        dir, std::string("simulate --integrator ") + integrator + " --fd aba --dt 1e-3 --duration 1e-3 --out t.csv");
    EXPECT_EQ(run.exit_code, 2) << integrator;
    EXPECT_NE(run.err.find("--fd chooses the forward dynamics of euler and rk4"), std::string::npos) << run.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "t.csv"));
  }
  const CliRun euler = humandyn_cli(dir, "simulate --integrator euler --fd aba --dt 1e-3 --duration 1e-3 --out t.csv");
  EXPECT_EQ(euler.exit_code, 0) << euler.err;
}

// The summary says what changes the energy besides the integrator's error: the servo, the external forces
// (unless all are zero), a scene's dropped velocity products, and backward Euler's own damping, whose total equals the
// energy the trajectory lost (a passive fall: E(0) - E(end) from the energy column, to the 3 digits printed)
TEST(CliSimulate, SaysWhatChangesTheEnergy) {
  Scratch dir;
  const CliRun fall = humandyn_cli(dir, "simulate --integrator backward-euler --dt 1/30 --duration 2 --out t.csv");
  ASSERT_EQ(fall.exit_code, 0) << fall.err;
  EXPECT_EQ(fall.out.find("drift is not an error here"), std::string::npos) << fall.out;
  const CsvTable t = read_csv((dir / "t.csv").string());
  ASSERT_EQ(t.rows.size(), 61u);
  const auto energy = std::size_t(std::find(t.header.begin(), t.header.end(), "energy") - t.header.begin());
  ASSERT_LT(energy, t.header.size());
  const double lost = t.rows.front()[energy] - t.rows.back()[energy];
  const std::string said = "backward Euler dissipated ";
  const std::size_t at = fall.out.find(said);
  ASSERT_NE(at, std::string::npos) << fall.out;
  std::size_t used = 0;
  const double printed = std::stod(fall.out.substr(at + said.size()), &used);
  EXPECT_NEAR(printed, lost, 5e-3 * lost) << fall.out;
  EXPECT_EQ(fall.out.substr(at + said.size() + used, 9), " J in 2 s") << fall.out;
  EXPECT_NE(fall.out.find("W), its numerical damping"), std::string::npos) << fall.out;
  const CliRun pushed = humandyn_cli(dir, "simulate --integrator euler --wrench l_forearm:0,0,-98.1 --duration 0.01");
  ASSERT_EQ(pushed.exit_code, 0) << pushed.err;
  EXPECT_NE(pushed.out.find("(the external forces do work: drift is not an error here)"), std::string::npos)
      << pushed.out;
  EXPECT_EQ(pushed.out.find("backward Euler"), std::string::npos) << pushed.out;
  // a zero force does no work
  const CliRun zero = humandyn_cli(dir, "simulate --integrator euler --wrench l_forearm:0,0,0 --duration 0.01");
  ASSERT_EQ(zero.exit_code, 0) << zero.err;
  EXPECT_EQ(zero.out.find("drift is not an error here"), std::string::npos) << zero.out;
  // a scene without the velocity products changes the energy too; the full one does not
  const CliRun scene = humandyn_cli(dir, "simulate --integrator euler --scene no_coriolis --duration 0.01");
  ASSERT_EQ(scene.exit_code, 0) << scene.err;
  EXPECT_NE(scene.out.find("(the scene drops the velocity products: drift is not an error here)"), std::string::npos)
      << scene.out;
  const CliRun full = humandyn_cli(dir, "simulate --integrator euler --scene full --duration 0.01");
  ASSERT_EQ(full.exit_code, 0) << full.err;
  EXPECT_EQ(full.out.find("drift is not an error here"), std::string::npos) << full.out;
  // with the trajectory on standard output, the summary goes to stderr: standard output is all CSV
  const CliRun piped = humandyn_cli(dir, "simulate --duration 0.002 --out -");
  ASSERT_EQ(piped.exit_code, 0) << piped.err;
  const CsvTable rows = parse_csv(piped.out, "-");
  EXPECT_EQ(rows.rows.size(), 3u) << piped.out;
  EXPECT_NE(piped.err.find("energy: E(0) = "), std::string::npos) << piped.err;
  EXPECT_NE(piped.err.find(" of m g z_com = "), std::string::npos) << piped.err;
  // so with standard output named as a file (/dev/stdout), a regular file or a pipe, where the summary
  // once followed the rows
  const CliRun named = humandyn_cli(dir, "simulate --duration 0.002 --out /dev/stdout");
  ASSERT_EQ(named.exit_code, 0) << named.err;
  EXPECT_EQ(parse_csv(named.out, "/dev/stdout").rows.size(), 3u) << named.out;
  EXPECT_NE(named.err.find("energy: E(0) = "), std::string::npos) << named.err;
  const int through_pipe = std::system(
      ("cd '" + dir.dir().string() +
       "' && '" HUMANDYN_CLI "' simulate --duration 0.002 --out /dev/stdout 2> pipe_err.txt | cat > pipe.csv")
          .c_str());
  ASSERT_TRUE(WIFEXITED(through_pipe) && WEXITSTATUS(through_pipe) == 0);
  EXPECT_EQ(parse_csv(read_text(dir / "pipe.csv"), "pipe.csv").rows.size(), 3u) << read_text(dir / "pipe.csv");
  EXPECT_NE(read_text(dir / "pipe_err.txt").find("energy: E(0) = "), std::string::npos);
  const std::string in_dir = "cd '" + dir.dir().string() + "' && '" HUMANDYN_CLI "' ";
  // and with standard output on a device (/dev/null here, a terminal alike): the summary is not lost there
  const int to_null =
      std::system((in_dir + "simulate --duration 0.002 --out /dev/stdout > /dev/null 2> null_err.txt").c_str());
  ASSERT_TRUE(WIFEXITED(to_null) && WEXITSTATUS(to_null) == 0);
  EXPECT_NE(read_text(dir / "null_err.txt").find("energy: E(0) = "), std::string::npos);
  // standard error's file (/dev/stderr) is written through it, in turn with the messages: a log appended
  // to keeps its lines, where it was once replaced
  write_text(dir / "run.log", "an earlier line\n");
  const int to_log =
      std::system((in_dir + "simulate --duration 0.002 --out /dev/stderr 2>> run.log > summary.txt").c_str());
  ASSERT_TRUE(WIFEXITED(to_log) && WEXITSTATUS(to_log) == 0);
  const std::string log = read_text(dir / "run.log");
  ASSERT_EQ(log.rfind("an earlier line\n", 0), 0u) << log;
  EXPECT_EQ(parse_csv(log.substr(16), "run.log").rows.size(), 3u) << log;
  EXPECT_NE(read_text(dir / "summary.txt").find("energy: E(0) = "), std::string::npos);
  // and a run that stops there says so beside its partial trajectory
  const int stopped = std::system(
      (in_dir + "simulate --integrator euler --dt 0.05 --duration 10 --out /dev/stderr 2> err.log > /dev/null")
          .c_str());
  ASSERT_TRUE(WIFEXITED(stopped) && WEXITSTATUS(stopped) == 3);
  const std::string err = read_text(dir / "err.log");
  EXPECT_NE(err.find("humandyn simulate: stopped at t = "), std::string::npos) << err;
  EXPECT_NE(err.find("holds the partial trajectory"), std::string::npos) << err;
  EXPECT_NE(err.find("\nt,q_"), std::string::npos) << err;
  // without gravity there is no m g z_com to measure the drift against: said, not printed as a drift of 0
  const CliRun model = humandyn_cli(dir, "model --json");
  ASSERT_EQ(model.exit_code, 0) << model.err;
  json::Json doc = json::parse(model.out, "model.json");
  doc["gravity"] = json::Json::array({0.0, 0.0, 0.0});
  write_text(dir / "weightless.json", json::write(doc));
  const CliRun weightless = humandyn_cli(dir, "simulate --model weightless.json --integrator euler --duration 0.01");
  ASSERT_EQ(weightless.exit_code, 0) << weightless.err;
  EXPECT_NE(weightless.out.find("J (no scale for a relative drift: m g z_com = 0 J)"), std::string::npos)
      << weightless.out;
  EXPECT_EQ(weightless.out.find(" of m g z_com"), std::string::npos) << weightless.out;
}

// A scene holds its locked joints still: what the states say of their motion goes unread, and id and fd
// say so, once per column, naming the first row where it differs
TEST(CliScene, SaysWhichLockedJointColumnsGoUnread) {
  Scratch dir;
  const auto d = human_description(default_parameters());
  const std::vector<std::string> names = joint_names(d);
  const auto index = [&](const std::string& n) {
    return Eigen::Index(std::find(names.begin(), names.end(), n) - names.begin());
  };
  std::vector<Eigen::VectorXd> q(3, Eigen::VectorXd::Zero(16)), qd = q, qdd = q;
  write_text(dir / "still.csv", humandyn::testing::joint_csv(names, {{"q_", q}, {"qd_", qd}, {"qdd_", qdd}}));
  q[1][index("r_knee_pitch")] = 1.2;
  qd[2][index("l_knee_pitch")] = 5;
  write_text(dir / "moved.csv", humandyn::testing::joint_csv(names, {{"q_", q}, {"qd_", qd}, {"qdd_", qdd}}));
  const CliRun still = humandyn_cli(dir, "id --scene upper_body --in still.csv");
  ASSERT_EQ(still.exit_code, 0) << still.err;
  EXPECT_EQ(still.err, "");
  const CliRun moved = humandyn_cli(dir, "id --scene upper_body --in moved.csv");
  ASSERT_EQ(moved.exit_code, 0) << moved.err;
  EXPECT_EQ(moved.out, still.out);  // (unread: the same torques)
  for (const char* part :
       {"humandyn id: warning: moved.csv: line 3: q_r_knee_pitch is 1.2, not used: the scene 'upper_body' holds joint "
        "'r_knee_pitch' still at 0 rad",
        "humandyn id: warning: moved.csv: line 4: qd_l_knee_pitch is 5, not used"})
    EXPECT_NE(moved.err.find(part), std::string::npos) << part << "\n" << moved.err;
}

// A standard error that cannot be written loses the messages, not the run: the warnings above with
// standard error full or closed, and an error so said
TEST(CliScene, AnUnwritableStandardErrorLosesOnlyTheMessages) {
  Scratch dir;
  const auto d = human_description(default_parameters());
  const std::vector<std::string> names = joint_names(d);
  std::vector<Eigen::VectorXd> q(3, Eigen::VectorXd::Zero(16)), qd = q, qdd = q;
  q[1][std::find(names.begin(), names.end(), "r_knee_pitch") - names.begin()] = 1.2;  // held by the scene
  write_text(dir / "moved.csv", humandyn::testing::joint_csv(names, {{"q_", q}, {"qd_", qd}, {"qdd_", qdd}}));
  const CliRun told = humandyn_cli(dir, "id --scene upper_body --in moved.csv --out told.csv");
  ASSERT_EQ(told.exit_code, 0) << told.err;
  ASSERT_NE(told.err.find("warning"), std::string::npos) << told.err;
  const std::string in_dir = "cd '" + dir.dir().string() + "' && '" HUMANDYN_CLI "' ";
  for (const char* to : {"2> /dev/full", "2>&-"}) {
    SCOPED_TRACE(to);
    write_text(dir / "out.csv", "before\n");
    const int run = std::system((in_dir + "id --scene upper_body --in moved.csv --out out.csv " + to).c_str());
    EXPECT_TRUE(WIFEXITED(run) && WEXITSTATUS(run) == 0) << run;
    EXPECT_EQ(read_text(dir / "out.csv"), read_text(dir / "told.csv"));
    const int failed = std::system((in_dir + "id --in nothere.csv " + to).c_str());
    EXPECT_TRUE(WIFEXITED(failed) && WEXITSTATUS(failed) != 0 && WEXITSTATUS(failed) <= 2) << failed;
    // a run that stops says so on stderr before its trajectory is written: with stderr closed, the message
    // does not land in the file, which took its descriptor
    const int stopped =
        std::system((in_dir + "simulate --integrator euler --dt 1/30 --duration 3 --out run.csv " + to).c_str());
    EXPECT_TRUE(WIFEXITED(stopped) && WEXITSTATUS(stopped) == 3) << stopped;
    EXPECT_EQ(read_text(dir / "run.csv").find("humandyn"), std::string::npos);
  }
}

// --up '' is refused as --up Y is; a gravity beyond 1e5 m/s^2 (near 1e155, or one whose magnitude
// overflows) is a usage error of --gravity
TEST(CliUrdf, UpAndGravityAreCheckedAsOptions) {
#ifndef HUMANDYN_CLI_READS_URDF
  GTEST_SKIP() << "the command line is built without the URDF importer";
#endif
  Scratch dir;
  write_text(dir / "t.urdf", two_joint_urdf);
  const CliRun empty = humandyn_cli(dir, "urdf2dh t.urdf --up ''");
  EXPECT_EQ(empty.exit_code, 2);
  EXPECT_NE(empty.err.find("humandyn urdf2dh: --up: unknown up axis ''"), std::string::npos) << empty.err;
  // the six axes the help text lists, no others; what the user typed shown with its invisible characters
  for (const auto& [arguments, message] : std::vector<std::pair<std::string, std::string>>{
           {"--up +z", "--up: unknown up axis '+z' (expected x, y, z, -x, -y or -z)"},
           {"--up 'z\x1b'", "--up: unknown up axis 'z<U+001B>'"},
           {"--root 'base\t'", "t.urdf: no link 'base\\t' to use as the base; the links: base, a, b\n"},
           {"--gravity '0,0,\x1b'", "--gravity needs three finite numbers GX,GY,GZ, got '0,0,<U+001B>'"}}) {
    const CliRun run = humandyn_cli(dir, "urdf2dh t.urdf " + arguments);
    EXPECT_NE(run.exit_code, 0) << arguments;
    EXPECT_NE(run.err.find(message), std::string::npos) << arguments << "\n" << run.err;
  }
  const CliRun large = humandyn_cli(dir, "urdf2dh t.urdf --gravity 0,0,-1e155");
  EXPECT_EQ(large.exit_code, 2) << large.err;
  EXPECT_NE(
      large.err.find("humandyn urdf2dh: --gravity '0,0,-1e155': the vector's magnitude, 1e+155 m/s^2, is beyond 100000 "
                     "m/s^2"),
      std::string::npos)
      << large.err;
  // the magnitude to nine figures, not its last bits (1.7e+308, not 1.7000000000000003e+308), and enough to
  // tell it from the limit (100000.4, not 100000)
  for (const auto& [given, magnitude] :
       std::vector<std::pair<std::string, std::string>>{{"0,0,-1.7e308", "1.7e+308"}, {"0,0,-100000.4", "100000.4"}}) {
    const CliRun over = humandyn_cli(dir, "urdf2dh t.urdf --gravity " + given);
    EXPECT_NE(over.err.find("--gravity '" + given + "': the vector's magnitude, " + magnitude +
                            " m/s^2, is beyond 100000 m/s^2"),
              std::string::npos)
        << over.err;
  }
  EXPECT_EQ(humandyn_cli(dir, "urdf2dh t.urdf --gravity 0,0,-1e5").exit_code, 0);
  const CliRun huge = humandyn_cli(dir, "urdf2dh t.urdf --gravity 1.5e308,1.5e308,0");
  EXPECT_EQ(huge.exit_code, 2);
  EXPECT_NE(huge.err.find("humandyn urdf2dh: --gravity: the vector's magnitude overflows a double"), std::string::npos)
      << huge.err;
  EXPECT_EQ(huge.err.find("t.urdf"), std::string::npos) << huge.err;
}

// ---- humandyn id -----------------------------------------------------------------------------------

TEST(CliId, EqualsTheLibrarysRneaForEveryChoiceOfTerms) {
  Scratch dir;
  const ModelDescription<double> d = human_description(default_parameters());
  const auto states = humandyn::testing::random_states(16, 50, 99);
  write_text(dir / "states.csv", states_csv(joint_names(d), states));
  const AnyModel<double> model(d);
  Data<AnyModel<double>> data(model);
  for (const char* terms : {"full", "no-coriolis", "gravity"}) {
    SCOPED_TRACE(terms);
    const CliRun run = humandyn_cli(dir, std::string("id --terms ") + terms + " --in states.csv --out torques.csv");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const CsvTable out = read_csv((dir / "torques.csv").string());
    std::vector<std::string> header{"t"};
    for (const auto& c : joint_columns(joint_names(d), "tau_")) header.push_back(c);
    ASSERT_EQ(out.header, header);
    ASSERT_EQ(out.rows.size(), states.size());
    for (std::size_t r = 0; r < states.size(); ++r) {
      const auto& s = states[r];
      const std::string t(terms);
      const Eigen::VectorXd tau = t == "full"          ? rnea<Terms::Full>(model, data, s.q, s.qd, s.qdd)
                                  : t == "no-coriolis" ? rnea<Terms::NoCoriolis>(model, data, s.q, s.qd, s.qdd)
                                                       : rnea<Terms::GravityOnly>(model, data, s.q, s.qd, s.qdd);
      EXPECT_EQ(out.rows[r][0], 0.001 * double(r));
      for (int i = 0; i < 16; ++i) ASSERT_EQ(out.rows[r][std::size_t(i) + 1], tau[i]) << "row " << r << " joint " << i;
    }
  }
  // standard output when --out is left out, and the velocity columns are optional for gravity only
  std::string only_q = "q_" + d.joints[0].name;
  for (std::size_t i = 1; i < 16; ++i) only_q += ",q_" + d.joints[i].name;
  std::string zeros = "0";
  for (int i = 1; i < 16; ++i) zeros += ",0";
  write_text(dir / "q.csv", only_q + "\n" + zeros + "\n");
  const CliRun gravity = humandyn_cli(dir, "id --terms gravity --in q.csv");
  ASSERT_EQ(gravity.exit_code, 0) << gravity.err;
  const CsvTable g = parse_csv(gravity.out, "stdout");
  ASSERT_EQ(g.rows.size(), 1u);
  const Eigen::VectorXd tau0 = gravity_torques(model, data, Eigen::VectorXd::Zero(16));
  for (int i = 0; i < 16; ++i) EXPECT_EQ(g.rows[0][std::size_t(i)], tau0[i]);
}

TEST(CliId, BadInputFailsWithFileLineColumnAndWritesNothing) {
  Scratch dir;
  const ModelDescription<double> d = human_description(default_parameters());
  const std::string good = states_csv(joint_names(d), humandyn::testing::random_states(16, 3, 5));
  write_text(dir / "torques.csv", "precious\n");

  struct Case {
    std::string csv, message;
  };
  // a cell spoiled on the third row (line 4): the 5th column is q_r_hip_pitch
  std::string spoiled = good;
  {
    std::size_t line_start = 0;
    for (int k = 0; k < 3; ++k) line_start = spoiled.find('\n', line_start) + 1;
    std::size_t cell = line_start;
    for (int k = 0; k < 4; ++k) cell = spoiled.find(',', cell) + 1;
    spoiled.replace(cell, spoiled.find(',', cell) - cell, "NaN");
  }
  const Case cases[] = {
      {spoiled, "humandyn id: states.csv: line 4, column 5 'q_r_hip_pitch': 'NaN' is not a finite number\n"},
      {good.substr(0, good.rfind(',')) + "\n",
       "humandyn id: states.csv: line 4, column 49 'qdd_l_ankle_pitch': missing cell: the row has 48 cells, the "
       "header 49 columns\n"},
      {"t,q_nobody\n1,2\n",
       "humandyn id: states.csv: line 1, column 2 'q_nobody': unknown column: q_ starts the command's own columns, and "
       "this is none it reads here (a misspelling, or a column to rename to carry it through)\n"},
      {"", "humandyn id: states.csv: line 1: empty file: expected a header row of column names\n"},
  };
  for (const auto& c : cases) {
    write_text(dir / "states.csv", c.csv);
    const CliRun run = humandyn_cli(dir, "id --in states.csv --out torques.csv");
    EXPECT_EQ(run.exit_code, 1) << run.err;
    EXPECT_EQ(run.err, c.message);
    EXPECT_EQ(read_text(dir / "torques.csv"), "precious\n") << "the output file was touched";
    EXPECT_EQ(run.out, "");
  }
  // the velocities are required by the full terms
  std::string q_only = "q_r_ankle_pitch";
  for (std::size_t i = 1; i < 16; ++i) q_only += ",q_" + d.joints[i].name;
  write_text(dir / "states.csv", q_only + "\n");
  const CliRun run = humandyn_cli(dir, "id --in states.csv --out torques.csv");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_EQ(run.err, "humandyn id: states.csv: line 1: missing column 'qd_r_ankle_pitch'\n");
  EXPECT_EQ(read_text(dir / "torques.csv"), "precious\n");
}

// ---- humandyn demo ---------------------------------------------------------------------------------

// The static torque of joint i by hand: minus the moment of the weights of all links beyond it about
// its axis, from forward kinematics.
double torque_from_weights(const AnyModel<double>& model, const Data<AnyModel<double>>& data, int i) {
  const auto& j = model.joint(i);
  const Pose<double> frame = j.parent < 0 ? model.base_pose() : data.oMi[std::size_t(j.parent)];
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  for (int k = 0; k < model.size(); ++k) {
    bool beyond = false;
    for (int a = k; a >= 0; a = model.joint(a).parent) beyond = beyond || a == i;
    if (beyond) moment += (data.com_world[std::size_t(k)] - frame.p).cross(model.joint(k).mass * model.gravity());
  }
  return -frame.R.col(2).dot(moment);
}

TEST(CliDemo, ZeroEntriesAreExactlyZeroAndTheArmPointsForward) {
  Scratch dir;
  const CliRun run = humandyn_cli(dir, "demo --out out");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("Table 2"), std::string::npos);

  const std::pair<const char*, SeedParameters> models[] = {{"paper", paper_parameters()},
                                                           {"default", default_parameters()}};
  for (const auto& [name, params] : models) {
    SCOPED_TRACE(name);
    const AnyModel<double> model(human_description(params));
    Data<AnyModel<double>> data(model);
    for (const char* scenario : {"arm_forward", "standing"}) {
      SCOPED_TRACE(scenario);
      const std::string stem = std::string(name) + "_" + scenario;
      const std::string svg = read_text(dir / "out" / (stem + ".svg"));
      EXPECT_NE(svg.find("<svg"), std::string::npos);
      EXPECT_NE(svg.find("l_shoulder_pitch"), std::string::npos) << "joints labelled";
      const CsvTable t = read_csv((dir / "out" / (stem + ".csv")).string());
      ASSERT_EQ(t.rows.size(), 1u);
      const auto value = [&](const std::string& column) { return t.rows[0][std::size_t(t.require_column(column))]; };

      // the pose the demo used, and its torques against the library and against the weights by hand
      Eigen::VectorXd q(16), tau(16);
      for (int i = 0; i < 16; ++i) {
        q[i] = value("q_" + model.joint_name(i));
        tau[i] = value("tau_" + model.joint_name(i));
      }
      const bool arm = std::string(scenario) == "arm_forward";
      Eigen::VectorXd expected_q = Eigen::VectorXd::Zero(16);
      if (arm) expected_q[6] = -pi / 2;
      EXPECT_EQ(q, expected_q);
      EXPECT_EQ(tau, gravity_torques(model, data, q));
      forward_kinematics(model, data, q);
      for (int i = 0; i < 16; ++i) EXPECT_NEAR(tau[i], torque_from_weights(model, data, i), 1e-12) << i;

      // the paper's zero entries: the waist twist (a vertical axis), the raised arm's roll joint, the
      // free leg's hip roll; and with the arm raised the right arm still hangs: all exactly zero
      EXPECT_EQ(value("tau_waist_yaw"), 0.0);
      EXPECT_EQ(value("tau_l_shoulder_roll"), 0.0);
      EXPECT_EQ(value("tau_l_hip_roll"), 0.0);
      for (const char* hanging : {"tau_r_shoulder_pitch", "tau_r_shoulder_roll", "tau_r_elbow_pitch"})
        EXPECT_EQ(value(hanging), 0.0) << hanging;

      // the left wrist (frame 9) is straight ahead of the shoulder (frame 7) with the arm raised
      const Eigen::Vector3d shoulder = data.oMi[6].p, wrist = data.oMi[8].p;
      if (arm) {
        EXPECT_NEAR(wrist.x() - shoulder.x(), params.a8 + params.a9, 1e-12);
        EXPECT_NEAR(wrist.y(), shoulder.y(), 1e-12);
        EXPECT_NEAR(wrist.z(), shoulder.z(), 1e-12);
        EXPECT_GT(shoulder.y(), 0) << "it is the left arm";
      } else {
        EXPECT_NEAR(shoulder.z() - wrist.z(), params.a8 + params.a9, 1e-12);
      }

      // the stance hip roll (paper: 98.55 standing) carries everything above the right hip at its
      // lateral offset: minus (mass above) g (lever), by hand
      double mass_above = 0, moment_y = 0;
      for (int k = 2; k < 16; ++k) {
        mass_above += model.joint(k).mass;
        moment_y += model.joint(k).mass * data.com_world[std::size_t(k)].y();
      }
      const double hip_y = data.oMi[1].p.y();
      const double lever = moment_y / mass_above - hip_y;
      // axis of joint 3 points backward (-x): the holding torque is -(m g lever)
      EXPECT_NEAR(data.oMi[1].R.col(2).x(), -1.0, 1e-15);
      EXPECT_NEAR(value("tau_r_hip_roll"), -mass_above * 9.81 * lever, 1e-12);
    }
  }
}

TEST(CliDemo, RunsOnOneChosenModelIncludingAJsonFile) {
  Scratch dir;
  const CliRun json = humandyn_cli(dir, "model --json --model female");
  ASSERT_EQ(json.exit_code, 0);
  write_text(dir / "her.json", json.out);
  const CliRun run = humandyn_cli(dir, "demo --model her.json --out o");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(fs::exists(dir / "o" / "her_arm_forward.svg"));
  EXPECT_TRUE(fs::exists(dir / "o" / "her_standing.csv"));
  EXPECT_FALSE(fs::exists(dir / "o" / "paper_standing.csv"));
  // a file name with a byte that is not UTF-8 and a control character: the files take it as it is, the
  // drawings (XML, which could carry neither) and the printed text show it
  write_text(dir / "h\xFF\x01r.json", json.out);
  const CliRun odd = humandyn_cli(dir, "demo --model 'h\xFF\x01r.json' --out odd");
  ASSERT_EQ(odd.exit_code, 0) << odd.err;
  EXPECT_NE(odd.out.find(" odd/h<0xFF><U+0001>r_standing.svg"), std::string::npos) << odd.out;
  const std::string svg = read_text(dir / "odd" / "h\xFF\x01r_standing.svg");
  EXPECT_NE(svg.find(">h&lt;0xFF&gt;&lt;U+0001&gt;r model: "), std::string::npos);
  EXPECT_EQ(svg.find_first_of(std::string("\xFF\x01", 2)), std::string::npos);
}

// ---- bad invocations -------------------------------------------------------------------------------

TEST(Cli, BadInvocationsExitNonZeroWithAClearMessage) {
  Scratch dir;
  write_text(dir / "s.csv", "t\n0\n");
  write_text(dir / "states.csv", states_csv(joint_names(human_description(default_parameters())),
                                            humandyn::testing::random_states(16, 1, 3)));
  std::filesystem::create_directory(dir / "folder.json");
  auto huge = human_description(default_parameters());
  for (int k : {0, 1, 2}) huge.joints[std::size_t(k)].body.mass = 1e308;
  write_text(dir / "huge.json", write_model_json(huge));
  auto other_shape = human_description(default_parameters());
  other_shape.joints.resize(2);  // the right ankle and knee alone
  write_text(dir / "two.json", write_model_json(other_shape));
  struct Case {
    std::string arguments;
    int exit_code;
    std::string message;  // a part of stderr
  };
  const Case cases[] = {
      {"id --in folder.json", 1, "humandyn id: folder.json: is a folder, not a file"},
      {"model --model folder.json", 1, "humandyn model: folder.json: is a folder, not a file"},
      {"demo --model huge.json --out huge", 1,
       "humandyn demo: huge.json: /joints/0: invalid model: joint 1 'r_ankle_pitch' (link 'r_shank'): mass 1e+308 kg "
       "is beyond 1e+09 kg"},
      // a body of another shape where a command needs the seed's: a usage error, as for every command
      {"demo --model two.json --out two", 2,
       "humandyn demo: model 'two' has no joint 'r_hip_roll': the demo needs the seed body's 16 joint names"},
      {"motion export states.csv --model two.json --out two.bvh", 2,
       "humandyn motion export: motion import and export take a body of the seed's shape, which 'two.json' is not"},
      // what cannot be seen is shown in every message
      {"model --model 'default '", 2, "humandyn model: unknown model 'default\u2420'"},
      {"id --in s.csv --wrench 'l_forearm :0,0,1'", 2, "unknown link 'l_forearm\u2420'"},
      {"id --in s.csv --terms 'full\t'", 2, "unknown --terms 'full\\t'"},
      {"id --in s.csv --scene 'upper_body '", 2, "unknown scene 'upper_body\u2420'"},
      {"model '\u200Bx'", 2, "unexpected argument '<U+200B>x'"},
      {"frobnicate", 2, "humandyn: unknown command 'frobnicate'"},
      {"model --jsn", 2, "humandyn model: unknown option --jsn"},
      {"model --model nobody", 2, "humandyn model: unknown model 'nobody'"},
      {"model --model missing.json", 1, "humandyn model: missing.json: cannot open"},
      {"model extra", 2, "humandyn model: unexpected argument 'extra'"},
      {"id --out x.csv", 2, "humandyn id: option --in is required"},
      {"id --inn s.csv", 2, "humandyn id: unknown option --inn"},
      {"motion import --outt x.csv", 2, "humandyn motion import: unknown option --outt"},
      {"motion import clip.bvh --out --cutoff 3", 2, "humandyn motion import: option --out needs a value, and"},
      {"motion import", 2, "humandyn motion import: option --out is required"},
      {"motion", 2, "humandyn motion: a command is needed: import or export"},
      {"motion imprt clip.bvh", 2, "humandyn motion: unknown command 'imprt' (expected import or export)"},
      // a stray argument before the command given is named, even where a required option is missing too
      {"motion foo import clip.bvh --out o.csv", 2, "humandyn motion: unexpected argument 'foo'"},
      {"motion help import", 2, "humandyn motion: unexpected argument 'help'"},
      {"id --in s.csv --terms some", 2, "humandyn id: unknown --terms 'some' (expected full, no-coriolis or gravity)"},
      {"id --in s.csv --out s.csv", 2, "humandyn id: s.csv is given to --in and --out"},
      {"id --in s.csv --out ./s.csv", 2, "humandyn id: ./s.csv is given to --in and --out"},
      {"id --in nowhere.csv", 1, "humandyn id: nowhere.csv: cannot open"},
      {"id --in 'nowhere.csv '", 1, "humandyn id: nowhere.csv\u2420: cannot open"},
      {"id --in s.csv --ground-reaction --sole 0.25,0.1,0.3,0.08", 2,
       "humandyn id: option --sole: the ankle stands 0.3 m ahead of the heel, beyond the 0.25 m sole"},
      {"id --in s.csv --ground-reaction --sole 1e-20,1e-20,0,0.07", 2,
       "humandyn id: option --sole: 1e-20,1e-20,0,0.07 m"},
      {"id --in s.csv --ground-reaction --sole 0.25,0.1,0.1,1e20", 2, "is not a foot's"},
      {"demo --out s.csv", 2, "humandyn demo: --out s.csv is not a folder that can be made"},
      // an option without its value before another option: not taken as its value
      {"simulate --out --duration 0", 2,
       "humandyn simulate: option --out needs a value, and --duration that follows is an option (a value of that "
       "spelling: --out=--duration)"},
      {"simulate --track --duration 0.002", 2, "option --track needs a value, and --duration that follows"},
      {"model --urdf --json", 2, "option --urdf needs a value, and --json that follows"},
      {"motion import clip.bvh --out --cmu", 2, "option --out needs a value, and --cmu that follows"},
      {"simulate --duration 9e-13", 2, "humandyn simulate: --duration 9e-13 s is shorter than one --dt 0.001 s step"},
      {"simulate --dt 1e7 --duration 0.002", 2, "s is shorter than one --dt"},
      {"simulate --duration 0.0006", 2, "humandyn simulate: --duration 0.0006 s is shorter than one --dt 0.001 s step"},
      {"bench --quick --csv -", 2, "humandyn bench: --csv -: the CSV files go to a folder, not to standard output"},
      // the usage first, then the landmark map read
      {"motion import s.csv --out o.csv --map nosuch.map --cutoff -1", 2, "--cutoff must be 0 (no filter) or positive"},
      {"simulate --dt '0.001\t\x1b[31mX'", 2, "got '0.001\\t<U+001B>[31mX'"},
      {"id --in states.csv --ground-reaction --moment-about '0,0,\x1b'", 2, "got '0,0,<U+001B>'"},
      {"bench --characters ' 5'", 2, "humandyn bench: option --characters needs a whole number, got '\u24205'"},
      {"motion import s.csv --out o.csv --mass 1e-310", 2, "--mass must be from 0.001 to 10000 kg, got 1e-310"},
      {"id --in s.csv --in s.csv", 2, "humandyn id: option --in given more than once"},
      {"model --json --json", 2, "humandyn model: option --json given more than once"},
      {"simulate --duration 0 --wrench 'l_forearm:0,0,-98.1 '", 2,
       "humandyn simulate: --wrench 'l_forearm:0,0,-98.1\u2420': the force '0,0,-98.1\u2420' must be three finite "
       "numbers X,Y,Z"},
      {"id --in", 2, "humandyn id: --in"},
      {"simulate --duration nan", 2,
       "humandyn simulate: option --duration needs a finite decimal number (e.g. 0.5, 2, 1e-3), got 'nan'"},
      {"simulate --dt 0.3 --duration 1", 2,
       "humandyn simulate: --duration 1 s is not a whole number of --dt 0.3 s steps (3.33333)"},
      {"simulate --dt 0.5 --duration 0.01", 2,
       "humandyn simulate: --duration 0.01 s is shorter than one --dt 0.5 s step"},
      {"simulate --kp 0x10", 2,
       "humandyn simulate: option --kp needs a finite decimal number (e.g. 0.5, 2, 1e-3), got '0x10'"},
      {"simulate --kp ' 5'", 2,
       "humandyn simulate: option --kp needs a finite decimal number (e.g. 0.5, 2, 1e-3), got '\u24205'"},
      {"simulate --duration 0 --scene upper_body --lock r_knee_pitch=0x10", 2,
       "humandyn simulate: --lock: the angle of joint 'r_knee_pitch': '0x10' is not a number"},
      // a number out of a double's range says so, as a cell does
      {"simulate --duration 0 --scene upper_body --lock r_knee_pitch=1e-400", 2,
       "humandyn simulate: --lock: the angle of joint 'r_knee_pitch': '1e-400' is out of the range of a double: too "
       "small, it would read as 0"},
      {"simulate --duration 0 --wrench 'l_forearm:0,0,-1e400'", 2,
       "the force '0,0,-1e400' must be three finite numbers X,Y,Z: '-1e400' is out of the range of a double: too "
       "large"},
      {"simulate --duration 0 --wrench 'l_forearm:0,0'", 2,
       "the force '0,0' must be three finite numbers X,Y,Z: 2 of the 3 numbers it needs"},
      {"id --in s.csv --ground-reaction --mu 1e-999", 2,
       "option --mu needs a finite decimal number (e.g. 0.5, 2, 1e-3), got '1e-999': '1e-999' is out of the range of "
       "a double: too small, it would read as 0"},
      {"simulate --duration 0 --gravity 0,0,9.81,1", 2, "got '0,0,9.81,1': more than the 3 numbers it needs"},
      {"simulate --duration 0 --gravity 0,,9.81", 2, "got '0,,9.81': an empty value, expected a number"},
      {"simulate --dt 1/1e-400", 2,
       "option --dt needs a positive number of seconds or 1/N, got '1/1e-400': '1e-400' is out of the range of a "
       "double: too small, it would read as 0"},
      {"simulate --duration 0 --scene upper_body --lock 'r_knee_pitch =1'", 2, "has no joint 'r_knee_pitch\u2420'"},
      {"simulate --kp 1e400", 2,
       "humandyn simulate: option --kp needs a finite decimal number (e.g. 0.5, 2, 1e-3), got '1e400'"},
      {"simulate --duration 2/3", 2,
       "humandyn simulate: option --duration needs a finite decimal number (e.g. 0.5, 2, 1e-3), got '2/3'"},
      {"simulate --dt 1/0", 2, "humandyn simulate: option --dt needs a positive number of seconds or 1/N, got '1/0'"},
      {"bench --characters 010x", 2, "humandyn bench: option --characters needs a whole number, got '010x'"},
      {"bench --quick --model paper", 1, "at the home pose: the mass matrix is singular at joint 'r_hip_pitch'"},
      {"bench --quick --seconds 1", 2, "--quick does not go with --seconds"},
      {"bench --quick --json -", 2, "humandyn bench: --json -: standard output holds the tables; give the JSON a file"},
      {"bench --quick --json /dev/stdout", 2,
       "humandyn bench: --json /dev/stdout: standard output holds the tables; give the JSON a file"},
      {"fd --in s.csv --method euler", 2,
       "humandyn fd: unknown --method 'euler' (expected mass-matrix or articulated)"},
      {"id --in s.csv --lock r_knee_pitch=1", 2, "humandyn id: --lock requires --scene"},
      {"id --in s.csv --scene full --terms full", 2, "humandyn id: --scene does not go with --terms"},
      {"simulate --kd 5", 2, "humandyn simulate: --kd requires --track"},
      {"simulate --track s.csv --kp 1e300", 2, "humandyn simulate: --kp must be from 0 to 1e12 N m/rad, got 1e+300"},
      {"simulate --track s.csv --kd 2e12", 2, "humandyn simulate: --kd must be from 0 to 1e12 N m s/rad, got 2e+12"},
      {"id --in s.csv --ground-reaction --mu -1", 2,
       "humandyn id: option --mu needs a friction coefficient >= 0, got -1"},
      {"motion import s.csv --out o.csv --threads -1", 2,
       "humandyn motion import: --threads must be 0 (every core it may run on) or positive, got -1"},
      {"view s.csv --plot '' --out p.html", 2, "humandyn view: --plot is given an empty value"},
      {"view s.csv --plot r_knee_pitch, --out p.html", 2,
       "humandyn view: --plot: an empty joint name in 'r_knee_pitch,'"},
      {"view s.csv --plot r_knee_pitch,l_knee_pitch,r_knee_pitch --out p.html", 2,
       "humandyn view: --plot: joint 'r_knee_pitch' given twice in 'r_knee_pitch,l_knee_pitch,r_knee_pitch'"},
      {"id --in s.csv --scene upper_body --lock ''", 2, "humandyn id: --lock needs JOINT=ANGLE,..., got ''"},
      {"simulate --duration 0 --scene upper_body --lock r_knee_pitch=1,", 2,
       "humandyn simulate: --lock: an empty JOINT=ANGLE item in 'r_knee_pitch=1,'"},
      {"simulate --duration 0 --scene upper_body --lock ,r_knee_pitch=1", 2,
       "humandyn simulate: --lock: an empty JOINT=ANGLE item in ',r_knee_pitch=1'"},
  };
  for (const auto& c : cases) {
    const CliRun run = humandyn_cli(dir, c.arguments);
    EXPECT_EQ(run.exit_code, c.exit_code) << c.arguments << "\n" << run.err;
    EXPECT_NE(run.err.find(c.message), std::string::npos) << c.arguments << "\n" << run.err;
  }
  // a model file that parses but is not physical: the library's validation names the link
  auto d = human_description(default_parameters());
  d.joints[7].body.mass = -1;
  write_text(dir / "bad.json", write_model_json(d));
  const CliRun run = humandyn_cli(dir, "model --model bad.json");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("invalid model: joint 8 'l_shoulder_roll' (link 'l_upper_arm'): negative mass"),
            std::string::npos)
      << run.err;
  // every command answers --help, and `help COMMAND` says the same
  for (const char* command : {"model", "id", "demo"}) {
    const CliRun help = humandyn_cli(dir, std::string(command) + " --help");
    EXPECT_EQ(help.exit_code, 0);
    EXPECT_EQ(help.out.rfind(std::string("usage: humandyn ") + command, 0), 0u) << help.out;
    const CliRun asked = humandyn_cli(dir, std::string("help ") + command);
    EXPECT_EQ(asked.exit_code, 0);
    EXPECT_EQ(asked.out, help.out);
  }
  EXPECT_EQ(humandyn_cli(dir, "help").out.rfind("usage: humandyn <command>", 0), 0u);
  for (const char* about_help : {"help help", "help --help"})  // (help is no command: the overview)
    EXPECT_EQ(humandyn_cli(dir, about_help).out, humandyn_cli(dir, "help").out) << about_help;
  const CliRun unknown = humandyn_cli(dir, "help frobnicate");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("humandyn help: unknown command 'frobnicate'"), std::string::npos) << unknown.err;
  const CliRun two = humandyn_cli(dir, "help id fd");
  EXPECT_EQ(two.exit_code, 2);
  EXPECT_NE(two.err.find("humandyn help: 'id' has no subcommand 'fd'"), std::string::npos) << two.err;
  const CliRun nested = humandyn_cli(dir, "help motion import");
  EXPECT_EQ(nested.exit_code, 0);
  EXPECT_EQ(nested.out, humandyn_cli(dir, "motion import --help").out);
  EXPECT_NE(nested.out.find("--cutoff"), std::string::npos) << nested.out;
}

}  // namespace

}  // namespace test_cli
