/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   The nearest periodic images of a grain, for the fixes that place new
   grains among old ones (fix reinject, fix insert/rain2d): a spot next to
   a periodic side has the grains just across the other side as
   neighbours, and a test that sees only the grains themselves would
   place a grain on top of one of their images.
------------------------------------------------------------------------- */

#ifndef SILOKIT_PERIODIC_IMAGES_H
#define SILOKIT_PERIODIC_IMAGES_H

#include <vector>

namespace silokit {

struct Shift { double d[3]; };

// The shifts from a grain to its nearest periodic images: every sum of
// -1, 0 or +1 times each periodic edge vector of the box but the zero one.
// `h` is the host's Domain::h (xprd, yprd, zprd, yz, xz, xy), so the edge
// vectors are a = (xprd, 0, 0), b = (xy, yprd, 0), c = (xz, yz, zprd), as
// for a triclinic box (an orthogonal one has the tilts 0). In 2D the third
// dimension is not a direction grains move in, and gets no images.
inline std::vector<Shift> periodic_image_shifts(const int *periodicity, const double *h,
                                                bool two_d)
{
  const double edge[3][3] = { { h[0], 0.0, 0.0 }, { h[5], h[1], 0.0 }, { h[4], h[3], h[2] } };
  int reach[3];
  for (int k = 0; k < 3; ++k) reach[k] = periodicity[k] && !(two_d && k == 2) ? 1 : 0;
  std::vector<Shift> shifts;
  for (int i = -reach[0]; i <= reach[0]; ++i)
    for (int j = -reach[1]; j <= reach[1]; ++j)
      for (int l = -reach[2]; l <= reach[2]; ++l) {
        if (i == 0 && j == 0 && l == 0) continue;
        Shift shift;
        for (int k = 0; k < 3; ++k) shift.d[k] = i*edge[0][k] + j*edge[1][k] + l*edge[2][k];
        shifts.push_back(shift);
      }
  return shifts;
}

}  // namespace silokit

#endif
