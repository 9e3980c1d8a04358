// Test driver for src_plugin/core/spherocylinder_geometry.h: reads commands from
// stdin, one per line, and prints one line of results per command. A rod
// is written c_x c_y c_z a_x a_y a_z h r (centre, unit axis, half-length of
// the core segment, radius); a point or vector as its three components.
//
// Input                                          Output
//   segments c1 a1 h1 c2 a2 h2                     segments t1 t2
//   rod_contact <rod 1> <rod 2>                    rod_contact t1 t2 distance overlap
//                                                    separation(3) normal(3) point(3)
//   within <rod 1> <rod 2>                         within 1|0 (cores_within, reach r1 + r2)
//   touching <rod 1> <rod 2>                       touching 0, or touching 1 and the
//                                                    numbers of rod_contact (rods_touching)
//   plane <rod> p0 n                               contacts <n> then, per contact,
//   cylinder <rod> axis_point axis Rc                t wall_point(3) normal(3) overlap
//   plate <rod> centre axis R
//   sphere_plate x centre axis R                   sphere_plate distance to_plate(3) point(3)
//                                                    (orifice_plate.h, for comparison)
//   mass d L density                               mass mass axial transverse
//
// Numbers are printed with 17 significant digits.

#include "orifice_plate.h"
#include "spherocylinder_geometry.h"

#include <cstdio>
#include <iostream>
#include <string>

namespace {

const int max_numbers = 16;

bool read_numbers(std::istream &in, int count, double *values)
{
  for (int k = 0; k < count; ++k)
    if (!(in >> values[k])) return false;
  return true;
}

void print_numbers(const double *values, int count)
{
  for (int k = 0; k < count; ++k) std::printf(" %.17g", values[k]);
}

void print_wall_contacts(const silokit::WallContacts &contacts)
{
  std::printf("contacts %d", contacts.count);
  for (int k = 0; k < contacts.count; ++k) {
    const silokit::WallContact &contact = contacts.contact[k];
    print_numbers(&contact.t, 1);
    print_numbers(contact.wall_point, 3);
    print_numbers(contact.normal, 3);
    print_numbers(&contact.overlap, 1);
  }
  std::printf("\n");
}

// values: c1(3) a1(3) h1 c2(3) a2(3) h2
void segments(const double *v)
{
  double t1 = 0.0, t2 = 0.0;
  silokit::closest_points_of_segments(v, v + 3, v[6], v + 7, v + 10, v[13], t1, t2);
  std::printf("segments %.17g %.17g\n", t1, t2);
}

void print_rod_contact(const silokit::RodContact &contact)
{
  std::printf(" %.17g %.17g %.17g %.17g", contact.t1, contact.t2, contact.distance, contact.overlap);
  print_numbers(contact.separation, 3);
  print_numbers(contact.normal, 3);
  print_numbers(contact.point, 3);
  std::printf("\n");
}

// values: rod 1 (8), rod 2 (8)
void rod_contact(const double *v)
{
  std::printf("rod_contact");
  print_rod_contact(silokit::rod_contact(v, v + 3, v[6], v[7], v + 8, v + 11, v[14], v[15]));
}

// values: rod 1 (8), rod 2 (8)
void touching(const double *v)
{
  silokit::RodContact contact;
  if (!silokit::rods_touching(v, v + 3, v[6], v[7], v + 8, v + 11, v[14], v[15], contact)) {
    std::printf("touching 0\n");
    return;
  }
  std::printf("touching 1");
  print_rod_contact(contact);
}

// values: point(3) centre(3) axis(3) R
void sphere_plate(const double *v)
{
  const silokit::PlateContact contact = silokit::nearest_plate_point(v, v + 3, v + 6, v[9]);
  std::printf("sphere_plate %.17g", contact.distance);
  print_numbers(contact.to_plate, 3);
  print_numbers(contact.point, 3);
  std::printf("\n");
}

// values: d L density
void mass(const double *v)
{
  const silokit::MassProperties properties = silokit::spherocylinder_mass_properties(v[0], v[1], v[2]);
  std::printf("mass %.17g %.17g %.17g\n", properties.mass, properties.axial_inertia,
              properties.transverse_inertia);
}

// Runs one command; false on an unknown command or missing numbers.
bool run(std::istream &in, const std::string &command)
{
  double v[max_numbers];
  if (command == "segments") {
    if (!read_numbers(in, 14, v)) return false;
    segments(v);
  } else if (command == "rod_contact") {
    if (!read_numbers(in, 16, v)) return false;
    rod_contact(v);
  } else if (command == "touching") {  // rod 1 (8), rod 2 (8)
    if (!read_numbers(in, 16, v)) return false;
    touching(v);
  } else if (command == "within") {     // rod 1 (8), rod 2 (8)
    if (!read_numbers(in, 16, v)) return false;
    std::printf("within %d\n", silokit::cores_within(v, v + 3, v[6], v + 8, v + 11, v[14], v[7] + v[15]) ? 1 : 0);
  } else if (command == "plane") {      // rod(8) p0(3) n(3)
    if (!read_numbers(in, 14, v)) return false;
    print_wall_contacts(silokit::rod_plane_contacts(v, v + 3, v[6], v[7], v + 8, v + 11));
  } else if (command == "cylinder") {   // rod(8) axis_point(3) axis(3) Rc
    if (!read_numbers(in, 15, v)) return false;
    print_wall_contacts(silokit::rod_cylinder_contacts(v, v + 3, v[6], v[7], v + 8, v + 11, v[14]));
  } else if (command == "plate") {      // rod(8) centre(3) axis(3) R
    if (!read_numbers(in, 15, v)) return false;
    print_wall_contacts(silokit::rod_plate_contacts(v, v + 3, v[6], v[7], v + 8, v + 11, v[14]));
  } else if (command == "sphere_plate") {
    if (!read_numbers(in, 10, v)) return false;
    sphere_plate(v);
  } else if (command == "mass") {
    if (!read_numbers(in, 3, v)) return false;
    mass(v);
  } else {
    return false;
  }
  return true;
}

}  // namespace

int main()
{
  std::string command;
  while (std::cin >> command) {
    if (!run(std::cin, command)) {
      std::cerr << "spherocylinder_geometry_driver: bad command or numbers at '" << command << "'\n";
      return 2;
    }
  }
  return 0;
}
