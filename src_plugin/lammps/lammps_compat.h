/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   The LAMMPS calls of our adapters that changed after LAMMPS 20220106
   (Debian 12's, the version we build and test), kept here so that a
   user's newer LAMMPS tree (-DLAMMPS_SOURCE_DIR) needs no change anywhere
   else. cmake/LammpsCompat.cmake compiles each newer call against the
   tree's headers and defines its macro when it compiles; 20220106 has no
   version macro to test, and the calls changed in different releases:

     SILOKIT_LAMMPS_ADD_REQUEST        neighbor->add_request(pair, flags)
                                       replaces request() + requests[i]->...
     SILOKIT_LAMMPS_GET_FIX_BY_STYLE   modify->get_fix_by_style(regex)
                                       replaces find_fix_by_style()
     SILOKIT_LAMMPS_GET_REGION_BY_ID   domain->get_region_by_id(id) replaces
                                       find_region() + regions[i]
     SILOKIT_LAMMPS_HISTORY_TYPES      Pair::transfer_history() takes the
                                       two atom types as well

   Checked: LAMMPS 20220106 (built, all tests) and 4Feb2025 (Debian 13's
   source; the adapters compile against its headers, doc/lammps_host.md).
------------------------------------------------------------------------- */

#ifndef SILOKIT_LAMMPS_COMPAT_H
#define SILOKIT_LAMMPS_COMPAT_H

#include "domain.h"
#include "fix.h"
#include "modify.h"
#include "neigh_request.h"
#include "neighbor.h"
#include "pair.h"
#include "region.h"

#include <string>

// the parameter list of Pair::transfer_history(): FixNeighHistory calls it
// when it hands a pair's history from i to j (with `nondefault_history_transfer`).
// Declaring the other list would hide the host's function instead of
// overriding it, and the history would be copied without its sign change:
// the pair declares it with `override`, so a wrong list fails to compile.
#ifdef SILOKIT_LAMMPS_HISTORY_TYPES
#define SILOKIT_TRANSFER_HISTORY_PARAMS double *source, double *target, int, int
#else
#define SILOKIT_TRANSFER_HISTORY_PARAMS double *source, double *target
#endif

namespace silokit_lammps {

// a half neighbor list of `pair` with radii (size) and per-pair history
inline void request_size_history_list(LAMMPS_NS::Neighbor *neighbor, LAMMPS_NS::Pair *pair,
                                      int instance)
{
#ifdef SILOKIT_LAMMPS_ADD_REQUEST
  (void) instance;    // add_request() takes the pair's own instance_me
  neighbor->add_request(pair, LAMMPS_NS::NeighConst::REQ_SIZE | LAMMPS_NS::NeighConst::REQ_HISTORY);
#else
  const int irequest = neighbor->request(pair, instance);
  neighbor->requests[irequest]->size = 1;
  neighbor->requests[irequest]->history = 1;
#endif
}

// the fix with this ID, or nullptr (find_fix() has not changed: here so
// that the adapters look fixes up one way)
inline LAMMPS_NS::Fix *fix_by_id(LAMMPS_NS::Modify *modify, const std::string &id)
{
  const int ifix = modify->find_fix(id);
  return ifix < 0 ? nullptr : modify->fix[ifix];
}

// the first fix whose style matches `pattern` (utils::strmatch), or nullptr
inline LAMMPS_NS::Fix *first_fix_by_style(LAMMPS_NS::Modify *modify, const char *pattern)
{
#ifdef SILOKIT_LAMMPS_GET_FIX_BY_STYLE
  const auto fixes = modify->get_fix_by_style(pattern);
  return fixes.empty() ? nullptr : fixes.front();
#else
  const int ifix = modify->find_fix_by_style(pattern);
  return ifix < 0 ? nullptr : modify->fix[ifix];
#endif
}

// the region with this ID, or nullptr
inline LAMMPS_NS::Region *region_by_id(LAMMPS_NS::Domain *domain, const std::string &id)
{
#ifdef SILOKIT_LAMMPS_GET_REGION_BY_ID
  return domain->get_region_by_id(id);
#else
  const int iregion = domain->find_region(id);
  return iregion < 0 ? nullptr : domain->regions[iregion];
#endif
}

}    // namespace silokit_lammps

#endif
