/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   One grain-grain contact as a host hands it to fix clog: the two atom
   ids, both centres, the overlap and the normal and tangential force on
   grain 1. LIGGGHTS fills it from a row of compute pair/gran/local (id
   pos force_normal force_tangential delta), LAMMPS from pair_style
   granular/jiang's current_contacts() (core/contact_law.h on the stored
   history, read without advancing it).
------------------------------------------------------------------------- */

#ifndef SILOKIT_CONTACT_SAMPLE_H
#define SILOKIT_CONTACT_SAMPLE_H

namespace silokit {

struct ContactSample {
  int id1, id2;
  double x1[3], x2[3];         // centres (a ghost's image as the host holds it)
  double overlap;              // r1 + r2 - |x1 - x2|
  double normal_force[3];      // on grain 1, elastic + damping
  double tangential_force[3];  // on grain 1, after the Coulomb cap
};

}  // namespace silokit

#endif
