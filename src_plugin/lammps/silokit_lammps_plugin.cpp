/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   The one entry point of build/lib/silokit_lammps.so: LAMMPS' `plugin load`
   calls lammpsplugin_init, which registers each of our LAMMPS styles. The
   styles are then used like built-in ones, restart files included.
------------------------------------------------------------------------- */

#include "lammpsplugin.h"
#include "version.h"

#include "fix_clog_lammps.h"
#include "fix_insert_rain2d_lammps.h"
#include "fix_reinject_lammps.h"
#include "fix_wall_gran_rotating_lammps.h"
#include "pair_granular_jiang.h"

using namespace LAMMPS_NS;

namespace {

Pair *granular_jiang_creator(LAMMPS *lmp)
{
  return new PairGranularJiang(lmp);
}

Fix *wall_gran_rotating_creator(LAMMPS *lmp, int argc, char **argv)
{
  return new FixWallGranRotating(lmp, argc, argv);
}

Fix *reinject_creator(LAMMPS *lmp, int argc, char **argv)
{
  return new FixReinject(lmp, argc, argv);
}

Fix *clog_creator(LAMMPS *lmp, int argc, char **argv)
{
  return new FixClog(lmp, argc, argv);
}

Fix *insert_rain2d_creator(LAMMPS *lmp, int argc, char **argv)
{
  return new FixInsertRain2d(lmp, argc, argv);
}

}    // namespace

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *regfunc)
{
  lammpsplugin_t plugin;
  lammpsplugin_regfunc register_plugin = (lammpsplugin_regfunc) regfunc;

  plugin.version = LAMMPS_VERSION;
  plugin.author = "silokit";
  plugin.handle = handle;

  plugin.style = "pair";
  plugin.name = "granular/jiang";
  plugin.info = "silokit: LIGGGHTS' hooke contact law with Jiang's rolling resistance";
  plugin.creator.v1 = (lammpsplugin_factory1 *) &granular_jiang_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.style = "fix";
  plugin.name = "wall/gran/rotating";
  plugin.info = "silokit: flat plate with an orifice, turning about the silo axis";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &wall_gran_rotating_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.name = "reinject";
  plugin.info = "silokit: grains leaving through the outlet re-enter at the top, counted";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &reinject_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.name = "clog";
  plugin.info = "silokit: finds the clogging arch, records it, stops the run or breaks the arch";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &clog_creator;
  (*register_plugin)(&plugin, lmp);

  plugin.name = "insert/rain2d";
  plugin.info = "silokit: rain deposition of polydisperse discs in 2D, row by row";
  plugin.creator.v2 = (lammpsplugin_factory2 *) &insert_rain2d_creator;
  (*register_plugin)(&plugin, lmp);
}
