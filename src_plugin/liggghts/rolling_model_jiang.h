/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   rolling_friction jiang: rolling resistance after Jiang, Yu & Harris (2005)
   as used by Magalhaes et al. (2014), eq. 1. Documentation:
   doc/rolling_friction_jiang.md. The law itself is in rolling_law_jiang.h.

     k_r  = a k_n l_c^2        (a: rollingStiffnessFactor, default 1)
     mu_r = b mu  l_c          (b: rollingFrictionFactor,  default 1)
     tau  = -k_r delta_r, capped at mu_r f_el

   k_n is the normal model's stiffness at this contact (its secant stiffness
   f_el/delta_n for non-linear models), f_el = k_n delta_n its elastic normal
   force (no damping, no cohesion), mu = coefficientFriction.
------------------------------------------------------------------------- */

#ifdef ROLLING_MODEL
ROLLING_MODEL(ROLLING_JIANG,jiang,7)
#else
#ifndef ROLLING_MODEL_JIANG_H_
#define ROLLING_MODEL_JIANG_H_

#include "contact_models.h"
#include "rolling_model_base.h"
#include "rolling_law_jiang.h"
#include "global_properties.h"
#include "domain.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "modify.h"
#include "update.h"
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

namespace MODEL_PARAMS
{
  // Absolute contact length l_c per type pair: required in the fixed-length
  // mode, where 0 switches rolling resistance off for that pair (k_r = mu_r
  // = 0), so that one pair style can give it to some contacts only (e.g. the
  // grains on a substrate, doc/pile2d.md); optional with l_c from the
  // overlap, where a pair given l_c > 0 keeps that fixed length.
  inline MatrixProperty* createRollingContactLength(PropertyRegistry & registry,
                                                    const char * caller, bool)
  {
    MatrixProperty * contact_length =
      createPerTypePairProperty(registry, "rollingContactLength", caller);
    const int max_type = registry.max_type();
    for (int i = 1; i <= max_type; i++)
      for (int j = 1; j <= max_type; j++)
        if (!(contact_length->data[i][j] >= 0.0)) {
          std::ostringstream message;
          message << "rolling_friction jiang: rollingContactLength must be >= 0 "
                  << "(0: no rolling resistance for that pair) for every type pair (types "
                  << i << " " << j << " have " << contact_length->data[i][j] << ")";
          registry.getLAMMPS()->error->all(FLERR, message.str().c_str());
        }
    return contact_length;
  }
}

namespace LIGGGHTS {
namespace ContactModels
{
  using namespace LAMMPS_NS;

  template<>
  class RollingModel<ROLLING_JIANG> : public RollingModelBase
  {
  public:
    RollingModel(class LAMMPS * lmp, IContactHistorySetup * hsetup, class ContactModelBase * c) :
        RollingModelBase(lmp, hsetup, c),
        coefficient_friction(nullptr), fixed_contact_length(nullptr), rolling_damping_ratio(nullptr),
        stiffness_factor(1.0), friction_factor(1.0),
        contact_length_from_overlap(false), contact_length_from_depth(false), rolling_damping(false),
        fixed_pairs_reported(false)
    {
      // accumulated relative rolling angle, a vector in the tangent plane;
      // newton flag "1": it changes sign when i and j swap
      history_offset = hsetup->add_history_value("jiang_rolling_angle_x", "1");
      hsetup->add_history_value("jiang_rolling_angle_y", "1");
      hsetup->add_history_value("jiang_rolling_angle_z", "1");
      // the last time step that advanced the spring (see isContinuing)
      hsetup->add_history_value("jiang_last_step", "0");
      // k_r at that step (see silokit::jiang::adapt_to_stiffness)
      hsetup->add_history_value("jiang_stiffness", "0");
    }

    void registerSettings(Settings & settings)
    {
      settings.registerDoubleSetting("rollingStiffnessFactor", stiffness_factor, 1.0);
      settings.registerDoubleSetting("rollingFrictionFactor", friction_factor, 1.0);
      settings.registerOnOff("contactLengthFromOverlap", contact_length_from_overlap, false);
      settings.registerOnOff("contactLengthFromDepth", contact_length_from_depth, false);
      settings.registerOnOff("rollingDamping", rolling_damping, false);
    }

    inline void postSettings(IContactHistorySetup *, ContactModelBase *)
    {
      // DoubleSetting takes any text through atof: check what it made of it
      if (!(stiffness_factor > 0.0))
        error->all(FLERR, "rolling_friction jiang: rollingStiffnessFactor must be > 0");
      if (!(friction_factor > 0.0))
        error->all(FLERR, "rolling_friction jiang: rollingFrictionFactor must be > 0");
      if (contact_length_from_overlap && contact_length_from_depth)
        error->all(FLERR, "rolling_friction jiang: contactLengthFromOverlap and contactLengthFromDepth "
                          "exclude each other (l_c is the overlap's chord or its depth)");
    }

    void connectToProperties(PropertyRegistry & registry)
    {
      registry.registerProperty("coeffFrict", &MODEL_PARAMS::createCoeffFrict);
      registry.connect("coeffFrict", coefficient_friction, "rolling_friction jiang");
      // fixed mode needs rollingContactLength; with l_c from the overlap it
      // is optional, and a type pair given a positive value keeps that
      // fixed l_c (e.g. grains on a substrate, doc/pile2d.md)
      const bool geometric = contact_length_from_overlap || contact_length_from_depth;
      if (!geometric || modify->find_fix_property("rollingContactLength", "property/global",
                                                  "peratomtypepair", 0, 0, "rolling_friction jiang",
                                                  false)) {
        registry.registerProperty("rollingContactLength", &MODEL_PARAMS::createRollingContactLength);
        registry.connect("rollingContactLength", fixed_contact_length, "rolling_friction jiang");
        if (geometric && !fixed_pairs_reported) reportFixedPairs(registry.max_type());
      }
      if (rolling_damping) {
        registry.registerProperty("coeffRollVisc", &MODEL_PARAMS::createCoeffRollVisc);
        registry.connect("coeffRollVisc", rolling_damping_ratio, "rolling_friction jiang");
      }
      if (force->cg_active())
        error->cg(FLERR, "rolling_friction jiang");
    }

    void surfacesIntersect(SurfacesIntersectData & sidata, ForceData & i_forces, ForceData & j_forces)
    {
      if (sidata.contact_flags) *sidata.contact_flags |= CONTACT_ROLLING_MODEL;

      const int itype = sidata.itype;
      const int jtype = sidata.jtype;
      const double * const normal = sidata.en;

      // relative rotation rate, its twisting part removed. A wall turns only
      // when its fix says so (omega_j set, e.g. fix wall/gran/rotating);
      // stock walls leave omega_j null.
      double relative_omega[3];
      for (int k = 0; k < 3; ++k)
        relative_omega[k] = sidata.omega_j ? sidata.omega_i[k] - sidata.omega_j[k]
                                           : sidata.omega_i[k];
      silokit::jiang::remove_normal_component(relative_omega, normal);

      const silokit::jiang::RollingSpring spring = silokit::jiang::rolling_spring(
          sidata.kn, sidata.deltan, coefficient_friction[itype][jtype], contactLength(sidata),
          stiffness_factor, friction_factor);
      const double stiffness = spring.stiffness;

      // The force call that sets up a run (after `run` or `read_restart`)
      // must not advance the spring: it returns the torque of the stored
      // angle, like stock `tangential history`, so that a run split in two
      // or restarted continues exactly.
      const bool update_history = sidata.computeflag && sidata.shearupdate;
      double * const history = &sidata.contact_history[history_offset];
      double rolling_angle[3] = { 0.0, 0.0, 0.0 };
      if (isContinuing(history, update_history))
        for (int k = 0; k < 3; ++k) rolling_angle[k] = history[k];
      double torque[3];
      const bool rolls = silokit::jiang::step_rolling_spring(
          rolling_angle, history[4], normal, relative_omega, spring, update->dt, update_history,
          torque);

      if (update_history) {
        for (int k = 0; k < 3; ++k) history[k] = rolling_angle[k];
        history[3] = static_cast<double>(update->ntimestep);
        history[4] = stiffness;
      }

      if (rolling_damping && !rolls)
        silokit::jiang::add_rolling_damping(rolling_damping_ratio[itype][jtype],
                                            rollingInertia(sidata), stiffness, relative_omega,
                                            torque);

      for (int k = 0; k < 3; ++k) {
        i_forces.delta_torque[k] += torque[k];
        j_forces.delta_torque[k] -= torque[k];
      }
    }

    void surfacesClose(SurfacesCloseData & scdata, ForceData &, ForceData &)
    {
      // the contact has opened: the next one starts from an unloaded spring
      if (scdata.contact_flags) *scdata.contact_flags &= ~CONTACT_ROLLING_MODEL;
      double * const history = &scdata.contact_history[history_offset];
      for (int k = 0; k < 5; ++k) history[k] = 0.0;
    }

    void beginPass(SurfacesIntersectData &, ForceData &, ForceData &) {}
    void endPass(SurfacesIntersectData &, ForceData &, ForceData &) {}

  private:
    double ** coefficient_friction;
    double ** fixed_contact_length;
    double ** rolling_damping_ratio;
    double stiffness_factor;
    double friction_factor;
    bool contact_length_from_overlap;   // l_c = the chord (2D) or diameter (3D) of the overlap
    bool contact_length_from_depth;     // l_c = the overlap depth delta_n
    bool rolling_damping;
    bool fixed_pairs_reported;          // reportFixedPairs has run
    int history_offset;

    // With l_c from the overlap, a type pair given rollingContactLength > 0
    // keeps that fixed l_c. A deck written before that rule may hold a
    // placeholder there: say which pairs keep a fixed l_c, once, on rank 0.
    void reportFixedPairs(int max_type)
    {
      fixed_pairs_reported = true;
      std::ostringstream pairs;
      int count = 0;
      for (int i = 1; i <= max_type; i++)
        for (int j = i; j <= max_type; j++)
          if (fixed_contact_length[i][j] > 0.0)
            pairs << (count++ ? ", " : "") << i << "-" << j << " (" << fixed_contact_length[i][j] << ")";
      if (count == 0 || comm->me != 0) return;
      std::ostringstream message;
      message << "rolling_friction jiang: " << (contact_length_from_depth ? "contactLengthFromDepth"
                                                                           : "contactLengthFromOverlap")
              << " is on, but type pair" << (count > 1 ? "s " : " ") << pairs.str()
              << " keep" << (count > 1 ? "" : "s") << " the fixed l_c of rollingContactLength "
              << "(give 0 for l_c from the contact)";
      error->warning(FLERR, message.str().c_str());
    }

    // True when the stored rolling angle belongs to this contact: it was
    // advanced in the previous step (the current one, for a call that does
    // not advance it). LIGGGHTS 3.8 keeps the history of a pair that stopped
    // touching until the next neighbor-list build (surfacesClose is only
    // called within neigh_modify contact_distance_factor > 1), so a contact
    // that opens and closes again between two builds would otherwise start
    // from a stale, loaded spring. Exact in doubles for any step count below
    // 2^53; `reset_timestep` makes every spring start unloaded again.
    inline bool isContinuing(const double * history, bool advancing) const
    {
      const double step = static_cast<double>(update->ntimestep);
      return history[3] == (advancing ? step - 1.0 : step);
    }

    inline double contactLength(const SurfacesIntersectData & sidata) const
    {
      const double contact_length = fixed_contact_length ? fixed_contact_length[sidata.itype][sidata.jtype]
                                                         : 0.0;
      const bool fixed_here = !(contact_length_from_depth || contact_length_from_overlap) ||
                              contact_length > 0.0;
      if (!fixed_here) {
        // the contact's deformation itself: the normal overlap delta_n
        if (contact_length_from_depth) return std::max(sidata.deltan, 0.0);
        return sidata.is_wall
          ? silokit::jiang::wall_overlap_contact_length(sidata.radi, sidata.deltan)
          : silokit::jiang::overlap_contact_length(sidata.radi, sidata.radj, sidata.r);
      }

      const double smallest_diameter =
        2.0*(sidata.is_wall ? sidata.radi : std::min(sidata.radi, sidata.radj));
      if (contact_length > smallest_diameter) {
        std::ostringstream message;
        message << "rolling_friction jiang: rollingContactLength " << contact_length
                << " for types " << sidata.itype << " " << sidata.jtype
                << " is larger than the diameter " << smallest_diameter
                << " of a grain in contact";
        // only the rank that meets this contact knows of it: error->one,
        // which our patch of LIGGGHTS makes flush the screen and the log
        // before it aborts (doc/liggghts_quirks.md)
        error->one(FLERR, message.str().c_str());
      }
      return contact_length;
    }

    // Reduced moment of inertia for rolling about the contact point: disc
    // (2D) 1/2 m r^2 + m r^2, sphere 2/5 m r^2 + m r^2, as in epsd2/epsd3.
    inline double rollingInertia(const SurfacesIntersectData & sidata) const
    {
      const double factor = domain->dimension == 2 ? 1.5 : 1.4;
      const double inertia_i = factor*sidata.mi*sidata.radi*sidata.radi;
      if (sidata.is_wall) return inertia_i;
      const double inertia_j = factor*sidata.mj*sidata.radj*sidata.radj;
      return inertia_i*inertia_j/(inertia_i + inertia_j);
    }
  };
}
}

#endif // ROLLING_MODEL_JIANG_H_
#endif
