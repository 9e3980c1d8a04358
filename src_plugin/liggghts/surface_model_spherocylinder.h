/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   surface spherocylinder: the contact geometry of two rods (atom_style
   spherocylinder) for pair_style gran and for the walls that know rods,
   so that LIGGGHTS' normal and tangential models run unchanged on it
   (Pongo et al. 2022, sec. II: closest points of the two core segments,
   overlap d - distance, normal along the line of closest points).

     pair_style gran model hooke/stiffness tangential history surface spherocylinder

   What the stock models need from a surface model is what
   SurfaceModel<SURFACE_DEFAULT> (surface_model_default.h) fills for
   spheres: the unit normal en (from j to i), the overlap deltan, the
   normal relative velocity vn and the tangential relative velocity
   vtr at the contact; with NONSPHERICAL_ACTIVE_FLAG (CMakeLists.txt) they
   also take the torque arms from sidata.contact_point, which for a rod is
   not on the line of centres.

   - beginPass (once per force evaluation): the axis of every rod, local
     and ghost, from its quaternion, so that each of the many pairs of the
     list does not compute it again.
   - checkSurfaceIntersect (the narrow phase after the bounding-sphere
     test of PairGranBase): whether the core segments come closer than
     the sum of the rods' radii and, for a pair that touches, the contact
     (rods_touching, spherocylinder_geometry.h: the distance of the two
     core lines rejects some of the pairs that do not touch cheaply, and
     the closest points of the others are computed once). The pair is
     taken in the order of the atom tags, so that the two ranks that
     compute a pair crossing a processor boundary (newton off, as history
     needs) find the same points to the last bit.
   - surfacesIntersect: en, deltan and the contact point (on the line of
     closest points, half the overlap inside rod j's surface: for equal
     radii the midpoint of the two closest core points) are set again
     here, since PairGranBase overwrites en with the line of centres
     between the two calls. The relative velocity is that of the two
     material points at the contact point, v + omega x (contact - x).
   - walls (sidata.is_wall): the wall fix has resolved the contact
     (contact point and delta from the wall point to the core point,
     fix_wall_gran_base.h makes en and the distance from them); the model
     adds the relative velocity at the contact point.
------------------------------------------------------------------------- */

#ifdef SURFACE_MODEL
SURFACE_MODEL(SURFACE_SPHEROCYLINDER,spherocylinder,7)
#else
#ifndef SURFACE_MODEL_SPHEROCYLINDER_H_
#define SURFACE_MODEL_SPHEROCYLINDER_H_

#include "contact_models.h"
#include "surface_model_base.h"
#include "atom.h"
#include "atom_vec_spherocylinder.h"
#include "error.h"
#include "math_extra.h"
#include "spherocylinder_geometry.h"

#include <vector>

#ifndef NONSPHERICAL_ACTIVE_FLAG
#error "surface spherocylinder needs NONSPHERICAL_ACTIVE_FLAG (see CMakeLists.txt)"
#endif

namespace LIGGGHTS {
namespace ContactModels
{
  template<>
  class SurfaceModel<SURFACE_SPHEROCYLINDER> : public SurfaceModelBase
  {
  public:
    SurfaceModel(LAMMPS *lmp, IContactHistorySetup *hsetup, class ContactModelBase *cmb) :
      SurfaceModelBase(lmp, hsetup, cmb)
    {
      if (!atom->quaternion || !atom->shape)
        error->all(FLERR, "surface spherocylinder needs atom_style spherocylinder");
    }

    void registerSettings(Settings &) {}
    void postSettings(IContactHistorySetup *, ContactModelBase *) {}
    void connectToProperties(PropertyRegistry &) {}

    bool checkSurfaceIntersect(SurfacesIntersectData &sidata)
    {
      if (sidata.is_wall) return true;
      const int i = sidata.i, j = sidata.j;
      // first the rod of the lower tag
      const bool swapped = atom->tag[i] > atom->tag[j];
      const int first = swapped ? j : i, second = swapped ? i : j;
      const double *centre1 = atom->x[first], *axis1 = &axes_[3*first];
      const double *centre2 = atom->x[second], *axis2 = &axes_[3*second];
      const double h1 = half_segment(first), h2 = half_segment(second);
      const double r1 = radius_of(first), r2 = radius_of(second);
      silokit::RodContact contact;
      if (!silokit::rods_touching(centre1, axis1, h1, r1, centre2, axis2, h2, r2, contact)) return false;
      // en from j to i, as for spheres
      const double sign = swapped ? -1.0 : 1.0;
      for (int k = 0; k < 3; ++k) {
        normal_[k] = sign*contact.normal[k];
        contact_point_[k] = contact.point[k];
      }
      overlap_ = contact.overlap;
      return true;
    }

    void surfacesIntersect(SurfacesIntersectData &sidata, ForceData &, ForceData &)
    {
      const int i = sidata.i;
      double **x = atom->x;
      if (!sidata.is_wall) {
        for (int k = 0; k < 3; ++k) {
          sidata.en[k] = normal_[k];
          sidata.contact_point[k] = contact_point_[k];
        }
        sidata.deltan = overlap_;
      } else {
        sidata.deltan = sidata.radi - sidata.r;
      }
      sidata.is_non_spherical = true;

      // velocities of the two material points at the contact point
      double arm_i[3], spin_i[3], velocity[3];
      for (int k = 0; k < 3; ++k) arm_i[k] = sidata.contact_point[k] - x[i][k];
      MathExtra::cross3(sidata.omega_i, arm_i, spin_i);
      for (int k = 0; k < 3; ++k) velocity[k] = sidata.v_i[k] + spin_i[k] - sidata.v_j[k];
      if (!sidata.is_wall) {
        double arm_j[3], spin_j[3];
        for (int k = 0; k < 3; ++k) arm_j[k] = sidata.contact_point[k] - x[sidata.j][k];
        MathExtra::cross3(sidata.omega_j, arm_j, spin_j);
        for (int k = 0; k < 3; ++k) velocity[k] -= spin_j[k];
      }
      const double vn = velocity[0]*sidata.en[0] + velocity[1]*sidata.en[1] + velocity[2]*sidata.en[2];
      sidata.vn = vn;
      sidata.vtr1 = velocity[0] - vn*sidata.en[0];
      sidata.vtr2 = velocity[1] - vn*sidata.en[1];
      sidata.vtr3 = velocity[2] - vn*sidata.en[2];
      // no rolling model acts on rods (the spin part is in vtr already)
      sidata.wr1 = sidata.wr2 = sidata.wr3 = 0.0;
      sidata.cri = sidata.radi - 0.5*sidata.deltan;
      sidata.crj = sidata.radj - 0.5*sidata.deltan;
      sidata.P_diss = 0.0;
    }

    void endSurfacesIntersect(SurfacesIntersectData &, TriMesh *, double * const) {}
    void surfacesClose(SurfacesCloseData &, ForceData &, ForceData &) {}
    void beginPass(SurfacesIntersectData &, ForceData &, ForceData &)
    {
      const int all = atom->nlocal + atom->nghost;
      axes_.resize(3*static_cast<size_t>(all));
      for (int i = 0; i < all; ++i)
        AtomVecSpherocylinder::axis_of_quaternion(atom->quaternion[i], &axes_[3*i]);
    }
    void endPass(SurfacesIntersectData &, ForceData &, ForceData &) {}
    void tally_pp(double, int, int, int) {}
    void tally_pw(double, int, int, int) {}

  private:
    // the axis (body x) of every local and ghost rod, 3 per atom, from the
    // quaternions at the start of the force evaluation (beginPass)
    std::vector<double> axes_;
    // shape holds the half extents L/2, d/2, d/2
    double radius_of(int i) const { return atom->shape[i][1]; }
    double half_segment(int i) const { return atom->shape[i][0] - atom->shape[i][1]; }

    // the contact checkSurfaceIntersect found, for surfacesIntersect
    double normal_[3];
    double contact_point_[3];
    double overlap_;
  };
}
}

#endif
#endif
