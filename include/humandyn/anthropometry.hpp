// de Leva (1996), "Adjustments to Zatsiorsky-Seluyanov's segment inertia parameters", J. Biomech.
// 29(9):1223-1230, Table 4, compiled in so that the default model needs no file.
// com: centre of mass from the first-listed endpoint, fraction of the segment length.
// r_sag, r_trans, r_long: radii of gyration about the centre of mass, fraction of the segment length,
// about the sagittal (antero-posterior, x), transverse (medio-lateral, y) and longitudinal axes.
#pragma once

#include <array>
#include <string_view>

namespace humandyn::anthropometry {

/// The sex a de Leva row is for (that of its reference subject).
enum class Sex { Male, Female };

/// One row of de Leva's Table 4: a segment between two endpoints, for one sex.
struct SegmentRow {
  std::string_view segment, endpoints;  ///< as de Leva names them, e.g. "thigh", "HJC-KJC"
  Sex sex;                              ///< the sex the row is for
  double length;                        ///< m, of the reference subject
  double mass_fraction;                 ///< of body mass
  /// Centre of mass from the first-listed endpoint, and the radii of gyration about it (sagittal x,
  /// transverse y, longitudinal), each a fraction of the segment length.
  double com, r_sag, r_trans, r_long;
};

/// A reference subject's stature and body mass.
struct Reference {
  double height, mass;  ///< m, kg
};
/// de Leva's reference male: 1.741 m, 73.0 kg.
inline constexpr Reference reference_male{1.741, 73.0};
/// de Leva's reference female: 1.735 m, 61.9 kg.
inline constexpr Reference reference_female{1.735, 61.9};

/// The rows of data/anthropometry/de_leva_1996.csv, percentages turned into fractions.
inline constexpr std::array<SegmentRow, 28> de_leva_1996{{
    {"head", "VERT-MIDG", Sex::Male, 0.2033, 0.0694, 0.5976, 0.362, 0.376, 0.312},
    {"head", "VERT-MIDG", Sex::Female, 0.2002, 0.0668, 0.5894, 0.330, 0.359, 0.318},
    {"head_neck", "VERT-CERV", Sex::Male, 0.2429, 0.0694, 0.5002, 0.303, 0.315, 0.261},
    {"head_neck", "VERT-CERV", Sex::Female, 0.2437, 0.0668, 0.4841, 0.271, 0.295, 0.261},
    {"trunk", "SUPR-MIDH", Sex::Male, 0.5319, 0.4346, 0.4486, 0.372, 0.347, 0.191},
    {"trunk", "SUPR-MIDH", Sex::Female, 0.5293, 0.4257, 0.4151, 0.357, 0.339, 0.171},
    {"trunk", "CERV-MIDH", Sex::Male, 0.6033, 0.4346, 0.5138, 0.328, 0.306, 0.169},
    {"trunk", "CERV-MIDH", Sex::Female, 0.6148, 0.4257, 0.4964, 0.307, 0.292, 0.147},
    {"upper_trunk", "SUPR-XYPH", Sex::Male, 0.1707, 0.1596, 0.2999, 0.716, 0.454, 0.659},
    {"upper_trunk", "SUPR-XYPH", Sex::Female, 0.1425, 0.1545, 0.2077, 0.746, 0.502, 0.718},
    {"mid_trunk", "XYPH-OMPH", Sex::Male, 0.2155, 0.1633, 0.4502, 0.482, 0.383, 0.468},
    {"mid_trunk", "XYPH-OMPH", Sex::Female, 0.2053, 0.1465, 0.4512, 0.433, 0.354, 0.415},
    {"lower_trunk", "OMPH-MIDH", Sex::Male, 0.1457, 0.1117, 0.6115, 0.615, 0.551, 0.587},
    {"lower_trunk", "OMPH-MIDH", Sex::Female, 0.1815, 0.1247, 0.4920, 0.433, 0.402, 0.444},
    {"upper_arm", "SJC-EJC", Sex::Male, 0.2817, 0.0271, 0.5772, 0.285, 0.269, 0.158},
    {"upper_arm", "SJC-EJC", Sex::Female, 0.2751, 0.0255, 0.5754, 0.278, 0.260, 0.148},
    {"forearm", "EJC-WJC", Sex::Male, 0.2689, 0.0162, 0.4574, 0.276, 0.265, 0.121},
    {"forearm", "EJC-WJC", Sex::Female, 0.2643, 0.0138, 0.4559, 0.261, 0.257, 0.094},
    {"hand", "WJC-MET3", Sex::Male, 0.0862, 0.0061, 0.7900, 0.628, 0.513, 0.401},
    {"hand", "WJC-MET3", Sex::Female, 0.0780, 0.0056, 0.7474, 0.531, 0.454, 0.335},
    {"thigh", "HJC-KJC", Sex::Male, 0.4222, 0.1416, 0.4095, 0.329, 0.329, 0.149},
    {"thigh", "HJC-KJC", Sex::Female, 0.3685, 0.1478, 0.3612, 0.369, 0.364, 0.162},
    {"shank", "KJC-LMAL", Sex::Male, 0.4340, 0.0433, 0.4459, 0.255, 0.249, 0.103},
    {"shank", "KJC-LMAL", Sex::Female, 0.4323, 0.0481, 0.4416, 0.271, 0.267, 0.093},
    {"shank", "KJC-AJC", Sex::Male, 0.4403, 0.0433, 0.4395, 0.251, 0.246, 0.102},
    {"shank", "KJC-AJC", Sex::Female, 0.4386, 0.0481, 0.4352, 0.267, 0.263, 0.092},
    {"foot", "HEEL-TTIP", Sex::Male, 0.2581, 0.0137, 0.4415, 0.257, 0.245, 0.124},
    {"foot", "HEEL-TTIP", Sex::Female, 0.2283, 0.0129, 0.4014, 0.299, 0.279, 0.139},
}};

/// The row for a segment, its endpoints and sex. A lookup in a constant expression fails to compile if the
/// row is absent; at run time (a sex known only then) it throws a const char*, which the library's lookups,
/// every one of a row the table has for both sexes, never do.
/// \param segment    e.g. "thigh"
/// \param endpoints  e.g. "HJC-KJC"
/// \return the row of de_leva_1996
constexpr const SegmentRow& row(std::string_view segment, std::string_view endpoints, Sex sex) {
  for (const auto& r : de_leva_1996)
    if (r.segment == segment && r.endpoints == endpoints && r.sex == sex) return r;
  throw "no such de Leva row";
}

/// The mass fraction of a whole body: head, trunk and both of each limb segment. As printed, the
/// male rows sum to 100 %, the female ones to 99.99 % (rounding); builders divide by this sum so that
/// a person's segments weigh what the person weighs.
constexpr double whole_body_mass_fraction(Sex sex) {
  return row("head", "VERT-MIDG", sex).mass_fraction + row("trunk", "SUPR-MIDH", sex).mass_fraction +
         2 * (row("upper_arm", "SJC-EJC", sex).mass_fraction + row("forearm", "EJC-WJC", sex).mass_fraction +
              row("hand", "WJC-MET3", sex).mass_fraction + row("thigh", "HJC-KJC", sex).mass_fraction +
              row("shank", "KJC-AJC", sex).mass_fraction + row("foot", "HEEL-TTIP", sex).mass_fraction);
}

/// Half the distance between the hip joint centres, a fraction of stature (0.09 m for the reference male).
/// Like the five below, a length de Leva does not give, for the model's frame placement.
inline constexpr double hip_half_width = 0.09 / 1.741;
/// Half the distance between the shoulder joint centres of a man, a fraction of stature (0.19 m for the
/// reference male).
inline constexpr double shoulder_half_width_male = 0.19 / 1.741;
/// Half the distance between the shoulder joint centres of a woman, a fraction of stature (0.17 m for the
/// reference female).
inline constexpr double shoulder_half_width_female = 0.17 / 1.735;
/// The ankle's height above the sole, a fraction of stature (Drillis and Contini's 0.039).
inline constexpr double ankle_height = 0.039;
/// The foot's width, a fraction of stature (Drillis and Contini's 0.055; the sole of ground_reaction.hpp).
inline constexpr double foot_width = 0.055;
/// How far the ankle sits ahead of the heel: a quarter of the foot's length.
inline constexpr double heel_to_ankle = 0.25;

}  // namespace humandyn::anthropometry
