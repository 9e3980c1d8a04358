/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   The part of a primitive granular wall that acts on rods (atom_style
   spherocylinder), shared by fix wall/gran/spherocylinder (planes and the
   inner wall of a cylinder) and fix wall/gran/rotating (the plate with
   its orifice). Not a style of its own.

   A rod touches a wall at up to a few points at once (both ends of a rod
   lying flat; its ends and the rim of an orifice: spherocylinder_geometry.h
   gives them). Each contact is handed to the wall's contact model as a
   sphere contact of the rod's radius at its core point, with the contact
   point in the middle of the overlap, so that the stock normal and
   tangential models act on it and take the torque arm from the contact
   point (surface spherocylinder, NONSPHERICAL_ACTIVE_FLAG).

   Each contact needs its own tangential history. The stock wall keeps one
   per particle; here a rod has `slots` of them (a fix property/atom of
   ours, kept in restart files), each with the segment parameter t of the
   contact that holds it. At every step each contact takes the slot whose
   t is nearest to its own, if that is within the rod's radius (a contact
   moves far less than that in one step), else a free slot with a zeroed
   history; a slot no contact takes is zeroed. So a contact that slides
   along the rod keeps its history, and one that ends loses it, as a
   sphere's does.
------------------------------------------------------------------------- */

#ifndef LMP_FIX_WALL_GRAN_ROD_CONTACTS_H
#define LMP_FIX_WALL_GRAN_ROD_CONTACTS_H

#include "fix_wall_gran.h"
#include "spherocylinder_geometry.h"

namespace LAMMPS_NS {

class FixWallGranRodContacts : public FixWallGran {
 public:
  // max_contacts: the most contacts the wall's geometry gives one rod
  // (spherocylinder_geometry.h rules 6-8), 1 to silokit::max_wall_contacts;
  // the wall keeps that many history slots per rod
  FixWallGranRodContacts(class LAMMPS *, int, char **, int max_contacts);
  void post_create();
  void pre_delete(bool unfixflag);
  void init();

 protected:
  // true when the particles are rods (atom_style spherocylinder)
  bool rods() const { return rod_history_ != nullptr; }
  // the rod's axis (unit vector), its core half-length and its radius
  void rod_of(int i, double *axis, double &half_length, double &radius) const;
  // applies the forces of rod i's contacts with this wall (none: its
  // slots are freed)
  void apply_rod_contacts(int i, const silokit::WallContacts &contacts);
  // velocity of the wall at `point` (a fixed wall by default)
  virtual void wall_velocity(const double *point, double *velocity) const;

 private:
  const int slots_;
  class FixPropertyAtom *rod_history_;
  // per slot: in use (0/1), t, then the contact model's dnum_ values
  int slot_size() const { return 2 + dnum_; }
  // the slot for a contact at t; needs a slot not taken (see the .cpp)
  int take_slot(double *slots, double t, double radius, const bool *taken) const;
};

}

#endif
