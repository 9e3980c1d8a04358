/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   pair_style granular/jiang for LAMMPS (a plugin style, loaded with
   `plugin load silokit_lammps.so`): spheres with LIGGGHTS' contact law
   (`model hooke/stiffness` or `model hooke`, `tangential history`;
   core/contact_law.h) and Jiang's rolling resistance (`rolling_friction
   jiang`; core/rolling_law_jiang.h), so that a contact computes the same
   numbers in both hosts. Documentation: doc/pair_granular_jiang.md.

   Derived from LAMMPS' core Pair class, not from PairGranular (whose
   models and history are private in LAMMPS 20220106 and were rewritten
   in 2023): per-pair history through the core FixNeighHistory, as
   LAMMPS' gran/hooke/history keeps it.
------------------------------------------------------------------------- */

#ifndef SILOKIT_LAMMPS_PAIR_GRANULAR_JIANG_H
#define SILOKIT_LAMMPS_PAIR_GRANULAR_JIANG_H

#include "pair.h"

#include "contact_law_keywords.h"
#include "contact_sample.h"
#include "lammps_compat.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class PairGranularJiang : public Pair {
 public:
  // the coefficients of one type pair (pair_coeff I J ...): the contact-law
  // keywords it shares with fix wall/gran/rotating; plain data, written to
  // restart files as it is
  using Coeff = silokit_lammps::ContactLawSettings;
  // per-pair history: tangential spring (3), rolling angle (3), k_r of the
  // last step (1)
  enum { HISTORY_SHEAR = 0, HISTORY_ROLLING = 3, HISTORY_STIFFNESS = 6, HISTORY_SIZE = 7 };

  PairGranularJiang(class LAMMPS *);
  ~PairGranularJiang() override;
  void compute(int, int) override;
  void settings(int, char **) override;
  void coeff(int, char **) override;
  void init_style() override;
  double init_one(int, int) override;
  void write_restart(FILE *) override;
  void read_restart(FILE *) override;
  double single(int, int, int, int, double, double, double, double &) override;
  void transfer_history(SILOKIT_TRANSFER_HISTORY_PARAMS) override;    // lammps_compat.h
  double memory_usage() override;
  double atom2cut(int) override;
  double radii2cut(double, double) override;

  // the contacts of this rank's neighbor list that touch now, with the
  // forces of the current positions, velocities and stored history (read,
  // not advanced): what fix clog records at a clog. Under `newton off` a
  // pair with a ghost partner is listed by both ranks.
  std::vector<silokit::ContactSample> current_contacts();

 protected:
  std::vector<Coeff> coeffs;     // (ntypes+1)^2, symmetric
  int freeze_group_bit;
  int neighprev;                 // single(): where the last neighbor was found
  double *onerad_dynamic, *onerad_frozen;
  double *maxrad_dynamic, *maxrad_frozen;
  class FixDummy *fix_dummy;
  class FixNeighHistory *fix_history;

  // what one contact gives (compute and single)
  struct Result {
    double force_i[3];           // on i; j gets the opposite
    double torque_i[3], torque_j[3];
    double fn;                   // normal force, > 0 repulsive
    double ft[3];                // tangential force on i
    double vn;                   // (v_i - v_j).n
    double overlap;              // r_i + r_j - |x_i - x_j|
    double n[3];
    double rinv;
  };
  void contact(int i, int j, const Coeff &c, double *history, bool advance, Result &out);

  int stride;                    // ntypes + 1, the row length of coeffs
  Coeff &coeff_of(int i, int j) { return coeffs[i * stride + j]; }
  void allocate();
  std::string history_id() const;
};

}    // namespace LAMMPS_NS

#endif
