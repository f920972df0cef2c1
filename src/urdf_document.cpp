#include "urdf_document.hpp"

#include "humandyn/urdf.hpp"
#include "text/decimal.hpp"
#include "text/names.hpp"
#include "text/shown.hpp"

#include <console_bridge/console.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <sstream>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

namespace humandyn::urdf::detail {

const char* type_name(JointType t) {
  switch (t) {
    case JointType::Revolute:
      return "revolute";
    case JointType::Continuous:
      return "continuous";
    case JointType::Prismatic:
      return "prismatic";
    case JointType::Fixed:
      return "fixed";
    case JointType::Floating:
      return "floating";
    case JointType::Planar:
      return "planar";
  }
  return "unknown";
}

std::string UrdfDocument::where_joint(int j) const {
  const auto& x = joints[std::size_t(j)];
  return source + ":" + std::to_string(x.line) + ": joint '" + text::shown(x.name) + "'";
}

std::string UrdfDocument::where_link(int l) const {
  const auto& x = links[std::size_t(l)];
  return source + ":" + std::to_string(x.line) + ": link '" + text::shown(x.name) + "'";
}

int UrdfDocument::find_link(const std::string& link_name) const {
  for (std::size_t i = 0; i < links.size(); ++i)
    if (links[i].name == link_name) return int(i);
  return -1;
}

int UrdfDocument::find_joint(const std::string& joint_name) const {
  for (std::size_t i = 0; i < joints.size(); ++i)
    if (joints[i].name == joint_name) return int(i);
  return -1;
}

namespace {

[[noreturn]] void fail(const std::string& message) { throw Error(message); }

// "source:line: <element> 'name'" for an element being read
std::string at(const std::string& source, const tinyxml2::XMLElement* e, const std::string& what) {
  return source + ":" + std::to_string(e->GetLineNum()) + ": " + what;
}

// The numbers of attribute `attr` (n of them), each decimal and finite; a missing attribute is left to
// the caller. As urdfdom reads them: one number alone, without blanks around it; three separated by spaces.
void check_numbers(const std::string& source, const tinyxml2::XMLElement* e, const char* attr, int n,
                   const std::string& who) {
  const char* text = e->Attribute(attr);
  if (!text) return;
  const std::string value = text;
  std::istringstream in{value};
  std::string token;
  int count = 0;
  const std::string where = at(source, e, who + ": <" + e->Name() + " " + attr + "=\"" + text::shown(value) + "\">");
  while (in >> token) {
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end != token.c_str() && *end == '\0' && !std::isfinite(v))
      fail(where + ": '" + text::shown(token) + "' is not a finite number");
    if (!text::is_decimal(token)) fail(where + ": '" + text::shown(token) + "' is not a number");
    if (double read = 0; text::read_double(token, read) == std::errc::result_out_of_range)
      fail(where + ": '" + token + "'" + text::out_of_range(token));
    ++count;
  }
  if (count != n)
    fail(where + ": expected " + std::to_string(n) + (n == 1 ? " number" : " numbers") + ", found " +
         std::to_string(count));
  if (n == 1 && value != token) fail(where + ": blanks around the number (write " + attr + "=\"" + token + "\")");
  if (n > 1 && value.find_first_of("\t\n\r\f\v") != std::string::npos)
    fail(where + ": the numbers must be separated by spaces only");
}

// At most one <tag> in `e`: urdfdom would read the first and ignore the others.
void check_single(const std::string& source, const tinyxml2::XMLElement* e, const char* tag, const std::string& who) {
  const auto* first = e->FirstChildElement(tag);
  if (!first) return;
  if (const auto* second = first->NextSiblingElement(tag))
    fail(at(source, second,
            who + ": a second <" + tag + "> in <" + e->Name() + "> (the first is on line " +
                std::to_string(first->GetLineNum()) + "); URDF allows one"));
}

// Names URDF does not give, in an element the dynamics read. urdfdom passes over any child element or
// attribute it does not know, so a misspelt one (<Inertial>, <orgin>, xzy="...") would silently leave
// its numbers out. Refused: a name that is one of the expected ones in another case or within an edit
// or two (one for names of three letters), or one of URDF's names for an element that goes elsewhere
// (`misplaced`: an <origin> or an <inertia> straight in a <link>); any unexpected child element where
// `strict_children` (<inertial>) and any unexpected attribute where `strict_attributes` (the elements
// whose attributes are their numbers: <origin>, <mass>, <inertia>, <axis>). Other names are extensions
// (<gazebo>, <contact>, drake:..., <inertial name="...">) and pass unread.
std::u32string code_points(const std::string& s) {  // UTF-8, lower-cased where ASCII; a stray byte as itself
  std::u32string out;
  for (std::size_t i = 0; i < s.size();) {
    const auto b = static_cast<unsigned char>(s[i]);
    const std::size_t n = b >= 0xF0 ? 4 : b >= 0xE0 ? 3 : b >= 0xC0 ? 2 : 1;
    char32_t c = n == 1 ? b : b & (0x3F >> (n - 1));
    std::size_t k = 1;
    for (; k < n && i + k < s.size() && (static_cast<unsigned char>(s[i + k]) & 0xC0) == 0x80; ++k)
      c = (c << 6) | (static_cast<unsigned char>(s[i + k]) & 0x3F);
    if (k < n) c = b;  // (a sequence cut short)
    out += c < 0x80 ? char32_t(std::tolower(int(c))) : c;
    i += k < n ? 1 : n;
  }
  return out;
}

// The optimal string alignment distance: insertions, deletions, substitutions and swaps of neighbours.
std::size_t edit_distance(const std::u32string& a, const std::u32string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

// The expected name `name` is a misspelling of (or, in another case, is), or nullptr.
const char* misspelt(const std::string& name, std::initializer_list<const char*> expected) {
  if (name.size() > 40) return nullptr;  // (no name this long is a misspelling of a URDF one)
  const std::u32string n = code_points(name);
  for (const char* e : expected) {
    const std::u32string x = code_points(e);
    if (edit_distance(n, x) <= (x.size() <= 3 ? 1U : 2U)) return e;
  }
  return nullptr;
}

std::string listed(std::initializer_list<const char*> names) {
  std::string out;
  std::size_t k = 0;
  for (const char* n : names) out += (k++ == 0 ? "" : k == names.size() ? " or " : ", ") + std::string(n);
  return out;
}

void check_names(const std::string& source, const tinyxml2::XMLElement* e, const std::string& who,
                 std::initializer_list<const char*> children, std::initializer_list<const char*> attributes,
                 bool strict_children, bool strict_attributes, std::initializer_list<const char*> misplaced = {}) {
  const auto is = [](const char* name, std::initializer_list<const char*> names) {
    return std::any_of(names.begin(), names.end(), [&](const char* n) { return std::string(n) == name; });
  };
  const std::string in = "<" + std::string(e->Name()) + ">";
  const auto urdfs = [](std::initializer_list<const char*> names) {
    return names.size() ? " (URDF's are " + listed(names) + ")" : std::string(" (URDF gives it none)");
  };
  for (const auto* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    const std::string name = c->Name();
    if (is(name.c_str(), children)) continue;
    const char* near = misspelt(name, children);
    const char* elsewhere = near ? nullptr : misspelt(name, misplaced);
    if (near || elsewhere || strict_children)
      fail(at(source, c,
              who + ": <" + text::shown(name) + "> is not an element of " + in +
                  (near ? std::string(": is it <") + near + ">?"
                   : elsewhere
                       ? (name == elsewhere ? std::string(": URDF puts it elsewhere")
                                            : std::string(": is it <") + elsewhere + ">, which URDF puts elsewhere?")
                       : std::string()) +
                  urdfs(children)));
  }
  for (const auto* a = e->FirstAttribute(); a; a = a->Next()) {
    const std::string name = a->Name();
    if (is(name.c_str(), attributes) || name.starts_with("xmlns")) continue;
    const char* near = misspelt(name, attributes);
    if (near || strict_attributes)
      fail(at(source, e,
              who + ": " + in + " has an attribute " + text::shown(name) + " that URDF does not give it" +
                  (near ? std::string(": is it ") + near + "?" : std::string()) + urdfs(attributes)));
  }
}

// An unexpanded xacro file: elements of xacro's namespace anywhere (the prefix "xacro:", or the one a
// robot attribute xmlns:P="http://www.ros.org/wiki/xacro" declares), which urdfdom would pass over with
// the links and joints inside them.
void check_not_xacro(const std::string& source, const tinyxml2::XMLElement* robot) {
  std::vector<std::string> prefixes{"xacro:"};
  for (const auto* a = robot->FirstAttribute(); a; a = a->Next())
    if (std::string_view name = a->Name();
        name.starts_with("xmlns:") && std::string_view(a->Value()).find("wiki/xacro") != std::string_view::npos)
      prefixes.push_back(std::string(name.substr(6)) + ":");
  std::vector<const tinyxml2::XMLElement*> stack{robot};  // depth first, in the document's order
  while (!stack.empty()) {
    const auto* e = stack.back();
    stack.pop_back();
    const std::string name = e->Name();
    for (const auto& p : prefixes)
      if (name.starts_with(p))
        fail(at(source, e,
                "<" + text::shown(name) +
                    ">: a xacro file, which needs expanding into URDF first (`xacro FILE.xacro > "
                    "FILE.urdf`)"));
    for (const auto* c = e->LastChildElement(); c; c = c->PreviousSiblingElement()) stack.push_back(c);
  }
}

// The largest coordinate of an origin, in metres, and the largest angle of its rpy, in radians: the DH
// construction's absolute tolerances (1e-9 m, 1e-9 rad) would drown in the round-off of larger ones.
constexpr double kMaxOffset = 1e6;
constexpr double kMaxAngle = 1e6;

// An attribute the element must have, as urdfdom requires it.
void check_required(const std::string& source, const tinyxml2::XMLElement* e, const char* attr,
                    const std::string& who) {
  if (!e->Attribute(attr)) fail(at(source, e, who + ": <" + e->Name() + "> has no " + attr + " attribute"));
}

// An <origin> (at most one) in `parent`: its numbers and, when `bounded`, its coordinates within kMaxOffset
// and its angles within kMaxAngle.
void check_origin_numbers(const std::string& source, const tinyxml2::XMLElement* parent, const std::string& who,
                          bool bounded) {
  check_single(source, parent, "origin", who);
  const auto* o = parent->FirstChildElement("origin");
  if (!o) return;
  for (const auto& [attr, bound, unit] : {std::tuple{"xyz", kMaxOffset, " m"}, std::tuple{"rpy", kMaxAngle, " rad"}}) {
    check_numbers(source, o, attr, 3, who);
    const char* text = o->Attribute(attr);
    if (!bounded || !text) continue;
    std::istringstream in{std::string(text)};
    for (double v = 0; in >> v;)
      if (std::abs(v) > bound)
        fail(at(source, o,
                who + ": <origin " + attr + "=\"" + text::shown(text) + "\">: the " +
                    (attr == std::string("xyz") ? "coordinate " : "angle ") + exact_number(v) + unit +
                    " is out of range (at most " + exact_number(bound) + unit + " in size)"));
  }
}

// The origin of a joint or of an inertial, which the dynamics read.
void check_origin(const std::string& source, const tinyxml2::XMLElement* parent, const std::string& who) {
  check_origin_numbers(source, parent, who, true);
  if (const auto* o = parent->FirstChildElement("origin")) check_names(source, o, who, {}, {"xyz", "rpy"}, true, true);
}

// A <material> (urdfdom's rules): a name attribute, a color's rgba four numbers in [0, 1]; one the robot
// defines at its top level gives a color or a texture file, where one in a visual may only name it.
void check_material(const std::string& source, const tinyxml2::XMLElement* m, const std::string& who, bool top_level) {
  check_required(source, m, "name", who);
  check_single(source, m, "color", who);
  check_single(source, m, "texture", who);
  const auto* c = m->FirstChildElement("color");
  if (c && c->Attribute("rgba")) {
    check_numbers(source, c, "rgba", 4, who);
    std::istringstream in{std::string(c->Attribute("rgba"))};
    for (double v = 0; in >> v;)
      if (v < 0 || v > 1)
        fail(at(source, c,
                who + ": <color rgba=\"" + text::shown(c->Attribute("rgba")) + "\">: the component " + exact_number(v) +
                    " is outside [0, 1]"));
  }
  const auto* t = m->FirstChildElement("texture");
  if (top_level && !(c && c->Attribute("rgba")) && !(t && t->Attribute("filename")))
    fail(at(source, m, who + ": defines neither a <color rgba=\"...\"> nor a <texture filename=\"...\">"));
}

// A <visual> or <collision>: no dynamics reads it, but urdfdom refuses the whole file for a fault in
// it, so its faults are named here with their line: the origin's numbers, one <geometry> whose first
// element is a known shape with its sizes (non-negative) and no second shape after it, and a visual's
// material (urdfdom reads none in a collision).
void check_shape(const std::string& source, const tinyxml2::XMLElement* e, const std::string& who) {
  check_origin_numbers(source, e, who, false);
  check_single(source, e, "geometry", who);
  const bool visual = std::string(e->Name()) == "visual";
  if (visual) check_single(source, e, "material", who);
  if (const auto* m = e->FirstChildElement("material"); visual && m) check_material(source, m, who, false);
  const auto* g = e->FirstChildElement("geometry");
  if (!g) fail(at(source, e, who + ": <" + e->Name() + "> has no <geometry>"));
  const std::string shapes = "box, cylinder, sphere or mesh";
  const auto is_shape = [](const std::string& name) {
    return name == "box" || name == "cylinder" || name == "sphere" || name == "mesh";
  };
  const auto* shape = g->FirstChildElement();
  if (!shape) fail(at(source, g, who + ": <geometry> holds no shape (" + shapes + ")"));
  const std::string kind = shape->Name();
  if (!is_shape(kind))
    fail(at(source, shape, who + ": unknown shape <" + text::shown(kind) + "> in <geometry> (" + shapes + ")"));
  for (const auto* x = shape->NextSiblingElement(); x; x = x->NextSiblingElement())
    if (is_shape(x->Name()))
      fail(at(source, x,
              who + ": a second shape <" + x->Name() + "> in <geometry> (the first, <" + text::shown(kind) +
                  ">, is on line " + std::to_string(shape->GetLineNum()) + "); URDF allows one"));
  const auto sizes = [&](std::initializer_list<std::pair<const char*, int>> attrs) {
    for (const auto& [attr, n] : attrs) {
      check_required(source, shape, attr, who);
      check_numbers(source, shape, attr, n, who);
      std::istringstream in{std::string(shape->Attribute(attr))};
      for (double v = 0; in >> v;)
        if (v < 0)
          fail(at(
              source, shape,
              who + ": <" + kind + " " + attr + "=\"" + text::shown(shape->Attribute(attr)) + "\">: a negative size"));
    }
  };
  if (kind == "box") {
    sizes({{"size", 3}});
  } else if (kind == "cylinder") {
    sizes({{"radius", 1}, {"length", 1}});
  } else if (kind == "sphere") {
    sizes({{"radius", 1}});
  } else {
    check_required(source, shape, "filename", who);
    check_numbers(source, shape, "scale", 3, who);
  }
}

// An <inertial> as URDF writes it: <mass value="..."/> and <inertia .../> with all six attributes,
// every number readable. urdfdom keeps a link whose inertial it cannot read, with zeros; here each
// gap is an error naming its line.
void check_inertial(const std::string& source, const tinyxml2::XMLElement* in, const std::string& who) {
  check_names(source, in, who, {"origin", "mass", "inertia"}, {}, true, false);
  check_origin(source, in, who);
  check_single(source, in, "mass", who);
  check_single(source, in, "inertia", who);
  const auto* m = in->FirstChildElement("mass");
  if (!m) fail(at(source, in, who + ": <inertial> has no <mass value=\"...\"/>"));
  check_names(source, m, who, {}, {"value"}, true, true);
  if (!m->Attribute("value")) {
    const char* text = m->GetText();
    fail(at(source, m,
            who + ": <mass> has no value attribute" +
                (text ? std::string(" (its text '") + text::shown(text) + "' is not read: write <mass value=\"" +
                            text::shown(text) + "\"/>)"
                      : std::string())));
  }
  check_numbers(source, m, "value", 1, who);
  if (m->DoubleAttribute("value", 0) < 0) fail(at(source, m, who + ": negative mass " + m->Attribute("value") + " kg"));
  const auto* I = in->FirstChildElement("inertia");
  if (!I)
    fail(at(
        source, in,
        who +
            ": <inertial> has no <inertia ixx=\"...\" ixy=\"...\" ixz=\"...\" iyy=\"...\" iyz=\"...\" izz=\"...\"/>"));
  check_names(source, I, who, {}, {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"}, true, true);
  std::string missing;
  for (const char* a : {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"})
    if (!I->Attribute(a)) missing += (missing.empty() ? "" : ", ") + std::string(a);
  if (!missing.empty())
    fail(at(source, I,
            who + ": <inertia> lacks " + missing +
                " (URDF gives all six of ixx, ixy, ixz, iyy, iyz, izz; write 0 for a zero product of inertia)"));
  for (const char* a : {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"}) check_numbers(source, I, a, 1, who);
}

// A joint's <limit>, <dynamics>, <mimic>, <calibration> and <safety_controller> as urdfdom requires them.
void check_joint_parts(const std::string& source, const tinyxml2::XMLElement* e, const std::string& type,
                       const std::string& who) {
  const auto* limit = e->FirstChildElement("limit");
  if (!limit && (type == "revolute" || type == "prismatic"))
    fail(at(
        source, e,
        who + ": a " + type + " joint needs <limit effort=\"...\" velocity=\"...\"/> (lower and upper default to 0)"));
  const auto numbers = [&](const tinyxml2::XMLElement* x, std::initializer_list<const char*> attrs) {
    for (const char* a : attrs) check_numbers(source, x, a, 1, who);
  };
  const auto required = [&](const tinyxml2::XMLElement* x, const char* attr) { check_required(source, x, attr, who); };
  if (limit) {
    check_names(source, limit, who, {}, {"lower", "upper", "effort", "velocity"}, false, false);
    numbers(limit, {"lower", "upper", "effort", "velocity"});
    required(limit, "effort");
    required(limit, "velocity");
  }
  if (const auto* d = e->FirstChildElement("dynamics")) {
    check_names(source, d, who, {}, {"damping", "friction"}, false, false);
    numbers(d, {"damping", "friction"});
    if (!d->Attribute("damping") && !d->Attribute("friction"))
      fail(at(source, d, who + ": <dynamics> has neither damping nor friction"));
  }
  if (const auto* m = e->FirstChildElement("mimic")) {
    check_names(source, m, who, {}, {"joint", "multiplier", "offset"}, false, false);
    numbers(m, {"multiplier", "offset"});
    required(m, "joint");
  }
  if (const auto* c = e->FirstChildElement("calibration")) {
    check_names(source, c, who, {}, {"rising", "falling", "reference_position"}, false, false);
    numbers(c, {"rising", "falling"});
  }
  if (const auto* s = e->FirstChildElement("safety_controller")) {
    check_names(source, s, who, {}, {"soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"}, false, false);
    numbers(s, {"soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"});
    required(s, "k_velocity");
  }
}

// Structure and numbers from the XML itself: every message names its line.
struct Outline {
  std::string robot;
  std::vector<std::pair<std::string, int>> links;  // name, line
  struct Joint {
    std::string name, parent, child;
    int line = 0;
    bool mimic = false;
  };
  std::vector<Joint> joints;
};

// XML's end-of-line handling (XML 1.0, §2.11): CR LF and a lone CR read as LF, so that lines are
// counted as an editor shows them whichever ending the file uses.
std::string with_lf_line_ends(const std::string& xml) {
  std::string out;
  out.reserve(xml.size());
  for (std::size_t i = 0; i < xml.size(); ++i) {
    if (xml[i] != '\r') {
      out += xml[i];
    } else if (i + 1 == xml.size() || xml[i + 1] != '\n') {
      out += '\n';
    }
  }
  return out;
}

// The <robot> element as urdfdom reads it: a name, and a version, when given, of the form x.y and 1.0.
void check_robot(const std::string& source, const tinyxml2::XMLElement* robot) {
  if (!robot->Attribute("name")) fail(at(source, robot, "<robot> has no name attribute"));
  const char* version = robot->Attribute("version");
  if (!version) return;
  unsigned major = 0, minor = 0;
  char rest = 0;
  if (std::sscanf(version, "%u.%u%c", &major, &minor, &rest) != 2 || major != 1 || minor != 0)
    fail(at(source, robot,
            "<robot version=\"" + text::shown(version) + "\">: URDF's version is 1.0 (written x.y), the one read"));
}

// What the XML reader (tinyxml2, urdfdom's too) could not read, in words, its own name for it after.
std::string xml_fault(const tinyxml2::XMLDocument& doc) {
  const char* what = "the text cannot be read as XML";
  switch (doc.ErrorID()) {
    case tinyxml2::XML_ERROR_PARSING_ELEMENT:
      what = "an element's tag cannot be read";
      break;
    case tinyxml2::XML_ERROR_PARSING_ATTRIBUTE:
      what = "an attribute cannot be read (name=\"value\")";
      break;
    case tinyxml2::XML_ERROR_PARSING_TEXT:
      what = "text between tags cannot be read";
      break;
    case tinyxml2::XML_ERROR_PARSING_CDATA:
      what = "a <![CDATA[ section is not closed by ]]>";
      break;
    case tinyxml2::XML_ERROR_PARSING_COMMENT:
      what = "a comment is not closed by -->";
      break;
    case tinyxml2::XML_ERROR_PARSING_DECLARATION:
      what =
          "a <?...?> declaration or processing instruction stands after the document's start, or is not "
          "closed by ?> (the XML reader takes one only before the first element)";
      break;
    case tinyxml2::XML_ERROR_PARSING_UNKNOWN:
      what = "a <!...> construct is not closed by >";
      break;
    case tinyxml2::XML_ERROR_EMPTY_DOCUMENT:
      what = "there is no element";
      break;
    case tinyxml2::XML_ERROR_MISMATCHED_ELEMENT:
      what = "the element opened on this line is closed by an end tag of another name";
      break;
    case tinyxml2::XML_ELEMENT_DEPTH_EXCEEDED:
      what = "elements are nested too deep";
      break;
    default:
      break;
  }
  return std::string(what) + " (" + doc.ErrorName() + ")";
}

// XML's characters (XML 1.0, production 2): the XML reader takes control characters and character
// references such as &#0; (which cuts a name short) that XML does not; refused with their line.
bool xml_char(unsigned long c) {
  return c == 0x9 || c == 0xA || c == 0xD || (c >= 0x20 && c <= 0xD7FF) || (c >= 0xE000 && c <= 0xFFFD) ||
         (c >= 0x10000 && c <= 0x10FFFF);
}

void check_characters(const std::string& xml, const std::string& source) {
  int line = 1;
  std::string_view until;  // the end of the comment, CDATA section, instruction or declaration the scan is in
  bool in_tag = false;     // within an element's tag, where attribute values stand
  char quote = 0;          // the quote of the attribute value the scan is in
  const auto at = [&] { return source + ":" + std::to_string(line) + ": not XML: "; };
  for (std::size_t i = 0; i < xml.size(); ++i) {
    const char ch = xml[i];
    const auto b = static_cast<unsigned char>(ch);
    if (b == '\n') ++line;
    if (b < 0x20 && !xml_char(b))
      fail(at() + "a control character, " + text::shown(xml.substr(i, 1)) + ", which XML does not allow");
    // references are read in attributes and text only
    if (!until.empty()) {
      if (xml.compare(i, until.size(), until) == 0) until = {};
      continue;
    }
    if (quote) {
      if (ch == quote) quote = 0;
      if (ch == '<') fail(at() + "a '<' in an attribute value, which XML does not allow (write &lt;)");
    } else if (in_tag) {
      if (ch == '"' || ch == '\'') quote = ch;
      if (ch == '>') in_tag = false;
    } else if (ch == '<') {
      for (const auto& [open, close] : {std::pair<std::string_view, std::string_view>{"<!--", "-->"},
                                        {"<![CDATA[", "]]>"},
                                        {"<?", "?>"},
                                        {"<!", ">"}})
        if (until.empty() && xml.compare(i, open.size(), open) == 0) until = close;
      in_tag = until.empty();
      continue;
    }
    if (ch != '&' || xml.compare(i, 2, "&#") != 0) continue;
    const bool hex = i + 2 < xml.size() && xml[i + 2] == 'x';
    const std::size_t digits = i + (hex ? 3 : 2), end = xml.find(';', digits);
    const bool bounded = end != std::string::npos && end - i <= 40;
    const std::string reference = xml.substr(i, bounded ? end + 1 - i : 12);
    unsigned long c = 0;
    bool number = bounded && end > digits;
    for (std::size_t k = digits; number && k < end; ++k) {
      const char d = xml[k];
      const int v = d >= '0' && d <= '9'          ? d - '0'
                    : hex && d >= 'a' && d <= 'f' ? d - 'a' + 10
                    : hex && d >= 'A' && d <= 'F' ? d - 'A' + 10
                                                  : -1;
      number = v >= 0;
      c = std::min(c * (hex ? 16 : 10) + static_cast<unsigned long>(v), 0x110000UL);  // (beyond: none)
    }
    if (!number || !xml_char(c))
      fail(at() + "the character reference " + text::shown(reference) +
           (number ? " names no character XML allows" : " is not &#DIGITS; or &#xHEX;"));
  }
}

Outline outline(const std::string& xml_as_given, const std::string& source) {
  const std::string xml = with_lf_line_ends(xml_as_given);
  check_characters(xml, source);
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS)
    fail(source +
         (doc.ErrorLineNum() > 0 ? ":" + std::to_string(doc.ErrorLineNum()) : std::string()) +  // (none: empty)
         ": not XML: " + xml_fault(doc));
  // urdfdom's XML reader does not take a document type with its own declarations (entities)
  for (const auto* n = doc.FirstChild(); n; n = n->NextSibling())
    if (const auto* u = n->ToUnknown(); u && std::string(u->Value()).find('[') != std::string::npos)
      fail(source + ":" + std::to_string(u->GetLineNum()) +
           ": a <!DOCTYPE> with declarations of its own ([...]) is not read by urdfdom");
  const auto* robot = doc.RootElement();
  if (!robot) fail(source + ": no <robot> element");
  if (std::string(robot->Name()) != "robot")
    fail(at(source, robot, "no <robot> element (the document is a <" + text::shown(robot->Name()) + ">)"));
  // XML has one root element; tinyxml2 reads on past its end, and urdfdom would read the first alone
  if (const auto* second = robot->NextSiblingElement())
    fail(at(source, second,
            "<" + text::shown(second->Name()) + "> after the root element <robot> has ended (line " +
                std::to_string(robot->GetLineNum()) +
                "): an XML document has one root element (a </robot> too early, or two robots in one file?)"));
  check_robot(source, robot);
  check_not_xacro(source, robot);
  check_names(source, robot, "<robot>", {"link", "joint", "material", "gazebo", "transmission"}, {"name", "version"},
              false, false);

  Outline out;
  if (const char* n = robot->Attribute("name")) out.robot = n;
  if (const std::string fault = text::label_fault(out.robot); !out.robot.empty() && !fault.empty())
    fail(at(source, robot, "<robot name=\"" + text::shown(out.robot) + "\">: " + fault));
  std::map<std::string, int> link_line, joint_line, material_line;
  for (const auto* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string tag = e->Name();
    if (tag == "material") {
      const char* name = e->Attribute("name");
      if (!name) fail(at(source, e, "<material> has no name attribute"));
      const std::string who = "material '" + text::shown(name) + "'";
      check_material(source, e, who, true);
      if (const auto [it, fresh] = material_line.emplace(name, e->GetLineNum()); !fresh)
        fail(at(source, e, who + ": the name is used twice (first on line " + std::to_string(it->second) + ")"));
      continue;
    }
    if (tag != "link" && tag != "joint") continue;
    const char* name = e->Attribute("name");
    if (!name || !*name) fail(at(source, e, "<" + tag + "> without a name"));
    const std::string who = tag + " '" + text::shown(name) + "'";
    auto& seen = tag == "link" ? link_line : joint_line;
    if (const auto it = seen.find(name); it != seen.end())
      fail(at(source, e, who + ": the name is used twice (first on line " + std::to_string(it->second) + ")"));
    seen[name] = e->GetLineNum();

    if (tag == "link") {
      if (const std::string fault = text::label_fault(name); !fault.empty()) fail(at(source, e, who + ": " + fault));
      out.links.emplace_back(name, e->GetLineNum());
      check_names(source, e, who, {"inertial", "visual", "collision"}, {"name"}, false, false,
                  {"inertia", "mass", "origin", "geometry"});
      check_single(source, e, "inertial", who);
      if (const auto* in = e->FirstChildElement("inertial")) check_inertial(source, in, who);
      for (const char* part : {"visual", "collision"})
        for (const auto* x = e->FirstChildElement(part); x; x = x->NextSiblingElement(part))
          check_shape(source, x, who);
      continue;
    }

    // any joint can become a model joint, whose name heads CSV columns
    if (const std::string fault = name_fault(name); !fault.empty()) {
      const auto* c = e->FirstChildElement("child");
      const char* child = c ? c->Attribute("link") : nullptr;
      fail(at(source, e,
              who + (child ? std::string(" (moving link '") + text::shown(child) + "')" : std::string()) + ": " +
                  fault + ", so no CSV column can name it"));
    }
    Outline::Joint j;
    j.name = name;
    j.line = e->GetLineNum();
    check_names(source, e, who,
                {"origin", "parent", "child", "axis", "calibration", "dynamics", "limit", "mimic", "safety_controller"},
                {"name", "type"}, false, false);
    for (const char* part :
         {"parent", "child", "axis", "limit", "dynamics", "mimic", "calibration", "safety_controller"})
      check_single(source, e, part, who);
    const auto* p = e->FirstChildElement("parent");
    const auto* c = e->FirstChildElement("child");
    if (!p || !p->Attribute("link")) fail(at(source, e, who + ": no <parent link=\"...\">"));
    if (!c || !c->Attribute("link")) fail(at(source, e, who + ": no <child link=\"...\">"));
    check_names(source, p, who, {}, {"link"}, true, false);
    check_names(source, c, who, {}, {"link"}, true, false);
    j.parent = p->Attribute("link");
    j.child = c->Attribute("link");
    j.mimic = e->FirstChildElement("mimic") != nullptr;
    check_origin(source, e, who);
    const char* type = e->Attribute("type");
    const std::string types = "revolute, continuous, prismatic, fixed, floating or planar";
    if (!type) fail(at(source, e, who + ": no type attribute (" + types + ")"));
    const std::string t = type;
    if (t != "revolute" && t != "continuous" && t != "prismatic" && t != "fixed" && t != "floating" && t != "planar")
      fail(at(source, e, who + ": unknown joint type '" + text::shown(t) + "' (expected " + types + ")"));
    const bool fixed = t == "fixed";
    check_joint_parts(source, e, t, who);
    if (const auto* ax = e->FirstChildElement("axis")) {
      check_names(source, ax, who, {}, {"xyz", "rpy"}, true, true);
      if (const char* rpy = ax->Attribute("rpy")) {  // (written by some tutorials' robots, always as zeros)
        check_numbers(source, ax, "rpy", 3, who);
        std::istringstream angles{std::string(rpy)};
        for (double v = 0; angles >> v;)
          if (v != 0)
            fail(at(source, ax,
                    who + ": <axis rpy=\"" + text::shown(rpy) +
                        "\">: urdfdom reads no rpy on an axis, which would not turn it: give the axis's direction in "
                        "xyz"));
      }
      check_numbers(source, ax, "xyz", 3, who);
      if (!fixed && ax->Attribute("xyz")) {
        std::istringstream in{std::string(ax->Attribute("xyz"))};
        double x = 0, y = 0, z = 0;
        in >> x >> y >> z;
        if (x == 0 && y == 0 && z == 0) fail(at(source, ax, who + ": zero axis"));
      }
    }
    out.joints.push_back(j);
  }
  if (out.links.empty()) fail(at(source, robot, "robot '" + text::shown(out.robot) + "' has no links"));

  // the links named by joints exist, each link has one parent, one root, no cycle
  std::map<std::string, int> parent_of;  // link -> joint index
  for (std::size_t k = 0; k < out.joints.size(); ++k) {
    const auto& j = out.joints[k];
    const std::string who = source + ":" + std::to_string(j.line) + ": joint '" + text::shown(j.name) + "'";
    const std::string parent = text::shown(j.parent), child = text::shown(j.child);
    if (!link_line.count(j.parent)) fail(who + ": parent link '" + parent + "' is not defined");
    if (!link_line.count(j.child)) fail(who + ": child link '" + child + "' is not defined");
    if (j.parent == j.child) fail(who + ": link '" + child + "' is its own parent (a cycle)");
    if (const auto it = parent_of.find(j.child); it != parent_of.end())
      fail(who + ": link '" + child + "' already has a parent joint, '" +
           text::shown(out.joints[std::size_t(it->second)].name) + "' (line " +
           std::to_string(out.joints[std::size_t(it->second)].line) + ")");
    parent_of[j.child] = int(k);
  }
  std::vector<std::string> roots;
  for (const auto& [name, line] : out.links)
    if (!parent_of.count(name)) roots.push_back(name);
  if (roots.empty()) fail(source + ": no root link: every link is the child of a joint (the joints form a cycle)");
  if (roots.size() > 1)
    fail(source + ": two root links, '" + text::shown(roots[0]) + "' (line " + std::to_string(link_line[roots[0]]) +
         ") and '" + text::shown(roots[1]) + "' (line " + std::to_string(link_line[roots[1]]) +
         "): a URDF is one tree");
  // every link reaches the root going up; a link that does not sits on a cycle (each link is walked once)
  std::map<std::string, bool> reaches{{roots[0], true}};
  for (const auto& [name, line] : out.links) {
    std::vector<std::string> path;
    std::string l = name;
    while (!reaches.count(l)) {
      if (path.size() > out.links.size()) {
        const auto& j = out.joints[std::size_t(parent_of[l])];
        fail(source + ":" + std::to_string(j.line) + ": joint '" + text::shown(j.name) + "': link '" + text::shown(l) +
             "' lies on a cycle of joints that never reaches the root link '" + text::shown(roots[0]) + "'");
      }
      path.push_back(l);
      l = out.joints[std::size_t(parent_of[l])].parent;
    }
    for (const auto& p : path) reaches[p] = true;
  }
  return out;
}

// urdfdom reports through console_bridge; its messages are collected while it parses.
class Collector : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) text_ += (text_.empty() ? "" : "; ") + text;
  }
  std::string text_;
};

::urdf::ModelInterfaceSharedPtr parse_with_urdfdom(const std::string& xml, std::string& errors) {
  static std::mutex mutex;  // console_bridge's handler is global
  std::lock_guard<std::mutex> lock(mutex);
  Collector collector;
  console_bridge::useOutputHandler(&collector);
  struct Restore {
    ~Restore() { console_bridge::restorePreviousOutputHandler(); }
  } restore;
  auto model = ::urdf::parseURDF(xml);
  errors = collector.text_;
  return model;
}

// Whether the principal moments of a positive semidefinite tensor violate the triangle inequality
// (C > A + B beyond check_inertia's tolerance); `ev` receives them, ascending.
bool breaks_triangle(const Eigen::Matrix3d& I, double mass, Eigen::Vector3d& ev) {
  const double tol = inertia_tolerance(I, mass);
  ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I, Eigen::EigenvaluesOnly).eigenvalues();
  return ev(0) >= -tol && ev(2) > ev(0) + ev(1) + tol;
}

// MuJoCo's `balanceinertia`: the three principal moments `ev` replaced by their mean, with a warning.
void balance(Eigen::Matrix3d& I, const Eigen::Vector3d& ev, const std::string& where,
             std::vector<std::string>& warnings) {
  const double mean = ev.sum() / 3;
  I = mean * Eigen::Matrix3d::Identity();
  char change[96];  // the changes to 6 digits: their last bits are round-off of the moments'
  std::snprintf(change, sizeof change, "%+.6g, %+.6g, %+.6g", mean - ev(0), mean - ev(1), mean - ev(2));
  warnings.push_back(where + ": principal moments " + exact_number(ev(0)) + ", " + exact_number(ev(1)) + ", " +
                     exact_number(ev(2)) + " kg m^2 violate the triangle inequality; balanced to their mean " +
                     exact_number(mean) + " kg m^2 each (changed by " + change + ")");
}

Pose<double> to_pose(const ::urdf::Pose& p) {
  const Eigen::Quaterniond q(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  Pose<double> out;
  out.R = q.normalized().toRotationMatrix();
  out.p = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return out;
}

}  // namespace

UrdfDocument read_urdf_document(const std::string& xml, const std::string& source, bool balance_inertia,
                                std::vector<std::string>& warnings) {
  const Outline o = outline(xml, source);
  std::string errors;
  const auto model = parse_with_urdfdom(xml, errors);
  if (!model) fail(source + ": urdfdom rejects the file: " + (errors.empty() ? "no reason given" : errors));
  // urdfdom goes on after many of the errors it logs (keeping what it could not read as zeros): each is fatal
  if (!errors.empty()) fail(source + ": urdfdom could not read all of the file: " + errors);

  UrdfDocument doc;
  doc.source = source;
  doc.name = o.robot;
  for (const auto& [name, line] : o.links) {
    UrdfLink l;
    l.name = name;
    l.line = line;
    const std::string where = source + ":" + std::to_string(line) + ": link '" + text::shown(name) + "'";
    const auto link = model->getLink(name);
    if (!link) fail(where + ": urdfdom lost it");
    if (const auto& in = link->inertial) {
      const Pose<double> X = to_pose(in->origin);
      Eigen::Matrix3d I;
      I << in->ixx, in->ixy, in->ixz, in->ixy, in->iyy, in->iyz, in->ixz, in->iyz, in->izz;
      l.body.mass = in->mass;
      l.body.com = X.p;
      l.body.inertia = X.R * I * X.R.transpose();
      l.body.inertia = 0.5 * (l.body.inertia + l.body.inertia.transpose()).eval();
      if (Eigen::Vector3d ev; breaks_triangle(l.body.inertia, l.body.mass, ev)) {
        if (!balance_inertia)
          fail(where + ": inertial: principal moments violate the triangle inequality (" + exact_number(ev(2)) + " > " +
               exact_number(ev(0)) + " + " + exact_number(ev(1)) +
               "); ImportOptions::balance_inertia (--balance-inertia) replaces them by their mean");
        balance(l.body.inertia, ev, where, warnings);
      }
      try {
        check_inertia(l.body, "");
      } catch (const ModelError& e) {
        fail(where + ": inertial" + e.what());
      }
    }
    doc.links.push_back(l);
  }
  for (const auto& oj : o.joints) {
    UrdfJoint j;
    j.name = oj.name;
    j.line = oj.line;
    j.mimic = oj.mimic;
    j.parent = doc.find_link(oj.parent);
    j.child = doc.find_link(oj.child);
    const auto joint = model->getJoint(oj.name);
    if (!joint)
      fail(source + ":" + std::to_string(oj.line) + ": joint '" + text::shown(oj.name) + "': urdfdom lost it");
    switch (joint->type) {
      case ::urdf::Joint::REVOLUTE:
        j.type = JointType::Revolute;
        break;
      case ::urdf::Joint::CONTINUOUS:
        j.type = JointType::Continuous;
        break;
      case ::urdf::Joint::PRISMATIC:
        j.type = JointType::Prismatic;
        break;
      case ::urdf::Joint::FIXED:
        j.type = JointType::Fixed;
        break;
      case ::urdf::Joint::FLOATING:
        j.type = JointType::Floating;
        break;
      case ::urdf::Joint::PLANAR:
        j.type = JointType::Planar;
        break;
      default:
        fail(source + ":" + std::to_string(oj.line) + ": joint '" + text::shown(oj.name) + "': unknown joint type");
    }
    j.origin = to_pose(joint->parent_to_joint_origin_transform);
    const Eigen::Vector3d axis(joint->axis.x, joint->axis.y, joint->axis.z);
    if (j.type != JointType::Fixed && j.type != JointType::Floating) {  // urdfdom reads no axis for these
      // a direction: any length, scaled before it is normalised so that no square overflows or underflows
      const double longest = axis.cwiseAbs().maxCoeff();
      if (!(longest > 0) || !std::isfinite(longest))
        fail(source + ":" + std::to_string(oj.line) + ": joint '" + text::shown(oj.name) +
             (longest > 0 ? "': axis not finite" : "': zero axis"));
      j.axis = (axis / longest).normalized();
    }
    // URDF's joint damping and Coulomb friction are not part of the model: said, not dropped silently
    // (a fixed joint's never act)
    if (const auto& d = joint->dynamics; d && j.type != JointType::Fixed && (d->damping != 0 || d->friction != 0))
      warnings.push_back(source + ":" + std::to_string(oj.line) + ": joint '" + text::shown(oj.name) +
                         "': <dynamics damping=\"" + exact_number(d->damping) + "\" friction=\"" +
                         exact_number(d->friction) + "\"/> is left out (the model's joints have neither)");
    doc.links[std::size_t(j.child)].parent_joint = int(doc.joints.size());
    doc.links[std::size_t(j.parent)].child_joints.push_back(int(doc.joints.size()));
    doc.joints.push_back(j);
  }
  for (std::size_t l = 0; l < doc.links.size(); ++l)
    if (doc.links[l].parent_joint < 0) doc.root = int(l);
  return doc;
}

}  // namespace humandyn::urdf::detail
