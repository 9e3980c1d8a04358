/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   Contact geometry of spherocylinders (rods): rod against rod, rod against
   the walls silokit uses (a plane, the inner wall of a cylinder, the flat
   plate with a circular hole of orifice_plate.h), and the mass and inertia
   of a rod. Plain functions of plain numbers, free of LIGGGHTS types, so
   that the surface model, the wall fixes and the atom style only call them,
   they are tested alone (tests/test_spherocylinder_geometry.py) and a
   later port reuses them.

   Conventions
   - Vectors are double[3]. Every direction passed in (rod axes, wall
     normals and axes) must be a unit vector: nothing is normalised here.
   - A rod is its centre c, its unit axis a, the half-length h >= 0 of its
     core segment and its radius r = d/2; with L its length end to end,
     h = (L - d)/2. Its core segment is c + t a, t in [-h, h]; t is the
     segment parameter. h = 0 is a sphere. The rod is every point within r
     of its core segment, so each contact is that of a sphere of radius r
     centred on a core point: the overlap is the sum of the radii minus the
     distance between the core points (rod-rod), r minus the distance from
     the core point to the wall (walls), and the bodies touch when it is
     > 0. This is what lets the stock normal and tangential models act on
     rods unchanged.

   Rod against rod
   1. The closest points of the two core segments minimise
      |c1 + t1 a1 - c2 - t2 a2| over [-h1, h1] x [-h2, h2] (the clamped
      solution of Vega & Lago 1994). The square is a convex quadratic: its
      stationary point when it lies in the rectangle, else its minimum on
      the edges, found by clamping and projecting from one segment onto
      the other, at most twice (each edge's minimum is an exact clamped
      projection).
   2. Parallel or antiparallel axes (|a1 x a2|^2 <= 1e-16, an angle below
      1e-8 rad) have a whole interval of closest points when their
      projections overlap: the middle of that overlap is taken on each
      segment, so that a line contact acts at its centre and exerts no
      spurious torque. Disjoint projections give the two nearest ends. The
      threshold balances the two errors in distance, both about 1e-8 times
      the rods' size: that of the general formula, which loses digits as
      1/angle, and that of the midpoint, off the true minimum by angle x h.
   3. Symmetry: the points are computed with the two rods in a fixed order
      (lexicographic on c, a, h) and handed back in the caller's order, so
      swapping rods 1 and 2 swaps the results bit for bit and flips the
      normal exactly. Two MPI ranks that each see the pair from their own
      side (newton off) then agree exactly, given the same coordinates.
   4. The contact (RodContact): the normal points from rod 2 towards rod 1
      (LIGGGHTS' en = (x_i - x_j)/|x_i - x_j| with i = rod 1); separation =
      core point 1 - core point 2 (LIGGGHTS' delta); overlap = r1 + r2 -
      distance. The contact point is in the middle of the overlap along
      the normal, at r2 - overlap/2 from core point 2 and r1 - overlap/2
      from core point 1: LIGGGHTS' sphere convention (cri = radi -
      deltan/2).
   5. Cores that meet (distance 0) have no direction between them: the
      normal is then a1 x a2 normalised (which flips with the exchange of
      the rods, as a normal from rod 2 to rod 1 must); for parallel axes it
      is the unit vector any_normal_to(a) of orifice_plate.h for the axis
      of the rod that comes first in rule 3's order, pointing from the
      other rod to that one: any_normal_to(a1) when rod 1 comes first,
      -any_normal_to(a2) otherwise.

   Rod against a wall
   A rod lying on a wall touches it along a line, and a tilted one at a
   point that moves as it tips. Each function returns up to
   max_wall_contacts contacts (WallContacts, in increasing t), each with
   its segment parameter t, the wall point nearest to its core point, the
   unit normal from that wall point to the core point, and its overlap
   r - distance; only contacts with an overlap > 0 are returned. A rod
   with h = 0 has one end point, not two: it gives the sphere's single
   contact.
   6. Plane (a point p0 and the unit normal n pointing into the allowed
      side; one-sided: the distance is signed and a core point behind the
      plane overlaps by more than r; the normal is always n). The distance
      is linear in t, so its extremes are the end points: both end points
      are contacts whenever they penetrate. A rod lying flat has two
      contacts of equal overlap at its ends (no torque); a tilted rod
      touches with its lower end, and the upper end joins continuously,
      with an overlap growing from zero, as it tips down.
   7. Inner wall of a cylinder (a point on its axis, the unit axis, radius
      Rc; the rod inside; one-sided: distance Rc - s with s the distance of
      the core point from the axis; normal towards the axis). s is convex
      along the segment, so Rc - s is concave and its minima are again the
      end points: both ends, each when it penetrates. A core point on the
      axis takes the wall point in the direction any_normal_to(axis).
   8. Plate with a hole (orifice_plate.h: the plane through `centre` normal
      to the unit `axis`, zero thickness, two-sided, hole of radius R on the
      axis). f(t) is the distance from the core point at t to the plate, as
      nearest_plate_point gives it for a sphere's centre; s(t) the core
      point's distance from the axis. The core line is over the hole where
      s < R; s^2 is a convex quadratic in t, so that is one open interval
      of the line, and the segment has at most one piece over the hole,
      between pieces over the plate. The contacts are
      (i)  each segment end point over the plate (s >= R), when it
           penetrates;
      (ii) every local minimum of f over the CLOSED piece over the hole
           (its ends included: the rim crossings, or segment end points
           over the hole), when it penetrates; a minimum at a segment end
           that lies over the plate is that end's contact of (i), not a
           second one.
      Why: over the plate f = |height|, linear, so a piece over the plate
      is held at its two ends, as in rule 6; its inner end is a rim
      crossing, which (ii) counts when f does not decrease from it into the
      hole. f is C1 at a crossing (sqrt((R - s)^2 + z^2) ~ |z| + (R -
      s)^2/(2|z|)), so: a level rod over the rim with one end over the hole
      rests on its back end and on the crossing point; tipping it forward
      moves that contact continuously into the hole, where it becomes an
      interior minimum; tipping it back keeps the crossing as the piece's
      minimum with a shrinking overlap; a level rod across the whole hole
      is held on both sides (its ends and the two crossings).
   9. The minima of rule 8 (ii) are found exactly rather than by sampling.
      Along the core line f^2 = R^2 - 2 R s + |x - centre|^2 (over the hole);
      with s^2 = m^2 + A (t - t_m)^2 (m the line's least distance from the
      axis, A = 1 - (a.axis)^2), (f^2)'' = 2 - 2 R A m^2 / s^3: f^2 is convex,
      then concave where s^3 < R A m^2, then convex again (at m = 0 the
      concave part is the kink of s on the axis). So the piece has at most
      two local minima, at most one per convex part, found by bisection on
      the sign of (f^2)' to 1e-12 h in t; a concave part contributes only
      those of its ends that are ends of the piece, where f increases into
      it; a junction between the parts is never a minimum.
   10. f = 0 (a core point in the plane of the plate, over the plate, e.g.
      a core line through the rim circle) has no direction: the normal is
      then +axis. A core point on the plate's axis takes the rim point in
      the direction any_normal_to(axis), as nearest_plate_point does.

   What rule 8 does not make continuous. Each piece over the plate is held
   at its two ends, whatever its length. When such a piece shrinks to
   nothing, its two contacts merge into one point and then one of them
   disappears (a rod end passing over the rim from the plate into the
   hole), and when a rod lying on the plate slides until its core line
   grazes the rim circle, the two crossings appear at once, each with the
   overlap of the plate under them. The total overlap jumps by one or two
   contacts' overlaps at those instants. Rule 6 has the same limit as h
   tends to 0 (two contacts, one at h = 0).

   Mass properties: a cylinder of length L - d and two hemispheres of
   radius r; about a transverse axis through the centre each hemisphere
   counts with its own moment about its centre of mass (3r/8 from its
   flat face) moved by the parallel-axis theorem to the rod's centre. L = d
   gives the sphere exactly.
------------------------------------------------------------------------- */

#ifndef SILOKIT_SPHEROCYLINDER_GEOMETRY_H
#define SILOKIT_SPHEROCYLINDER_GEOMETRY_H

#include <algorithm>
#include <cmath>
#include <utility>

#include "orifice_plate.h"

namespace silokit {

struct RodContact {
  double t1, t2;            // segment parameters of the closest core points
  double core_point1[3];    // c1 + t1 a1
  double core_point2[3];    // c2 + t2 a2
  double separation[3];     // core_point1 - core_point2
  double distance;          // |separation|
  double overlap;           // r1 + r2 - distance; the rods touch when > 0
  double normal[3];         // unit, from rod 2 towards rod 1 (rules 4, 5)
  double point[3];          // contact point, in the middle of the overlap (rule 4)
};

const int max_wall_contacts = 4;   // two ends over the plate, two minima over the hole

struct WallContact {
  double t;                 // segment parameter of the core point
  double wall_point[3];     // the wall point nearest to that core point
  double normal[3];         // unit, from the wall point towards the core point
  double overlap;           // r - distance from the wall, > 0
};

struct WallContacts {
  int count;
  WallContact contact[max_wall_contacts];   // in increasing t
};

struct MassProperties {
  double mass;
  double axial_inertia;        // about the rod's axis
  double transverse_inertia;   // about any axis normal to it through the centre
};

namespace rod_detail {

// Rule 2: below this |a1 x a2|^2 two axes count as parallel.
const double parallel_sine_squared = 1e-16;
// Rule 9: the bisection stops at this fraction of h.
const double minimum_tolerance = 1e-12;

inline double dot(const double *u, const double *v)
{
  return u[0]*v[0] + u[1]*v[1] + u[2]*v[2];
}

inline void cross(const double *u, const double *v, double *w)
{
  w[0] = u[1]*v[2] - u[2]*v[1];
  w[1] = u[2]*v[0] - u[0]*v[2];
  w[2] = u[0]*v[1] - u[1]*v[0];
}

inline void core_point(const double *centre, const double *axis, double t, double *point)
{
  for (int j = 0; j < 3; ++j) point[j] = centre[j] + t*axis[j];
}

inline double clamp(double t, double half_length)
{
  return std::max(-half_length, std::min(half_length, t));
}

// -h and h, or the single end 0 of a sphere, which must not count twice.
inline int segment_ends(double half_length, double *ends)
{
  if (half_length > 0.0) {
    ends[0] = -half_length;
    ends[1] = half_length;
    return 2;
  }
  ends[0] = 0.0;
  return 1;
}

inline double squared_distance(const double *c1, const double *a1, double t1,
                               const double *c2, const double *a2, double t2)
{
  double p1[3], p2[3], between[3];
  core_point(c1, a1, t1, p1);
  core_point(c2, a2, t2, p2);
  for (int j = 0; j < 3; ++j) between[j] = p1[j] - p2[j];
  return dot(between, between);
}

// Rule 3: true when rod 2 comes before rod 1 in the lexicographic order of
// (c, a, h); the computation then runs with the rods exchanged.
inline bool in_swapped_order(const double *c1, const double *a1, double h1,
                             const double *c2, const double *a2, double h2)
{
  const double rod1[7] = {c1[0], c1[1], c1[2], a1[0], a1[1], a1[2], h1};
  const double rod2[7] = {c2[0], c2[1], c2[2], a2[0], a2[1], a2[2], h2};
  return std::lexicographical_compare(rod2, rod2 + 7, rod1, rod1 + 7);
}

// Rule 2. Along axis 1, measured from c1, segment 2 covers
// [-e1 - |b| h2, -e1 + |b| h2]; the middle of its overlap with [-h1, h1]
// (or of the gap between them, which clamps to the nearest end) gives t1,
// and t2 is the projection of that point on segment 2.
inline void closest_points_parallel(const double *c1, const double *a1, double h1,
                                    const double *c2, const double *a2, double h2,
                                    double &t1, double &t2)
{
  double offset[3];
  for (int j = 0; j < 3; ++j) offset[j] = c1[j] - c2[j];
  const double b = dot(a1, a2), e1 = dot(a1, offset), e2 = dot(a2, offset);
  const double reach2 = std::fabs(b)*h2;
  const double overlap_begin = std::max(-h1, -e1 - reach2);
  const double overlap_end = std::min(h1, -e1 + reach2);
  t1 = clamp(0.5*(overlap_begin + overlap_end), h1);
  t2 = clamp(e2 + b*t1, h2);
}

// Rule 1 for axes that are not parallel. The stationary point's t1,
// (b e2 - e1)/sin^2, is clamped into segment 1 and its point projected
// on segment 2; when that projection falls outside segment 2 it is
// clamped, and its point projected back on segment 1 (clamped). For the
// strictly convex square of the distance this ends on its minimum over
// the rectangle |t1| <= h1, |t2| <= h2 (Ericson, Real-Time Collision
// Detection, 2005, sec. 5.1.9): the best of its four edges, with at most
// two projections instead of four edge points and their distances. At
// the stationary point t2 is the projection of point t1 on axis 2;
// taking it so (rather than from its own formula) keeps the pair
// consistent when the formula for t1 loses digits at small angles.
inline void closest_points_skew(const double *c1, const double *a1, double h1,
                                const double *c2, const double *a2, double h2,
                                double sine_squared, double &t1, double &t2)
{
  double offset[3];
  for (int j = 0; j < 3; ++j) offset[j] = c1[j] - c2[j];
  const double b = dot(a1, a2), e1 = dot(a1, offset), e2 = dot(a2, offset);
  t1 = clamp((b*e2 - e1)/sine_squared, h1);
  const double t2_projected = e2 + b*t1;
  t2 = clamp(t2_projected, h2);
  if (t2 != t2_projected) t1 = clamp(b*t2 - e1, h1);
}

inline void closest_points_in_given_order(const double *c1, const double *a1, double h1,
                                          const double *c2, const double *a2, double h2,
                                          double &t1, double &t2)
{
  double normal[3];
  cross(a1, a2, normal);
  const double sine_squared = dot(normal, normal);
  if (sine_squared <= parallel_sine_squared)
    closest_points_parallel(c1, a1, h1, c2, a2, h2, t1, t2);
  else
    closest_points_skew(c1, a1, h1, c2, a2, h2, sine_squared, t1, t2);
}

// Rule 5: the normal between cores that meet.
inline void normal_of_meeting_cores(const double *a1, const double *a2, double *normal)
{
  cross(a1, a2, normal);
  const double sine_squared = dot(normal, normal);
  if (sine_squared <= parallel_sine_squared) {
    any_normal_to(a1, normal);
    return;
  }
  const double length = std::sqrt(sine_squared);
  for (int j = 0; j < 3; ++j) normal[j] /= length;
}

// Rules 1 and 2 after a cheap test: false when the lines of the two cores
// are `reach` or more apart (skew cores are at least as far apart as
// their lines, |(c1 - c2).(a1 x a2)|/|a1 x a2|), else the closest points.
// In the settled bed of bench/spherocylinder_cost.py this rejects half of
// the pairs of LIGGGHTS' bounding-sphere list, 6 % of the pruned list's
// (spherocylinder_list_pruning.h; a fifth of its pairs that do not touch).
inline bool closest_points_unless_lines_apart(const double *c1, const double *a1, double h1,
                                              const double *c2, const double *a2, double h2,
                                              double reach, double &t1, double &t2)
{
  double normal[3];
  cross(a1, a2, normal);
  const double sine_squared = dot(normal, normal);
  if (sine_squared <= parallel_sine_squared) {
    closest_points_parallel(c1, a1, h1, c2, a2, h2, t1, t2);
    return true;
  }
  double offset[3];
  for (int j = 0; j < 3; ++j) offset[j] = c1[j] - c2[j];
  const double line_gap = dot(offset, normal);
  if (line_gap*line_gap >= reach*reach*sine_squared) return false;
  closest_points_skew(c1, a1, h1, c2, a2, h2, sine_squared, t1, t2);
  return true;
}

// The core points of contact.t1 and contact.t2 and their separation.
inline void place_core_points(const double *c1, const double *a1, const double *c2,
                              const double *a2, RodContact &contact)
{
  core_point(c1, a1, contact.t1, contact.core_point1);
  core_point(c2, a2, contact.t2, contact.core_point2);
  for (int j = 0; j < 3; ++j)
    contact.separation[j] = contact.core_point1[j] - contact.core_point2[j];
}

// Rules 4 and 5: distance, overlap, normal and contact point from the
// separation of the core points.
inline void complete_contact(const double *a1, double r1, const double *a2, double r2,
                             RodContact &contact)
{
  contact.distance = std::sqrt(dot(contact.separation, contact.separation));
  contact.overlap = r1 + r2 - contact.distance;
  if (contact.distance > 0.0) {
    for (int j = 0; j < 3; ++j) contact.normal[j] = contact.separation[j]/contact.distance;
  } else {
    normal_of_meeting_cores(a1, a2, contact.normal);
  }
  // rule 4, written symmetric in the two rods:
  // core_point2 + (r2 - overlap/2) normal = core_point1 - (r1 - overlap/2) normal
  for (int j = 0; j < 3; ++j)
    contact.point[j] = 0.5*(contact.core_point1[j] + contact.core_point2[j])
                       + 0.5*(r2 - r1)*contact.normal[j];
}

inline RodContact rod_contact_in_given_order(const double *c1, const double *a1, double h1,
                                             double r1, const double *c2, const double *a2,
                                             double h2, double r2)
{
  RodContact contact;
  closest_points_in_given_order(c1, a1, h1, c2, a2, h2, contact.t1, contact.t2);
  place_core_points(c1, a1, c2, a2, contact);
  complete_contact(a1, r1, a2, r2, contact);
  return contact;
}

// Whether the rods touch, and if so their contact (rod_contact_in_given_order's,
// to the last bit): the test of cores_within (its lines, then its closest
// points) with the closest points computed once for both.
inline bool touching_in_given_order(const double *c1, const double *a1, double h1, double r1,
                                    const double *c2, const double *a2, double h2, double r2,
                                    RodContact &contact)
{
  const double reach = r1 + r2;
  if (!closest_points_unless_lines_apart(c1, a1, h1, c2, a2, h2, reach, contact.t1, contact.t2))
    return false;
  place_core_points(c1, a1, c2, a2, contact);
  if (!(dot(contact.separation, contact.separation) < reach*reach)) return false;
  complete_contact(a1, r1, a2, r2, contact);
  return contact.overlap > 0.0;
}

// The same contact seen with the rods exchanged, in place.
inline void mirror(RodContact &contact)
{
  std::swap(contact.t1, contact.t2);
  for (int j = 0; j < 3; ++j) {
    std::swap(contact.core_point1[j], contact.core_point2[j]);
    contact.separation[j] = -contact.separation[j];
    contact.normal[j] = -contact.normal[j];
  }
}

inline void add_if_touching(WallContacts &contacts, double t, const double *wall_point,
                            const double *normal, double overlap)
{
  if (!(overlap > 0.0) || contacts.count == max_wall_contacts) return;
  WallContact &contact = contacts.contact[contacts.count++];
  contact.t = t;
  for (int j = 0; j < 3; ++j) {
    contact.wall_point[j] = wall_point[j];
    contact.normal[j] = normal[j];
  }
  contact.overlap = overlap;
}

// Rule 8: the rod's core line seen from the plate's axis. The distance of
// the core point from the axis is s(t) = sqrt(m^2 + A (t - t_m)^2).
struct CoreLineAroundAxis {
  double speed_squared;       // A: the squared in-plane part of the rod's axis
  double nearest_t;           // t_m, where s is least (0 when A = 0: s is constant)
  double least_squared;       // m^2, the least s^2 along the line
  double axial_offset;        // (c - centre).a: (f^2)'/2 = axial_offset + t - R s' over the hole
  double hole_radius;
};

inline CoreLineAroundAxis core_line_around_axis(const double *rod_centre, const double *rod_axis,
                                                const double *plate_centre,
                                                const double *plate_axis, double hole_radius)
{
  double offset[3], offset_in_plane[3], axis_in_plane[3];
  for (int j = 0; j < 3; ++j) offset[j] = rod_centre[j] - plate_centre[j];
  const double height = dot(offset, plate_axis), rise = dot(rod_axis, plate_axis);
  for (int j = 0; j < 3; ++j) {
    offset_in_plane[j] = offset[j] - height*plate_axis[j];
    axis_in_plane[j] = rod_axis[j] - rise*plate_axis[j];
  }
  CoreLineAroundAxis line;
  line.speed_squared = dot(axis_in_plane, axis_in_plane);
  line.hole_radius = hole_radius;
  line.axial_offset = dot(offset, rod_axis);
  const double centre_squared = dot(offset_in_plane, offset_in_plane);
  if (line.speed_squared > 0.0) {
    const double rate = dot(offset_in_plane, axis_in_plane);
    line.nearest_t = -rate/line.speed_squared;
    line.least_squared = std::max(0.0, centre_squared - rate*rate/line.speed_squared);
  } else {
    line.nearest_t = 0.0;
    line.least_squared = centre_squared;
  }
  return line;
}

// The open interval of t over the hole (s < R), possibly the whole line;
// false when the line never passes over the hole.
inline bool hole_interval(const CoreLineAroundAxis &line, double &begin, double &end)
{
  const double radius_squared = line.hole_radius*line.hole_radius;
  if (!(line.least_squared < radius_squared)) return false;
  if (line.speed_squared == 0.0) {
    begin = -HUGE_VAL;
    end = HUGE_VAL;
    return true;
  }
  const double half_width = std::sqrt((radius_squared - line.least_squared)/line.speed_squared);
  begin = line.nearest_t - half_width;
  end = line.nearest_t + half_width;
  return true;
}

// Rule 9: half the width, in t, of the part where f^2 is concave, centred
// on t_m; 0 for the kink of a line through the axis; negative when f^2 is
// convex everywhere.
inline double concave_half_width(const CoreLineAroundAxis &line)
{
  if (line.speed_squared == 0.0) return -1.0;
  if (line.least_squared == 0.0) return 0.0;
  const double s_inflection = std::cbrt(line.hole_radius*line.speed_squared*line.least_squared);
  const double excess = s_inflection*s_inflection - line.least_squared;
  return excess > 0.0 ? std::sqrt(excess/line.speed_squared) : -1.0;
}

// (f^2)'/2 over the hole at t. On the kink of a line through the axis
// (s = 0) s' has two one-sided values: `side` (-1 or +1) says which.
inline double rim_distance_slope(const CoreLineAroundAxis &line, double t, double side)
{
  const double from_nearest = t - line.nearest_t;
  const double s = std::sqrt(line.least_squared + line.speed_squared*from_nearest*from_nearest);
  const double s_rate = s > 0.0 ? line.speed_squared*from_nearest/s
                                : side*std::sqrt(line.speed_squared);
  return line.axial_offset + t - line.hole_radius*s_rate;
}

// The minimum of f over [lower, upper], on which f^2 is convex: an end
// when the slope does not change sign, else the root of the slope.
inline double minimise_convex(const CoreLineAroundAxis &line, double lower, double upper,
                              double side, double tolerance)
{
  if (rim_distance_slope(line, lower, side) >= 0.0) return lower;
  if (rim_distance_slope(line, upper, side) <= 0.0) return upper;
  while (upper - lower > tolerance) {
    const double middle = 0.5*(lower + upper);
    if (rim_distance_slope(line, middle, side) < 0.0) lower = middle;
    else upper = middle;
  }
  return 0.5*(lower + upper);
}

// Rule 9: the local minima of f over the closed piece [begin, end] over
// the hole, in increasing t; returns how many (at most 2).
inline int minima_over_hole(const CoreLineAroundAxis &line, double begin, double end,
                            double half_length, double *minima)
{
  if (begin == end) {
    minima[0] = begin;
    return 1;
  }
  // cut the piece where f^2 changes between convex and concave
  const double half_width = concave_half_width(line);
  double cuts[4];
  int cut_count = 0;
  cuts[cut_count++] = begin;
  // two junctions around a concave part, one at the kink on the axis, or none
  const double junctions[2] = {line.nearest_t - half_width, line.nearest_t + half_width};
  const int junction_count = half_width > 0.0 ? 2 : (half_width == 0.0 ? 1 : 0);
  for (int k = 0; k < junction_count; ++k)
    if (junctions[k] > begin && junctions[k] < end) cuts[cut_count++] = junctions[k];
  cuts[cut_count++] = end;

  int count = 0;
  for (int k = 0; k + 1 < cut_count; ++k) {
    const double lower = cuts[k], upper = cuts[k + 1];
    const double middle = 0.5*(lower + upper);
    const double side = middle < line.nearest_t ? -1.0 : 1.0;
    if (std::fabs(middle - line.nearest_t) < half_width) {
      // concave: only the piece's own ends, where f rises into the piece
      if (lower == begin && rim_distance_slope(line, lower, side) >= 0.0) minima[count++] = lower;
      if (upper == end && rim_distance_slope(line, upper, side) <= 0.0) minima[count++] = upper;
    } else {
      const double t = minimise_convex(line, lower, upper, side,
                                       minimum_tolerance*half_length);
      const bool at_junction = (t == lower && lower != begin) || (t == upper && upper != end);
      if (!at_junction) minima[count++] = t;
    }
  }
  return count;
}

// Rules 8 and 10: the contact at core point t, when it penetrates.
inline void add_plate_contact(WallContacts &contacts, const double *rod_centre,
                              const double *rod_axis, double t, double radius,
                              const double *plate_centre, const double *plate_axis,
                              double hole_radius)
{
  double x[3], normal[3];
  core_point(rod_centre, rod_axis, t, x);
  const PlateContact nearest = nearest_plate_point(x, plate_centre, plate_axis, hole_radius);
  for (int j = 0; j < 3; ++j)
    normal[j] = nearest.distance > 0.0 ? -nearest.to_plate[j]/nearest.distance : plate_axis[j];
  add_if_touching(contacts, t, nearest.point, normal, radius - nearest.distance);
}

}  // namespace rod_detail

// Rules 1-3: the segment parameters t1, t2 of the closest points of the
// core segments c1 + t1 a1 (|t1| <= h1) and c2 + t2 a2 (|t2| <= h2).
inline void closest_points_of_segments(const double *c1, const double *a1, double h1,
                                       const double *c2, const double *a2, double h2,
                                       double &t1, double &t2)
{
  if (rod_detail::in_swapped_order(c1, a1, h1, c2, a2, h2))
    rod_detail::closest_points_in_given_order(c2, a2, h2, c1, a1, h1, t2, t1);
  else
    rod_detail::closest_points_in_given_order(c1, a1, h1, c2, a2, h2, t1, t2);
}

// Whether the cores c1 + t1 a1 and c2 + t2 a2 come closer than `reach`
// (the sum of the radii: whether the rods touch; the list pruning adds
// the skin). The cheap test of the lines comes first
// (closest_points_unless_lines_apart). Computed in rule 3's order, so
// symmetric in the two rods to the last bit.
inline bool cores_within(const double *c1, const double *a1, double h1,
                         const double *c2, const double *a2, double h2, double reach)
{
  double t1, t2;
  const bool swapped = rod_detail::in_swapped_order(c1, a1, h1, c2, a2, h2);
  const bool lines_near = swapped
      ? rod_detail::closest_points_unless_lines_apart(c2, a2, h2, c1, a1, h1, reach, t2, t1)
      : rod_detail::closest_points_unless_lines_apart(c1, a1, h1, c2, a2, h2, reach, t1, t2);
  return lines_near && rod_detail::squared_distance(c1, a1, t1, c2, a2, t2) < reach*reach;
}

// Rules 1-5: the contact of rod 1 (c1, a1, h1, radius r1) with rod 2.
inline RodContact rod_contact(const double *c1, const double *a1, double h1, double r1,
                              const double *c2, const double *a2, double h2, double r2)
{
  if (!rod_detail::in_swapped_order(c1, a1, h1, c2, a2, h2))
    return rod_detail::rod_contact_in_given_order(c1, a1, h1, r1, c2, a2, h2, r2);
  RodContact contact = rod_detail::rod_contact_in_given_order(c2, a2, h2, r2, c1, a1, h1, r1);
  rod_detail::mirror(contact);
  return contact;
}

// Whether rod 1 (c1, a1, h1, r1) and rod 2 touch (overlap > 0), and if so
// their contact, rod_contact's to the last bit: what the pair style needs
// for each listed pair, most of which do not touch. The same decision as
// cores_within(..., r1 + r2) && rod_contact(...).overlap > 0, with the
// closest points computed once.
inline bool rods_touching(const double *c1, const double *a1, double h1, double r1,
                          const double *c2, const double *a2, double h2, double r2,
                          RodContact &contact)
{
  if (!rod_detail::in_swapped_order(c1, a1, h1, c2, a2, h2))
    return rod_detail::touching_in_given_order(c1, a1, h1, r1, c2, a2, h2, r2, contact);
  if (!rod_detail::touching_in_given_order(c2, a2, h2, r2, c1, a1, h1, r1, contact)) return false;
  rod_detail::mirror(contact);
  return true;
}

// Rule 6: the rod (c, a, h, r) against the plane through `plane_point`
// with unit normal `plane_normal` towards the allowed side.
inline WallContacts rod_plane_contacts(const double *c, const double *a, double h, double r,
                                       const double *plane_point, const double *plane_normal)
{
  WallContacts contacts;
  contacts.count = 0;
  double ends[2];
  const int end_count = rod_detail::segment_ends(h, ends);
  for (int k = 0; k < end_count; ++k) {
    double x[3], wall_point[3], offset[3];
    rod_detail::core_point(c, a, ends[k], x);
    for (int j = 0; j < 3; ++j) offset[j] = x[j] - plane_point[j];
    const double height = rod_detail::dot(offset, plane_normal);
    for (int j = 0; j < 3; ++j) wall_point[j] = x[j] - height*plane_normal[j];
    rod_detail::add_if_touching(contacts, ends[k], wall_point, plane_normal, r - height);
  }
  return contacts;
}

// Rule 7: the rod (c, a, h, r) inside the cylinder of radius
// `cylinder_radius` about the line through `axis_point` along the unit
// `cylinder_axis`.
inline WallContacts rod_cylinder_contacts(const double *c, const double *a, double h, double r,
                                          const double *axis_point, const double *cylinder_axis,
                                          double cylinder_radius)
{
  WallContacts contacts;
  contacts.count = 0;
  double ends[2];
  const int end_count = rod_detail::segment_ends(h, ends);
  for (int k = 0; k < end_count; ++k) {
    double x[3], offset[3], outward[3], wall_point[3], normal[3];
    rod_detail::core_point(c, a, ends[k], x);
    for (int j = 0; j < 3; ++j) offset[j] = x[j] - axis_point[j];
    const double along = rod_detail::dot(offset, cylinder_axis);
    for (int j = 0; j < 3; ++j) outward[j] = offset[j] - along*cylinder_axis[j];
    const double from_axis = std::sqrt(rod_detail::dot(outward, outward));
    if (from_axis > 0.0) {
      for (int j = 0; j < 3; ++j) outward[j] /= from_axis;
    } else {
      any_normal_to(cylinder_axis, outward);
    }
    for (int j = 0; j < 3; ++j) {
      wall_point[j] = axis_point[j] + along*cylinder_axis[j] + cylinder_radius*outward[j];
      normal[j] = -outward[j];
    }
    rod_detail::add_if_touching(contacts, ends[k], wall_point, normal,
                                r - (cylinder_radius - from_axis));
  }
  return contacts;
}

// Rules 8-10: the rod (c, a, h, r) against the plate through
// `plate_centre` normal to the unit `plate_axis`, with a hole of radius
// `hole_radius` on the axis.
inline WallContacts rod_plate_contacts(const double *c, const double *a, double h, double r,
                                       const double *plate_centre, const double *plate_axis,
                                       double hole_radius)
{
  const rod_detail::CoreLineAroundAxis line =
      rod_detail::core_line_around_axis(c, a, plate_centre, plate_axis, hole_radius);
  double hole_begin = 0.0, hole_end = 0.0;
  const bool line_over_hole = rod_detail::hole_interval(line, hole_begin, hole_end);
  double ends[2];
  const int end_count = rod_detail::segment_ends(h, ends);
  bool end_over_plate[2] = {false, false};
  for (int k = 0; k < end_count; ++k)
    end_over_plate[k] = !(line_over_hole && hole_begin < ends[k] && ends[k] < hole_end);

  // candidates in increasing t: end -h, the minima over the hole, end +h
  double candidates[max_wall_contacts];
  int count = 0;
  if (end_over_plate[0]) candidates[count++] = ends[0];
  if (line_over_hole && hole_begin < h && hole_end > -h) {
    double minima[2];
    const int minimum_count = rod_detail::minima_over_hole(
        line, std::max(hole_begin, -h), std::min(hole_end, h), h, minima);
    for (int k = 0; k < minimum_count; ++k) {
      const bool counted_as_end = (minima[k] == ends[0] && end_over_plate[0])
                                  || (minima[k] == ends[end_count - 1] && end_over_plate[end_count - 1]);
      if (!counted_as_end) candidates[count++] = minima[k];
    }
  }
  if (end_count == 2 && end_over_plate[1]) candidates[count++] = ends[1];

  WallContacts contacts;
  contacts.count = 0;
  for (int k = 0; k < count; ++k)
    rod_detail::add_plate_contact(contacts, c, a, candidates[k], r, plate_centre, plate_axis,
                                  hole_radius);
  return contacts;
}

// The mass and principal moments of inertia of a solid rod of diameter
// `diameter`, length end to end `length` >= diameter (the caller checks)
// and density `density`.
inline MassProperties spherocylinder_mass_properties(double diameter, double length,
                                                     double density)
{
  const double pi = 3.14159265358979323846;
  const double r = 0.5*diameter, core = length - diameter;
  const double cylinder_mass = density*pi*r*r*core;
  const double caps_mass = density*4.0/3.0*pi*r*r*r;   // the two hemispheres: one sphere
  MassProperties properties;
  properties.mass = cylinder_mass + caps_mass;
  properties.axial_inertia = cylinder_mass*r*r/2.0 + caps_mass*2.0/5.0*r*r;
  // a hemisphere: 2/5 m r^2 about its flat face's centre, -(3r/8)^2 m to
  // its centre of mass, +(core/2 + 3r/8)^2 m to the rod's centre
  properties.transverse_inertia = cylinder_mass*(core*core/12.0 + r*r/4.0)
                                  + caps_mass*(2.0/5.0*r*r + core*core/4.0 + 3.0/8.0*r*core);
  return properties;
}

}  // namespace silokit

#endif
