/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   Geometry of a flat plate with an orifice, as met by a sphere: the point
   of the plate nearest to the sphere's centre, and the wall velocity of a
   plate that rotates about the orifice axis. Plain functions of plain
   numbers, free of LIGGGHTS types, so that fix wall/gran/rotating only
   calls them and they can be reused by a later port.

   The plate is the plane through `centre` normal to the unit vector
   `axis`, of zero thickness, with a hole of radius R = D/2 centred on the
   axis. In 3D the hole is a disc. In 2D (every centre in the plane z = 0
   and the axis in it) the same formula gives a slot of width D: the
   in-plane offset from the axis is then the offset along the one in-plane
   direction. Split the centre's offset from the axis point into its
   height h along the axis and its in-plane part u, of length s = |u|:

   - s >= R: the nearest point is the foot of the perpendicular on the
     plane, at distance |h|.
   - s < R: the nearest point of the plate is on the rim, the point of the
     rim circle in the direction of u, at distance sqrt((R - s)^2 + h^2).

   At s = R both give the foot point and the distance |h|: a grain rolling
   from the plate over the rim feels no jump in force or direction. Over
   the hole, a grain can only touch the rim edge, from above or below: it
   cannot tunnel, since the rim is a line it has to pass at a distance. A
   grain centred exactly on the axis (s = 0) touches the whole rim circle at
   once, which only happens for a grain wider than the hole; the rim point
   is then taken in the first in-plane direction (documented in
   doc/fix_wall_gran_rotating.md).
------------------------------------------------------------------------- */

#ifndef SILOKIT_ORIFICE_PLATE_H
#define SILOKIT_ORIFICE_PLATE_H

#include <cmath>

namespace silokit {

struct PlateContact {
  double distance;      // from the sphere's centre to the nearest plate point
  double to_plate[3];   // that point minus the centre (length `distance`)
  double point[3];      // the nearest plate point
};

// The unit vector of `axis` that the in-plane direction falls back to when
// a centre sits on the axis: any vector normal to the axis will do.
inline void any_normal_to(const double *axis, double *normal)
{
  // cross the axis with the coordinate direction least parallel to it
  int k = 0;
  for (int j = 1; j < 3; ++j)
    if (std::fabs(axis[j]) < std::fabs(axis[k])) k = j;
  double e[3] = {0.0, 0.0, 0.0};
  e[k] = 1.0;
  normal[0] = axis[1]*e[2] - axis[2]*e[1];
  normal[1] = axis[2]*e[0] - axis[0]*e[2];
  normal[2] = axis[0]*e[1] - axis[1]*e[0];
  const double length = std::sqrt(normal[0]*normal[0] + normal[1]*normal[1] + normal[2]*normal[2]);
  for (int j = 0; j < 3; ++j) normal[j] /= length;
}

// Nearest point of the plate (hole radius `hole_radius` >= 0) to `x`.
inline PlateContact nearest_plate_point(const double *x, const double *centre,
                                        const double *axis, double hole_radius)
{
  double offset[3], in_plane[3];
  for (int j = 0; j < 3; ++j) offset[j] = x[j] - centre[j];
  const double height = offset[0]*axis[0] + offset[1]*axis[1] + offset[2]*axis[2];
  for (int j = 0; j < 3; ++j) in_plane[j] = offset[j] - height*axis[j];
  const double s = std::sqrt(in_plane[0]*in_plane[0] + in_plane[1]*in_plane[1] +
                             in_plane[2]*in_plane[2]);

  PlateContact contact;
  if (s >= hole_radius) {   // over the plate: the foot of the perpendicular
    for (int j = 0; j < 3; ++j) {
      contact.to_plate[j] = -height*axis[j];
      contact.point[j] = x[j] + contact.to_plate[j];
    }
    contact.distance = std::fabs(height);
    return contact;
  }
  // over the hole: the rim point in the direction of the centre
  double direction[3];
  if (s > 0.0) {
    for (int j = 0; j < 3; ++j) direction[j] = in_plane[j]/s;
  } else {
    any_normal_to(axis, direction);
  }
  for (int j = 0; j < 3; ++j) {
    contact.point[j] = centre[j] + hole_radius*direction[j];
    contact.to_plate[j] = contact.point[j] - x[j];
  }
  contact.distance = std::sqrt((hole_radius - s)*(hole_radius - s) + height*height);
  return contact;
}

// Velocity of the plate point `point` when the plate turns at angular
// velocity `omega` (rad/s, right-handed about `axis`) about the axis
// through `centre`: omega axis x (point - centre).
inline void plate_velocity(const double *point, const double *centre, const double *axis,
                           double omega, double *velocity)
{
  const double r[3] = {point[0] - centre[0], point[1] - centre[1], point[2] - centre[2]};
  velocity[0] = omega*(axis[1]*r[2] - axis[2]*r[1]);
  velocity[1] = omega*(axis[2]*r[0] - axis[0]*r[2]);
  velocity[2] = omega*(axis[0]*r[1] - axis[1]*r[0]);
}

}  // namespace silokit

#endif
