// Test driver for src_plugin/core/arch_walk.h: reads one configuration from
// stdin, prints the arch that silokit::arch::find_arch identifies.
//
// Input (whitespace-separated; grain indices in contacts count from 0 in
// the order the grains are listed):
//   orifice_centre <horizontal>
//   grains <n>
//   <id> <horizontal> <vertical> <free|left|right>      n lines
//   contacts <m>
//   <i> <j>                                              m lines
//
// Output, one line each (ids, and angles in degrees with 17 digits):
//   status <found|no_start|dead_end|no_member|bad_contact>
//   reason <text, or - when found>
//   walk <ids of the walked grains, feet included>
//   members <ids of the arch grains, left to right>
//   phi <angle of each member>
//   eta <number of members>
//   span <horizontal span>

#include "arch_walk.h"

#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

namespace {

using silokit::arch::Base;
using silokit::arch::Contact;
using silokit::arch::Grain;

bool expect_keyword(std::istream &in, const std::string &keyword)
{
  std::string word;
  if (in >> word && word == keyword) return true;
  std::cerr << "arch_walk_driver: expected '" << keyword << "', read '" << word << "'\n";
  return false;
}

bool read_base(std::istream &in, Base &base)
{
  std::string word;
  in >> word;
  if (word == "free") base = Base::none;
  else if (word == "left") base = Base::left;
  else if (word == "right") base = Base::right;
  else {
    std::cerr << "arch_walk_driver: base must be free, left or right, not '" << word << "'\n";
    return false;
  }
  return true;
}

bool read_configuration(std::istream &in, double &orifice_centre,
                        std::vector<Grain> &grains, std::vector<Contact> &contacts)
{
  std::size_t count = 0;
  if (!expect_keyword(in, "orifice_centre") || !(in >> orifice_centre)) return false;
  if (!expect_keyword(in, "grains") || !(in >> count)) return false;
  grains.resize(count);
  for (Grain &grain : grains)
    if (!(in >> grain.id >> grain.horizontal >> grain.vertical) || !read_base(in, grain.base))
      return false;
  if (!expect_keyword(in, "contacts") || !(in >> count)) return false;
  contacts.resize(count);
  for (Contact &contact : contacts)
    if (!(in >> contact.first >> contact.second)) return false;
  return true;
}

void print_arch(const std::vector<Grain> &grains, const silokit::arch::Arch &arch)
{
  std::printf("status %s\n", silokit::arch::status_name(arch.status));
  std::printf("reason %s\n", arch.reason.empty() ? "-" : arch.reason.c_str());
  std::printf("walk");
  for (std::size_t index : arch.walk) std::printf(" %ld", grains[index].id);
  std::printf("\nmembers");
  for (const silokit::arch::Member &member : arch.members)
    std::printf(" %ld", grains[member.index].id);
  std::printf("\nphi");
  for (const silokit::arch::Member &member : arch.members)
    std::printf(" %.17g", member.phi_degrees);
  std::printf("\neta %zu\n", arch.eta());
  if (arch.status == silokit::arch::Status::found) {
    const silokit::arch::Foot feet[2] = {arch.left_foot, arch.right_foot};
    std::printf("feet %ld %ld\n", grains[feet[0].index].id, grains[feet[1].index].id);
    std::printf("foot_bases %ld %ld\n", grains[feet[0].base_index].id,
                grains[feet[1].base_index].id);
    std::printf("foot_phi %.17g %.17g\n", feet[0].phi_degrees, feet[1].phi_degrees);
    std::printf("foot_on_floor %d %d\n", feet[0].on_floor ? 1 : 0, feet[1].on_floor ? 1 : 0);
  }
  std::printf("span %.17g\n", silokit::arch::horizontal_span(grains, arch));
}

}  // namespace

int main()
{
  double orifice_centre = 0.0;
  std::vector<Grain> grains;
  std::vector<Contact> contacts;
  if (!read_configuration(std::cin, orifice_centre, grains, contacts)) {
    std::cerr << "arch_walk_driver: malformed input\n";
    return 2;
  }
  print_arch(grains, silokit::arch::find_arch(grains, contacts, orifice_centre));
  return 0;
}
