// Test driver for src_plugin/core/contact_law.h: reads commands from stdin,
// one per line, and prints one line per command (numbers with 17 digits).
// It holds one contact model and one contact's tangential history (shear),
// as a pair's or a wall's history does, and replays a contact sequence
// step by step.
//
//   model hooke/stiffness <kn> <kt> <gamman> <gammat> <mu> <absolute_damping 0|1>
//         <tangential_damping 0|1> <limit_force 0|1>
//   model hooke <Y_i> <nu_i> <Y_j> <nu_j> <e> <v_char> <mu> <tangential_damping 0|1>
//         <limit_force 0|1>
//                                   -> model <name>; the shear restarts at 0
//   spring <meff> <reff>            -> spring <kn> <kt> <gamman> <gammat> (the model's)
//   pair <update 0|1> <dt> <x_i 3> <x_j 3> <v_i 3> <v_j 3> <omega_i 3> <omega_j 3>
//        <r_i> <r_j> <m_i> <m_j>
//   zplane <update 0|1> <dt> <z0> <x_i 3> <v_i 3> <omega_i 3> <r_i> <m_i>
//                                   (a fixed plane z = z0 below the grain, as LIGGGHTS'
//                                    primitive `zplane` computes it)
//        -> apart                   (no contact; the shear is zeroed, or kept for a
//                                    pair after `separated keep`)
//        -> contact fn <Fn> slides <0|1> overlap <delta_n> force <F_i 3>
//           torque_i <3> torque_j <3> shear <3>
//   shear <s 3>                     -> shear <3>   (sets the history)
//   separated zero|keep             -> separated <policy>: what a pair that no longer
//                                      touches does with its history. LIGGGHTS 3.8
//                                      keeps it until the next neighbor build (a
//                                      re-contact before that starts from it);
//                                      zero (the default) is what a wall does.

#include "contact_law.h"

#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>

namespace {

using namespace silokit::contact;

struct Model {
  bool hooke;                 // false: hooke/stiffness
  double kn, kt, gamman, gammat;
  double youngs_effective, restitution, characteristic_velocity;
  double mu;
  bool absolute_damping, tangential_damping, limit_force;
};

NormalSpring spring_of(const Model &model, double meff, double reff)
{
  if (model.hooke)
    return hooke(model.youngs_effective, model.restitution, model.characteristic_velocity,
                 meff, reff, model.tangential_damping);
  return hooke_stiffness(model.kn, model.kt, model.gamman, model.gammat, meff,
                         model.absolute_damping, model.tangential_damping);
}

void read3(std::istream &in, double v[3])
{
  in >> v[0] >> v[1] >> v[2];
}

void print3(const char *name, const double v[3])
{
  std::printf(" %s %.17g %.17g %.17g", name, v[0], v[1], v[2]);
}

void print_contact(const ContactForces &c, double overlap, const double shear[3])
{
  std::printf("contact fn %.17g slides %d overlap %.17g", c.fn, c.slides ? 1 : 0, overlap);
  print3("force", c.force_i);
  print3("torque_i", c.torque_i);
  print3("torque_j", c.torque_j);
  print3("shear", shear);
}

}  // namespace

int main()
{
  Model model = Model();
  double shear[3] = { 0.0, 0.0, 0.0 };
  bool keep_when_separated = false;
  std::string line;
  while (std::getline(std::cin, line)) {
    std::istringstream in(line);
    std::string command;
    if (!(in >> command)) continue;
    if (command == "model") {
      std::string name;
      in >> name;
      model = Model();
      int absolute = 0, tangential = 1, limit = 0;
      if (name == "hooke/stiffness") {
        in >> model.kn >> model.kt >> model.gamman >> model.gammat >> model.mu >> absolute
           >> tangential >> limit;
      } else if (name == "hooke") {
        double youngs_i, poisson_i, youngs_j, poisson_j;
        in >> youngs_i >> poisson_i >> youngs_j >> poisson_j >> model.restitution
           >> model.characteristic_velocity >> model.mu >> tangential >> limit;
        model.hooke = true;
        model.youngs_effective = effective_youngs_modulus(youngs_i, poisson_i, youngs_j,
                                                          poisson_j);
      } else {
        std::printf("error unknown model %s\n", name.c_str());
        return 1;
      }
      model.absolute_damping = absolute != 0;
      model.tangential_damping = tangential != 0;
      model.limit_force = limit != 0;
      for (int d = 0; d < 3; ++d) shear[d] = 0.0;
      std::printf("model %s", name.c_str());
    } else if (command == "spring") {
      double meff, reff;
      in >> meff >> reff;
      const NormalSpring s = spring_of(model, meff, reff);
      std::printf("spring %.17g %.17g %.17g %.17g", s.kn, s.kt, s.gamman, s.gammat);
    } else if (command == "pair") {
      int update;
      double dt, x_i[3], x_j[3], v_i[3], v_j[3], omega_i[3], omega_j[3];
      double radius_i, radius_j, mass_i, mass_j;
      in >> update >> dt;
      read3(in, x_i); read3(in, x_j); read3(in, v_i); read3(in, v_j);
      read3(in, omega_i); read3(in, omega_j);
      in >> radius_i >> radius_j >> mass_i >> mass_j;
      if (!touching(x_i, x_j, radius_i, radius_j)) {
        if (!keep_when_separated)
          for (int d = 0; d < 3; ++d) shear[d] = 0.0;
        std::printf("apart\n");
        continue;
      }
      const Kinematics k = pair_kinematics(x_i, x_j, v_i, v_j, omega_i, omega_j,
                                           radius_i, radius_j);
      const NormalSpring s = spring_of(model, pair_effective_mass(mass_i, mass_j),
                                       pair_effective_radius(radius_i, radius_j));
      const ContactForces c = contact_forces(k, s, model.mu, dt, model.limit_force,
                                             update != 0, shear);
      print_contact(c, k.overlap, shear);
    } else if (command == "zplane") {
      int update;
      double dt, z0, x_i[3], v_i[3], omega_i[3], radius_i, mass_i;
      in >> update >> dt >> z0;
      read3(in, x_i); read3(in, v_i); read3(in, omega_i);
      in >> radius_i >> mass_i;
      // primitive_wall_definitions.h, Plane<2>::resolveContact for a grain
      // above the plane, and fix_wall_gran.cpp: contact when the gap <= 0
      const double gap = x_i[2] - z0 - radius_i;
      if (!(gap <= 0.0)) {
        for (int d = 0; d < 3; ++d) shear[d] = 0.0;
        std::printf("apart\n");
        continue;
      }
      const double delta[3] = { -0.0, -0.0, -(z0 - x_i[2]) };
      const double v_wall[3] = { 0.0, 0.0, 0.0 };
      const Kinematics k = wall_kinematics(delta, -gap, v_i, v_wall, omega_i, radius_i);
      const NormalSpring s = spring_of(model, mass_i, radius_i);
      const ContactForces c = contact_forces(k, s, model.mu, dt, model.limit_force,
                                             update != 0, shear);
      print_contact(c, k.overlap, shear);
    } else if (command == "separated") {
      std::string policy;
      in >> policy;
      keep_when_separated = policy == "keep";
      std::printf("separated %s", keep_when_separated ? "keep" : "zero");
    } else if (command == "shear") {
      read3(in, shear);
      print3("shear", shear);
    } else {
      std::printf("error unknown command %s\n", command.c_str());
      return 1;
    }
    std::printf("\n");
  }
  return 0;
}
