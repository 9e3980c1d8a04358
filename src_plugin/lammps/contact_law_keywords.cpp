/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   The contact-law keywords of our LAMMPS styles (contact_law_keywords.h).
------------------------------------------------------------------------- */

#include "contact_law_keywords.h"

#include "contact_law.h"
#include "lammps_args.h"

#include "error.h"

#include <cstring>
#include <string>

namespace silokit_lammps {

ContactLawSettings default_contact_law()
{
  ContactLawSettings law;
  std::memset(&law, 0, sizeof(law));
  law.normal_model = -1.0;
  law.mu = -1.0;
  law.tangential_damping = 1.0;
  law.length_mode = LENGTH_FIXED;
  return law;
}

int parse_contact_law_keyword(LAMMPS_NS::Error *error, const char *style, int narg, char **arg,
                              int iarg, ContactLawSettings &law)
{
  // checks that the keyword at `at` has `count` values after it
  auto need = [&](int at, int count, const std::string &what) {
    if (at + count >= narg)
      error->all(FLERR, "{}: {} needs {} value{}", style, what, count, count > 1 ? "s" : "");
  };
  auto number = [&](const char *what, int at) { return parse_number(error, style, what, arg[at]); };

  const std::string keyword = arg[iarg];
  if (keyword == "normal") {
    need(iarg, 1, "normal");
    const std::string model = arg[iarg + 1];
    if (model == "hooke/stiffness") {
      need(iarg + 1, 4, "normal hooke/stiffness (kn kt gamman gammat)");
      law.normal_model = NORMAL_HOOKE_STIFFNESS;
      law.kn = number("normal hooke/stiffness kn", iarg + 2);
      law.kt = number("normal hooke/stiffness kt", iarg + 3);
      law.gamman = number("normal hooke/stiffness gamman", iarg + 4);
      law.gammat = number("normal hooke/stiffness gammat", iarg + 5);
      if (!(law.kn > 0.0)) error->all(FLERR, "{}: normal hooke/stiffness kn must be > 0", style);
      if (!(law.kt >= 0.0)) error->all(FLERR, "{}: normal hooke/stiffness kt must be >= 0", style);
      if (!(law.gamman >= 0.0))
        error->all(FLERR, "{}: normal hooke/stiffness gamman must be >= 0", style);
      if (!(law.gammat >= 0.0))
        error->all(FLERR, "{}: normal hooke/stiffness gammat must be >= 0", style);
    } else if (model == "hooke") {
      need(iarg + 1, 4, "normal hooke (Y nu e v_char)");
      law.normal_model = NORMAL_HOOKE;
      law.youngs = number("normal hooke Y", iarg + 2);
      law.poisson = number("normal hooke nu", iarg + 3);
      law.restitution = number("normal hooke e", iarg + 4);
      law.characteristic_velocity = number("normal hooke v_char", iarg + 5);
      if (!(law.youngs > 0.0)) error->all(FLERR, "{}: normal hooke Y must be > 0", style);
      if (!(law.poisson > -1.0 && law.poisson <= 0.5))
        error->all(FLERR, "{}: normal hooke nu must be in (-1, 0.5]", style);
      if (!(law.restitution > 0.0 && law.restitution <= 1.0))
        error->all(FLERR, "{}: normal hooke e must be in (0, 1]", style);
      if (!(law.characteristic_velocity > 0.0))
        error->all(FLERR, "{}: normal hooke v_char must be > 0", style);
      // both bodies of this material (two grains of a type pair, or a
      // grain and the plate)
      law.youngs_effective = silokit::contact::effective_youngs_modulus(
          law.youngs, law.poisson, law.youngs, law.poisson);
    } else {
      error->all(FLERR, "{}: unknown normal model '{}' (hooke/stiffness or hooke)", style, model);
    }
    return iarg + 6;
  }
  if (keyword == "friction") {
    need(iarg, 1, "friction");
    law.mu = number("friction", iarg + 1);
    if (!(law.mu >= 0.0)) error->all(FLERR, "{}: friction must be >= 0", style);
    return iarg + 2;
  }
  if (keyword == "rolling") {
    need(iarg, 1, "rolling");
    const std::string model = arg[iarg + 1];
    if (model == "none") {
      law.rolling = 0.0;
      return iarg + 2;
    }
    if (model != "jiang")
      error->all(FLERR, "{}: unknown rolling model '{}' (jiang or none)", style, model);
    need(iarg + 1, 4, "rolling jiang (a b lc <length|overlap|depth>)");
    law.rolling = 1.0;
    law.stiffness_factor = number("rolling jiang a", iarg + 2);
    law.friction_factor = number("rolling jiang b", iarg + 3);
    if (!(law.stiffness_factor > 0.0))
      error->all(FLERR, "{}: rolling jiang a (stiffness factor) must be > 0", style);
    if (!(law.friction_factor > 0.0))
      error->all(FLERR, "{}: rolling jiang b (friction factor) must be > 0", style);
    if (std::strcmp(arg[iarg + 4], "lc") != 0)
      error->all(FLERR, "{}: rolling jiang a b is followed by lc, got '{}'", style, arg[iarg + 4]);
    const std::string length = arg[iarg + 5];
    if (length == "overlap") {
      law.length_mode = LENGTH_OVERLAP;
    } else if (length == "depth") {
      law.length_mode = LENGTH_DEPTH;
    } else {
      law.length_mode = LENGTH_FIXED;
      law.contact_length = number("rolling jiang lc", iarg + 5);
      if (!(law.contact_length >= 0.0))
        error->all(FLERR, "{}: rolling jiang lc must be >= 0 (0: no rolling resistance), "
                   "overlap or depth", style);
    }
    return iarg + 6;
  }
  if (keyword == "rolling_damping") {
    need(iarg, 1, "rolling_damping");
    law.rolling_damping = number("rolling_damping", iarg + 1);
    if (!(law.rolling_damping >= 0.0)) error->all(FLERR, "{}: rolling_damping must be >= 0", style);
    return iarg + 2;
  }
  if (keyword == "tangential_damping" || keyword == "absolute_damping" ||
      keyword == "limit_force") {
    need(iarg, 1, keyword);
    const double value = parse_yes_no(error, style, keyword, arg[iarg + 1]) ? 1.0 : 0.0;
    if (keyword == "tangential_damping") law.tangential_damping = value;
    else if (keyword == "absolute_damping") law.absolute_damping = value;
    else law.limit_force = value;
    return iarg + 2;
  }
  return iarg;
}

void check_contact_law(LAMMPS_NS::Error *error, const char *style, const ContactLawSettings &law)
{
  if (law.normal_model < 0.0)
    error->all(FLERR, "{}: normal is required (hooke/stiffness or hooke)", style);
  if (law.mu < 0.0) error->all(FLERR, "{}: friction is required", style);
  if (law.rolling_damping > 0.0 && law.rolling == 0.0)
    error->all(FLERR, "{}: rolling_damping needs rolling jiang", style);
  if (law.normal_model == NORMAL_HOOKE && law.absolute_damping != 0.0)
    error->all(FLERR, "{}: absolute_damping applies to normal hooke/stiffness only", style);
}

}    // namespace silokit_lammps
