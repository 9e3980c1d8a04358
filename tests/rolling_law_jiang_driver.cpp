// Test driver for src_plugin/core/rolling_law_jiang.h: reads commands from
// stdin, one per line, and prints one line per command (numbers with 17
// digits). It holds one rolling spring (stiffness, cap) and its
// accumulated rolling angle, as a contact's history does.
//
//   chord <r_i> <r_j> <distance>       -> length <l_c>   (overlap_contact_length)
//   wall_chord <r> <overlap>           -> length <l_c>   (wall_overlap_contact_length)
//   spring <k_n> <delta_n> <mu> <l_c> <a> <b>
//                                      -> spring <k_r> <torque limit>; the angle restarts at 0
//   roll <dx> <dy> <dz>                -> torque <tx> <ty> <tz> rolls <0|1> angle <ax> <ay> <az>
//                                         (adds the increment to the angle, then spring_torque)
//   restiffen <new k_r>                -> angle <ax> <ay> <az>   (adapt_to_stiffness, then the
//                                         spring takes the new k_r)
//   tangent <nx> <ny> <nz>             -> angle <ax> <ay> <az>   (rotate_into_tangent_plane)
//   no_twist <wx> <wy> <wz> <nx> <ny> <nz> -> omega <wx> <wy> <wz> (remove_normal_component)
//   step <new k_r> <nx> <ny> <nz> <wx> <wy> <wz> <dt> <advance 0|1>
//                                      -> torque <tx> <ty> <tz> rolls <0|1> angle <ax> <ay> <az>
//                                         (step_rolling_spring from the held angle and k_r; with
//                                         advance the spring keeps the new angle and k_r)
//   damp <ratio> <inertia> <wx> <wy> <wz> <tx> <ty> <tz>
//                                      -> torque <tx> <ty> <tz>  (add_rolling_damping, spring's k_r)

#include "rolling_law_jiang.h"

#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>

namespace {

void print_vector(const char *name, const double *v)
{
  std::printf(" %s %.17g %.17g %.17g", name, v[0], v[1], v[2]);
}

}  // namespace

int main()
{
  using namespace silokit::jiang;
  RollingSpring spring = { 0.0, 0.0 };
  double angle[3] = { 0.0, 0.0, 0.0 };
  std::string line;
  while (std::getline(std::cin, line)) {
    std::istringstream in(line);
    std::string command;
    if (!(in >> command)) continue;
    if (command == "chord") {
      double radius_i, radius_j, distance;
      in >> radius_i >> radius_j >> distance;
      std::printf("length %.17g", overlap_contact_length(radius_i, radius_j, distance));
    } else if (command == "wall_chord") {
      double radius, overlap;
      in >> radius >> overlap;
      std::printf("length %.17g", wall_overlap_contact_length(radius, overlap));
    } else if (command == "spring") {
      double normal_stiffness, overlap, friction, contact_length, stiffness_factor, friction_factor;
      in >> normal_stiffness >> overlap >> friction >> contact_length >> stiffness_factor
         >> friction_factor;
      spring = rolling_spring(normal_stiffness, overlap, friction, contact_length,
                              stiffness_factor, friction_factor);
      for (int k = 0; k < 3; ++k) angle[k] = 0.0;
      std::printf("spring %.17g %.17g", spring.stiffness, spring.torque_limit);
    } else if (command == "roll") {
      for (int k = 0; k < 3; ++k) {
        double increment;
        in >> increment;
        angle[k] += increment;
      }
      double torque[3];
      const bool rolls = spring_torque(angle, spring.stiffness, spring.torque_limit, torque);
      std::printf("torque %.17g %.17g %.17g rolls %d", torque[0], torque[1], torque[2],
                  rolls ? 1 : 0);
      print_vector("angle", angle);
    } else if (command == "restiffen") {
      double stiffness;
      in >> stiffness;
      adapt_to_stiffness(angle, spring.stiffness, stiffness);
      spring.stiffness = stiffness;
      std::printf("angle %.17g %.17g %.17g", angle[0], angle[1], angle[2]);
    } else if (command == "tangent") {
      double normal[3];
      in >> normal[0] >> normal[1] >> normal[2];
      rotate_into_tangent_plane(angle, normal);
      std::printf("angle %.17g %.17g %.17g", angle[0], angle[1], angle[2]);
    } else if (command == "no_twist") {
      double omega[3], normal[3];
      in >> omega[0] >> omega[1] >> omega[2] >> normal[0] >> normal[1] >> normal[2];
      remove_normal_component(omega, normal);
      std::printf("omega %.17g %.17g %.17g", omega[0], omega[1], omega[2]);
    } else if (command == "step") {
      RollingSpring next = spring;
      double normal[3], omega[3], dt;
      int advance;
      in >> next.stiffness >> normal[0] >> normal[1] >> normal[2] >> omega[0] >> omega[1]
         >> omega[2] >> dt >> advance;
      double stepped[3] = { angle[0], angle[1], angle[2] };
      double torque[3];
      const bool rolls = step_rolling_spring(stepped, spring.stiffness, normal, omega, next, dt,
                                             advance != 0, torque);
      std::printf("torque %.17g %.17g %.17g rolls %d", torque[0], torque[1], torque[2],
                  rolls ? 1 : 0);
      print_vector("angle", stepped);
      if (advance) {
        for (int k = 0; k < 3; ++k) angle[k] = stepped[k];
        spring = next;
      }
    } else if (command == "damp") {
      double ratio, inertia, omega[3], torque[3];
      in >> ratio >> inertia >> omega[0] >> omega[1] >> omega[2] >> torque[0] >> torque[1]
         >> torque[2];
      add_rolling_damping(ratio, inertia, spring.stiffness, omega, torque);
      std::printf("torque %.17g %.17g %.17g", torque[0], torque[1], torque[2]);
    } else {
      std::cerr << "rolling_law_jiang_driver: unknown command '" << command << "'\n";
      return 2;
    }
    if (in.fail()) {
      std::cerr << "rolling_law_jiang_driver: too few numbers in '" << line << "'\n";
      return 2;
    }
    std::printf("\n");
  }
  return 0;
}
