/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   The rod part of silokit's primitive walls (fix_wall_gran_rod_contacts.h).
------------------------------------------------------------------------- */

#include "fix_wall_gran_rod_contacts.h"

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "atom.h"
#include "atom_vec_spherocylinder.h"
#include "contact_interface.h"
#include "error.h"
#include "fix_property_atom.h"
#include "fix_wall_gran_base.h"
#include "modify.h"
#include "spherocylinder_model_check.h"

using namespace LAMMPS_NS;

FixWallGranRodContacts::FixWallGranRodContacts(LAMMPS *lmp, int narg, char **arg, int max_contacts) :
  FixWallGran(lmp, narg, arg), slots_(max_contacts), rod_history_(nullptr)
{
  // one slot per contact the wall's geometry can give a rod: then every
  // contact of a step finds a slot (take_slot), and the per-step arrays of
  // apply_rod_contacts, sized for the most any wall gives, hold them all
  if (slots_ < 1 || slots_ > silokit::max_wall_contacts) {
    const std::string message = std::string("Fix ") + style + " (id " + id + "): a wall keeps one "
      "history slot per contact a rod can have with it, 1 to silokit::max_wall_contacts (" +
      std::to_string(silokit::max_wall_contacts) + "), not " + std::to_string(slots_);
    error->all(FLERR, message.c_str());
  }
}

/* ----------------------------------------------------------------------
   With rods, a history of `slots` contacts per rod, kept in restart files.
------------------------------------------------------------------------- */

void FixWallGranRodContacts::post_create()
{
  FixWallGran::post_create();
  if (!dynamic_cast<AtomVecSpherocylinder *>(atom->avec)) return;
  const std::string name = std::string("rod_history_") + id;
  const int values = slots_*slot_size();
  std::vector<std::string> zeros(values, "0.");
  std::vector<const char *> fixarg;
  const char *head[] = {name.c_str(), "all", "property/atom", name.c_str(), "vector",
                        "yes",    // restart
                        "no",     // communicate ghost
                        "no"};    // communicate reverse
  fixarg.assign(head, head + 8);
  for (int k = 0; k < values; ++k) fixarg.push_back(zeros[k].c_str());
  modify->add_fix(static_cast<int>(fixarg.size()), const_cast<char **>(&fixarg[0]));
  rod_history_ = static_cast<FixPropertyAtom *>(
      modify->find_fix_property(name.c_str(), "property/atom", "vector", values, 0, style));
}

void FixWallGranRodContacts::pre_delete(bool unfixflag)
{
  if (unfixflag && rod_history_) modify->delete_fix(rod_history_->id);
  FixWallGran::pre_delete(unfixflag);
}

void FixWallGranRodContacts::init()
{
  FixWallGran::init();
  if (!rods()) return;
  if (!impl) error->fix_error(FLERR, this, "rods need a granular contact model");
  const std::string problem = silokit::rod_model_problem(*impl);
  if (!problem.empty()) error->fix_error(FLERR, this, ("the wall's model " + problem).c_str());
}

/* ---------------------------------------------------------------------- */

void FixWallGranRodContacts::rod_of(int i, double *axis, double &half_length, double &radius) const
{
  const AtomVecSpherocylinder *rods = static_cast<AtomVecSpherocylinder *>(atom->avec);
  rods->axis_of(i, axis);
  radius = atom->shape[i][1];
  half_length = rods->half_segment_of(i);
}

void FixWallGranRodContacts::wall_velocity(const double *, double *velocity) const
{
  velocity[0] = velocity[1] = velocity[2] = 0.0;
}

/* ----------------------------------------------------------------------
   The slot for a contact at t: the slot in use whose t is nearest, within
   the rod's radius, and not taken by another contact this step; else the
   first free one; else the first one not taken, afresh (its contact of
   the last step is not near any of this step's). The caller hands in
   fewer taken slots than there are (apply_rod_contacts), so a slot not
   taken exists and the index returned is always a valid one.
------------------------------------------------------------------------- */

int FixWallGranRodContacts::take_slot(double *slots, double t, double radius, const bool *taken) const
{
  int nearest = -1, first_free = -1, first_untaken = -1;
  double nearest_distance = radius;
  for (int s = 0; s < slots_; ++s) {
    if (taken[s]) continue;
    if (first_untaken < 0) first_untaken = s;
    const double *slot = slots + s*slot_size();
    if (slot[0] == 0.0) {
      if (first_free < 0) first_free = s;
      continue;
    }
    const double distance = std::fabs(slot[1] - t);
    if (distance <= nearest_distance) {
      nearest = s;
      nearest_distance = distance;
    }
  }
  if (nearest >= 0) return nearest;
  const int fresh = first_free >= 0 ? first_free : first_untaken;
  std::memset(slots + fresh*slot_size(), 0, slot_size()*sizeof(double));
  return fresh;
}

/* ----------------------------------------------------------------------
   Each contact as a sphere contact of the rod's radius at its core point:
   delta from the wall point to the core point (fix_wall_gran_base.h makes
   en and the distance from it), overlap, contact point in the middle of
   the overlap, and the wall's velocity there.
------------------------------------------------------------------------- */

void FixWallGranRodContacts::apply_rod_contacts(int i, const silokit::WallContacts &contacts)
{
  double *slots = rod_history_->array_atom[i];
  const double radius = atom->shape[i][1];   // d/2, as rod_of gives it

  // Contact c finds c slots taken: with no more contacts than slots, one
  // is left for it. The geometry gives at most as many as the subclass
  // declared (rules 6-8 of spherocylinder_geometry.h); this guards that.
  if (contacts.count > slots_) {
    const std::string message = std::string("Fix ") + style + " (id " + id + "): a rod has " +
      std::to_string(contacts.count) + " contacts with the wall, more than its " +
      std::to_string(slots_) + " history slots (a bug: please report it)";
    error->one(FLERR, message.c_str());
  }
  bool taken[silokit::max_wall_contacts];
  for (int s = 0; s < slots_; ++s) taken[s] = false;
  int slot_of[silokit::max_wall_contacts];
  for (int c = 0; c < contacts.count; ++c) {
    slot_of[c] = take_slot(slots, contacts.contact[c].t, radius, taken);
    taken[slot_of[c]] = true;
  }
  // slots no contact took: the contacts they held have ended (a slot not
  // in use is all zero already: most rods near a wall do not touch it)
  for (int s = 0; s < slots_; ++s)
    if (!taken[s] && slots[s*slot_size()] != 0.0)
      std::memset(slots + s*slot_size(), 0, slot_size()*sizeof(double));

  LIGGGHTS::ContactModels::SurfacesIntersectData sidata;
  sidata.is_wall = true;
  for (int c = 0; c < contacts.count; ++c) {
    const silokit::WallContact &contact = contacts.contact[c];
    double *slot = slots + slot_of[c]*slot_size();
    // a core point on the wall (rule 10 of spherocylinder_geometry.h) has
    // no direction the stock wall code could take (it divides by the
    // distance): reachable only through an overlap of a whole radius, as
    // for the sphere path of fix wall/gran/rotating
    if (contact.overlap >= radius) continue;
    slot[0] = 1.0;
    slot[1] = contact.t;
    const double distance = radius - contact.overlap;
    sidata.i = i;
    sidata.radi = radius;
    sidata.deltan = contact.overlap;
    sidata.contact_history = dnum_ > 0 ? slot + 2 : nullptr;
    for (int k = 0; k < 3; ++k) {
      sidata.delta[k] = distance*contact.normal[k];
      sidata.contact_point[k] = contact.wall_point[k] - 0.5*contact.overlap*contact.normal[k];
    }
    sidata.is_non_spherical = true;
    double velocity[3];
    wall_velocity(sidata.contact_point, velocity);
    impl->compute_force(this, sidata, true, velocity);
  }
}
