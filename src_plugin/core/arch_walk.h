/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   Identification of the arch that clogs a silo, by the protocol of
   Hidalgo, Lozano, Zuriguel & Garcimartin (2013), section 3, itself that of
   Garcimartin et al. (2010):

     "Departing from one side, the bead in contact with the base which is
      closer to the orifice is tagged. Beginning from it, the beads in
      contact with it are listed, and the angles to the centers of the beads
      are calculated; the first angle among them (starting from the downward
      direction) is selected, and the corresponding bead is labeled as the
      next one in the arch. The procedure is repeated until the bead is in
      contact with the base at the other side. Finally, the particles in
      contact with the bottom of the silo are not considered to be members
      of the bridge as they indeed are conforming the base of the arch."

   Written as plain functions of plain numbers, free of LIGGGHTS types, so
   that fix clog only gathers the grains and contacts near the orifice and
   calls find_arch(), and so that the walk is tested alone and can be reused
   unchanged (by a modern LAMMPS port, or by the analysis on dumped data).

   Plane and vocabulary. The caller projects the grains on the plane of the
   silo: `horizontal` grows from left to right, `vertical` points up (gravity
   along -vertical); in the quasi-2D silo it drops the coordinate across
   the gap, while the contacts stay those of the spheres. Base grains are
   the fixed grains of the silo bottom, on the left or on the right of the
   orifice; every other grain is free. A grain "touches the left base" when
   it is in contact with a base grain of the left side.

   The rules, made exact where the paper leaves a choice:

   1. Side. The walk departs from the left and ends on the right. (The
      paper says "one side"; fixing it makes the result deterministic. For
      an arch that spans the orifice along one lowest line of grains, the
      right-to-left walk visits the same grains in reverse order.)

   2. Start. Among the free grains that touch the left base and touch at
      least one other free grain, the one whose centre is horizontally
      nearest the orifice centre; ties go to the lower id. The second
      condition skips a grain that merely rests on (or hangs from) the rim
      alone: nothing can be built on it, and the paper's tagged bead is the
      one the arch departs from.

   3. Step. From the current grain, the candidates are its free neighbours
      not yet visited. Each is given the angle through which one turns,
      counter-clockwise (from down towards the right, the side the walk
      heads for), from a reference direction to the direction of its
      centre, in [0, 360); the smallest angle wins, ties to the lower id.
      At the start the reference is the downward direction, as in the
      paper: "the first angle among them (starting from the downward
      direction)". At every later grain it is the direction of the grain
      the walk comes from (the base lies behind the start, the previous
      grain behind the others). The two references give the same choice
      unless the current grain has a free neighbour between the previous
      grain and straight down, i.e. below the line the walk came along.
      That is typically the right foot of an arch whose last grain stands
      a little to the right of it: measured from straight down, the foot
      is at nearly 360 degrees, so any grain resting on or beside the last
      grain comes first and the walk leaves the arch for the pile. Measured
      from the previous grain, the foot comes first. Turning from the grain
      one came from is the usual way to trace the edge of a set of touching
      discs: the walk hugs the underside of the grain network, "the first
      line of beads in mutual contact that are just above the orifice",
      never climbs onto grains resting on the arch, and finds the same
      grains whichever side it departs from, as the paper's "departing
      from one side" takes for granted. Base grains are never candidates:
      the walk goes over the free grains, not along the bottom.

   4. No going back, no cycles. A visited grain is never a candidate again,
      so the walk has at most as many steps as there are grains and always
      ends. Should the paper's rule want to step back (the current grain has
      no other free neighbour), the walk stops with status dead_end: no
      line of grains in contact spans the orifice from there.

   5. End. The walk stops at the first grain that touches the right base
      (checked before stepping, so a start that touches both bases ends at
      once).

   6. Members. "The particles in contact with the bottom of the silo are not
      considered to be members": the members are the walked grains after
      the last one that touches the left base and before the final one,
      which touches the right base. Cutting after the *last* left-touching
      grain (not only after the start) also drops any grain the walk passed
      before reaching the real foot of the arch: such a grain lies in a
      pocket by the left base and does not span the orifice. The grain just
      before the first member is the left foot, the final grain the right
      foot. No member touches a base. A walk with no grain between the two
      feet has status no_member: the feet block the orifice alone.

   7. Angle phi of a member. The angle at its centre between the segments to
      its neighbours in the walk (the previous and the next grain; the feet
      serve as neighbours of the first and last member), measured on the
      lower side of the walk: swept counter-clockwise from the direction of
      the previous grain to the direction of the next one, in degrees in
      [0, 360). The paper defines phi by the contact points; for spheres
      the contact point lies on the line of centres, so it is the same
      angle. A straight line gives 180, a grain above the line of its
      neighbours (a regular arch) less than 180, a grain below it (a
      defect) more than 180.

   8. Feet. The left foot is the walked grain just before the first member,
      the right foot the final grain: the two grains on which the arch
      rests, "the base of the arch" in the paper's Fig. 1. They are
      returned with an angle of their own, for the reading in which they
      count as arch grains (doc/fix_clog.md, "Feet"): as rule 7, with the
      base grain in place of the missing walk neighbour. Of the base grains
      of its side that a foot touches, that one is the base grain met first
      when turning from the arch towards the orifice side, i.e. the one
      that gives the smallest angle (for a foot in the pocket between two
      base grains, the one nearer the orifice). A foot that is the walk's
      start and touches both bases cannot occur with members between the
      feet (rule 5 ends the walk at once). A foot is also told whether it
      touches the floor: a base grain of its side other than the outlet
      grain of that side (the base grain nearest the orifice centre), as a
      foot in the pocket beside the outlet grain does and one resting on
      the outlet grain alone does not.

   eta is the number of members.
------------------------------------------------------------------------- */

#ifndef SILOKIT_ARCH_WALK_H
#define SILOKIT_ARCH_WALK_H

#include <cmath>
#include <cstddef>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace silokit {
namespace arch {

enum class Base { none, left, right };

struct Grain {
  double horizontal;
  double vertical;
  long id;
  Base base;
};

// Two grains in contact, as indices into the grain array; either order,
// repeats allowed.
typedef std::pair<std::size_t, std::size_t> Contact;

enum class Status {
  found,        // an arch with at least one member
  no_start,     // no free grain touches the left base and another free grain
  dead_end,     // the walk stopped before reaching the right base
  no_member,    // the feet touch each other: nothing between them
  bad_contact   // a contact names a grain index out of range
};

inline const char *status_name(Status status)
{
  switch (status) {
    case Status::found:       return "found";
    case Status::no_start:    return "no_start";
    case Status::dead_end:    return "dead_end";
    case Status::no_member:   return "no_member";
    case Status::bad_contact: return "bad_contact";
  }
  return "unknown";
}

struct Member {
  std::size_t index;    // into the grain array
  double phi_degrees;   // rule 7 of the header comment
};

struct Foot {
  std::size_t index;        // into the grain array
  std::size_t base_index;   // the base grain that serves as its neighbour (rule 8)
  double phi_degrees;       // rule 8 of the header comment
  bool on_floor;            // touches a base grain of its side other than the outlet grain
};

struct Arch {
  Status status;
  std::string reason;              // why there is no arch; empty when found
  std::vector<std::size_t> walk;   // grains visited, in order, feet included
  std::vector<Member> members;     // the arch, left to right
  Foot left_foot, right_foot;      // rule 8; set only when the status is found
  std::size_t eta() const { return members.size(); }
};

namespace detail {

const double degrees_per_radian = 180.0 / 3.14159265358979323846;
const std::size_t none = static_cast<std::size_t>(-1);

typedef std::vector<std::vector<std::size_t> > Neighbours;

// Polar angle of the direction from `from` to `to`, in (-180, 180].
inline double direction_degrees(const Grain &from, const Grain &to)
{
  return std::atan2(to.vertical - from.vertical,
                    to.horizontal - from.horizontal) * degrees_per_radian;
}

// Rule 3: the angle turned counter-clockwise from the direction
// `reference_degrees` (polar, in [-180, 180]) to the direction from `from`
// to `to`; in [0, 360).
inline double turn_from(double reference_degrees, const Grain &from, const Grain &to)
{
  const double angle = direction_degrees(from, to) - reference_degrees;  // in [-360, 360]
  if (angle < 0.0) return angle + 360.0;
  return angle == 360.0 ? 0.0 : angle;
}

// Rule 7: counter-clockwise from the direction of `previous` to that of
// `next`, seen from `at`; in [0, 360). It is the angle by which the walk
// chose `next` (rule 3), so a member's phi is also the turn the walk made
// there.
inline double lower_side_angle(const Grain &previous, const Grain &at, const Grain &next)
{
  return turn_from(direction_degrees(at, previous), at, next);
}

inline bool touches_base(const std::vector<Grain> &grains, const Neighbours &neighbours,
                         std::size_t grain, Base side)
{
  for (std::size_t other : neighbours[grain])
    if (grains[other].base == side) return true;
  return false;
}

inline bool touches_free_grain(const std::vector<Grain> &grains, const Neighbours &neighbours,
                               std::size_t grain)
{
  return touches_base(grains, neighbours, grain, Base::none);
}

// Rule 2; `none` when no grain qualifies.
inline std::size_t choose_start(const std::vector<Grain> &grains, const Neighbours &neighbours,
                                double orifice_centre)
{
  std::size_t start = none;
  double start_distance = 0.0;
  for (std::size_t i = 0; i < grains.size(); ++i) {
    if (grains[i].base != Base::none) continue;
    if (!touches_base(grains, neighbours, i, Base::left)) continue;
    if (!touches_free_grain(grains, neighbours, i)) continue;
    const double distance = std::fabs(grains[i].horizontal - orifice_centre);
    const bool nearer = start == none || distance < start_distance
                        || (distance == start_distance && grains[i].id < grains[start].id);
    if (nearer) {
      start = i;
      start_distance = distance;
    }
  }
  return start;
}

// Rule 3: the next grain after `current`, reached from `previous` (`none`
// at the start); `none` when no free neighbour is left.
inline std::size_t next_in_walk(const std::vector<Grain> &grains, const Neighbours &neighbours,
                                const std::vector<bool> &visited, std::size_t previous,
                                std::size_t current)
{
  const double straight_down = -90.0;
  const double reference = previous == none ? straight_down
                           : direction_degrees(grains[current], grains[previous]);
  std::size_t next = none;
  double next_angle = 0.0;
  for (std::size_t candidate : neighbours[current]) {
    if (grains[candidate].base != Base::none || visited[candidate]) continue;
    const double angle = turn_from(reference, grains[current], grains[candidate]);
    const bool first = next == none || angle < next_angle
                       || (angle == next_angle && grains[candidate].id < grains[next].id);
    if (first) {
      next = candidate;
      next_angle = angle;
    }
  }
  return next;
}

inline std::string grain_text(const Grain &grain)
{
  std::ostringstream text;
  text << "grain id " << grain.id;
  return text.str();
}

// Contacts as neighbour lists; false (with `reason`) on an index out of
// range. A grain listed as its own neighbour is ignored.
inline bool build_neighbours(std::size_t grain_count, const std::vector<Contact> &contacts,
                             Neighbours &neighbours, std::string &reason)
{
  neighbours.assign(grain_count, std::vector<std::size_t>());
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const std::size_t i = contacts[k].first, j = contacts[k].second;
    if (i >= grain_count || j >= grain_count) {
      std::ostringstream text;
      text << "contact " << k << " (" << i << ", " << j << ") names a grain index"
           << " beyond the " << grain_count << " grains given";
      reason = text.str();
      return false;
    }
    if (i == j) continue;
    neighbours[i].push_back(j);
    neighbours[j].push_back(i);
  }
  return true;
}

// Rules 3-5: fills arch.walk; false (with status and reason) on a dead end.
inline bool walk_to_right_base(const std::vector<Grain> &grains, const Neighbours &neighbours,
                               std::size_t start, Arch &arch)
{
  std::vector<bool> visited(grains.size(), false);
  std::size_t previous = none, current = start;
  arch.walk.push_back(current);
  visited[current] = true;
  while (!touches_base(grains, neighbours, current, Base::right)) {
    const std::size_t next = next_in_walk(grains, neighbours, visited, previous, current);
    if (next == none) {
      arch.status = Status::dead_end;
      arch.reason = "the walk stopped at " + grain_text(grains[arch.walk.back()])
                    + ": no free neighbour left, right base not reached";
      return false;
    }
    previous = current;
    current = next;
    arch.walk.push_back(current);
    visited[current] = true;
  }
  return true;
}

// Rule 6: position in the walk of the first member (after the last grain
// that touches the left base).
inline std::size_t first_member_position(const std::vector<Grain> &grains,
                                         const Neighbours &neighbours,
                                         const std::vector<std::size_t> &walk)
{
  std::size_t position = 1;
  for (std::size_t k = 0; k < walk.size(); ++k)
    if (touches_base(grains, neighbours, walk[k], Base::left)) position = k + 1;
  return position;
}

// The outlet grain of a side: its base grain nearest the orifice centre
// (ties to the lower id); `none` when the side has no base grain.
inline std::size_t outlet_grain(const std::vector<Grain> &grains, Base side, double orifice_centre)
{
  std::size_t outlet = none;
  for (std::size_t i = 0; i < grains.size(); ++i) {
    if (grains[i].base != side) continue;
    const double distance = std::fabs(grains[i].horizontal - orifice_centre);
    const double best = outlet == none ? 0.0 : std::fabs(grains[outlet].horizontal - orifice_centre);
    if (outlet == none || distance < best || (distance == best && grains[i].id < grains[outlet].id))
      outlet = i;
  }
  return outlet;
}

// Rule 8: the foot `foot` of side `side`, whose neighbour in the arch is
// `member`. The left foot precedes its member in the walk, the right foot
// follows it; the base grain takes the place of the other neighbour.
inline Foot foot_of(const std::vector<Grain> &grains, const Neighbours &neighbours,
                    std::size_t foot, std::size_t member, Base side, double orifice_centre)
{
  Foot result = {foot, none, 0.0, false};
  const std::size_t outlet = outlet_grain(grains, side, orifice_centre);
  for (std::size_t base : neighbours[foot]) {
    if (grains[base].base != side) continue;
    if (base != outlet) result.on_floor = true;
    const double phi = side == Base::left
                       ? lower_side_angle(grains[base], grains[foot], grains[member])
                       : lower_side_angle(grains[member], grains[foot], grains[base]);
    const bool smaller = result.base_index == none || phi < result.phi_degrees
                         || (phi == result.phi_degrees && grains[base].id < grains[result.base_index].id);
    if (smaller) {
      result.base_index = base;
      result.phi_degrees = phi;
    }
  }
  return result;
}

}  // namespace detail

// The clogging arch of the grains and its feet, by rules 1-8 of the header comment.
// orifice_centre is the horizontal coordinate of the middle of the orifice.
inline Arch find_arch(const std::vector<Grain> &grains, const std::vector<Contact> &contacts,
                      double orifice_centre)
{
  Arch arch;
  arch.status = Status::found;
  detail::Neighbours neighbours;
  if (!detail::build_neighbours(grains.size(), contacts, neighbours, arch.reason)) {
    arch.status = Status::bad_contact;
    return arch;
  }

  const std::size_t start = detail::choose_start(grains, neighbours, orifice_centre);
  if (start == detail::none) {
    arch.status = Status::no_start;
    arch.reason = "no free grain touches both the left base and another free grain";
    return arch;
  }
  if (!detail::walk_to_right_base(grains, neighbours, start, arch)) return arch;

  const std::vector<std::size_t> &walk = arch.walk;
  const std::size_t right_foot_position = walk.size() - 1;
  const std::size_t first = detail::first_member_position(grains, neighbours, walk);
  for (std::size_t k = first; k < right_foot_position; ++k) {
    const Member member = {walk[k], detail::lower_side_angle(grains[walk[k - 1]], grains[walk[k]],
                                                            grains[walk[k + 1]])};
    arch.members.push_back(member);
  }
  if (arch.members.empty()) {
    arch.status = Status::no_member;
    arch.reason = "the walk reached the right base at " + detail::grain_text(grains[walk.back()])
                  + " with no grain off the base between the feet";
    return arch;
  }
  arch.left_foot = detail::foot_of(grains, neighbours, walk[first - 1], walk[first], Base::left,
                                   orifice_centre);
  arch.right_foot = detail::foot_of(grains, neighbours, walk[right_foot_position],
                                    walk[right_foot_position - 1], Base::right, orifice_centre);
  return arch;
}

// Horizontal distance between the centres of the first and the last member
// (0 for a one-grain arch, and when there is no arch).
inline double horizontal_span(const std::vector<Grain> &grains, const Arch &arch)
{
  if (arch.members.empty()) return 0.0;
  return std::fabs(grains[arch.members.back().index].horizontal
                   - grains[arch.members.front().index].horizontal);
}

}  // namespace arch
}  // namespace silokit

#endif
