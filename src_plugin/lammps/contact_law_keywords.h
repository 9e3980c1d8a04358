/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   The contact-law keywords that pair_style granular/jiang (per pair_coeff)
   and fix wall/gran/rotating (among its plate keywords) share:

       normal hooke/stiffness kn kt gamman gammat | normal hooke Y nu e v_char
       friction mu [rolling jiang a b lc <length | overlap | depth> | rolling none]
       [rolling_damping eta] [tangential_damping yes|no]
       [absolute_damping yes|no] [limit_force yes|no]

   One parser for both, so that a keyword means and checks the same in
   either style; the ERROR names the style and the keyword.
------------------------------------------------------------------------- */

#ifndef SILOKIT_LAMMPS_CONTACT_LAW_KEYWORDS_H
#define SILOKIT_LAMMPS_CONTACT_LAW_KEYWORDS_H

namespace LAMMPS_NS {
class Error;
}

namespace silokit_lammps {

// What the keywords set. Plain doubles (flags are 0 or 1), so that the pair
// style writes a type pair's settings to restart files as they are.
struct ContactLawSettings {
  double normal_model;                 // NORMAL_HOOKE_STIFFNESS or NORMAL_HOOKE; < 0: not given
  double kn, kt, gamman, gammat;       // hooke/stiffness
  double youngs, poisson, restitution, characteristic_velocity;   // hooke
  double youngs_effective;             // hooke: Y* of two bodies of this material
  double absolute_damping, tangential_damping, limit_force;      // 0 or 1
  double mu;                           // Coulomb friction; < 0: not given
  double rolling;                      // 0: none, 1: jiang
  double stiffness_factor, friction_factor;   // Jiang's a, b
  double length_mode;                  // LENGTH_FIXED, LENGTH_OVERLAP, LENGTH_DEPTH
  double contact_length;               // l_c of LENGTH_FIXED
  double rolling_damping;              // viscous rolling damping ratio (0: none)
};
enum { NORMAL_HOOKE_STIFFNESS = 0, NORMAL_HOOKE = 1 };
enum { LENGTH_FIXED = 0, LENGTH_OVERLAP = 1, LENGTH_DEPTH = 2 };

// LIGGGHTS' defaults: tangential damping on, damping relative to the
// effective mass, no force limit, no rolling resistance; normal and
// friction not given yet
ContactLawSettings default_contact_law();

// If arg[iarg] is one of the keywords above, reads it and its values into
// `law` and returns the index after them; otherwise returns iarg unchanged.
// A missing or bad value stops with an ERROR naming `style` and the keyword.
int parse_contact_law_keyword(LAMMPS_NS::Error *error, const char *style, int narg, char **arg,
                              int iarg, ContactLawSettings &law);

// After all keywords: normal and friction given, and the options consistent
// (rolling_damping needs rolling jiang; absolute_damping is for
// hooke/stiffness).
void check_contact_law(LAMMPS_NS::Error *error, const char *style, const ContactLawSettings &law);

}    // namespace silokit_lammps

#endif
