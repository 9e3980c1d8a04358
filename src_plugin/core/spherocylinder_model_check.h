/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   The contact model rods are computed with: surface spherocylinder, and
   of the stock sub-models only those that take nothing but the overlap,
   the normal and the relative velocity at the contact point from it
   (hooke/stiffness, tangential history or no_history, no cohesion, no
   rolling resistance). The others read the particle radius, which for a
   rod is its bounding sphere's (L/2), or its spin as a sphere's: they
   would run and be wrong. Used by atom_style spherocylinder for the pair
   style and by the rod walls for theirs (doc/spherocylinder.md).
------------------------------------------------------------------------- */

#ifndef SILOKIT_SPHEROCYLINDER_MODEL_CHECK_H
#define SILOKIT_SPHEROCYLINDER_MODEL_CHECK_H

#include <string>

namespace silokit {

// Empty when `model` (anything with contact_match(type, name), as
// PairGran and a wall's IGranularWall have) suits rods; else what is wrong.
template <class Model>
std::string rod_model_problem(Model &model)
{
  if (!model.contact_match("surface", "spherocylinder"))
    return "needs 'surface spherocylinder' (the default surface treats rods as their bounding spheres)";
  if (!model.contact_match("normal", "hooke/stiffness"))
    return "rods take 'model hooke/stiffness' only (the other normal models read the bounding radius)";
  if (!model.contact_match("tangential", "history") && !model.contact_match("tangential", "no_history"))
    return "rods take 'tangential history' or 'tangential no_history' only";
  if (!model.contact_match("cohesion", "off"))
    return "rods take no cohesion model";
  if (!model.contact_match("rolling_friction", "off"))
    return "rods take no rolling_friction model (it would turn them as spheres)";
  return std::string();
}

}  // namespace silokit

#endif
