/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   fix insert/poses: see fix_insert_poses.h and doc/fix_insert_poses.md.

   How: LIGGGHTS' FixInsert does the insertion (the distribution's
   particles, multisphere bodies, tags, the atom map, the migration of
   clump spheres that lie on another rank); this style only says how many
   bodies each rank inserts (the poses whose position lies in its
   sub-domain, the test create_atoms uses) and where, and never checks
   overlaps: the poses are those of a packing, whose grains touch.
------------------------------------------------------------------------- */

#include "fix_insert_poses.h"

#include "comm.h"
#include "domain.h"
#include "error.h"
#include "fix_particledistribution_discrete.h"
#include "math_extra_liggghts.h"
#include "particleToInsert.h"
#include "particleToInsert_multisphere.h"
#include "vector_liggghts.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

using namespace LAMMPS_NS;

namespace {

const int values_per_pose = 6;  // x y z ax ay az

// The poses of `path` (see read_poses), or a message saying what is wrong.
std::string parse_poses(const std::string &path, std::vector<double> &poses)
{
  std::ifstream in(path.c_str());
  if (!in) return "cannot open the file '" + path + "'";
  std::string line;
  int line_number = 0;
  int frames = 0;
  bool in_dump_header = false;  // inside a dump's ITEM: section other than ATOMS
  while (std::getline(in, line)) {
    ++line_number;
    std::istringstream words(line);
    std::string first;
    if (!(words >> first) || first[0] == '#') continue;
    std::ostringstream where;
    where << path << ", line " << line_number;
    if (first == "ITEM:") {
      std::string section;
      words >> section;
      if (section == "TIMESTEP" && ++frames > 1)
        return where.str() + ": the dump holds more than one frame (give one)";
      in_dump_header = section != "ATOMS";
      if (section == "ATOMS") {
        int columns = 0;
        std::string name;
        while (words >> name) ++columns;
        if (columns != values_per_pose)
          return where.str() + ": the dump's ATOMS section must have 6 columns, x y z ax ay az";
      }
      continue;
    }
    if (in_dump_header) continue;
    std::istringstream values(line);
    double pose[values_per_pose];
    for (int k = 0; k < values_per_pose; ++k)
      if (!(values >> pose[k]) || !std::isfinite(pose[k]))
        return where.str() + ": expected 6 finite numbers, x y z ax ay az";
    std::string extra;
    if (values >> extra) return where.str() + ": more than 6 values (x y z ax ay az)";
    const double length = std::sqrt(pose[3]*pose[3] + pose[4]*pose[4] + pose[5]*pose[5]);
    if (!(length > 0.0)) return where.str() + ": the axis (ax ay az) is zero";
    for (int k = 3; k < values_per_pose; ++k) pose[k] /= length;
    poses.insert(poses.end(), pose, pose + values_per_pose);
  }
  if (poses.empty()) return "the file '" + path + "' holds no pose";
  return "";
}

}  // namespace

/* ---------------------------------------------------------------------- */

FixInsertPoses::FixInsertPoses(LAMMPS *lmp, int narg, char **arg) :
  FixInsert(lmp, narg, arg)
{
  // the poses are a packing: its grains touch, so nothing could be placed
  // with an overlap check, and a random orientation would replace the file's
  for (int k = 3; k + 1 < narg; ++k) {
    if (!strcmp(arg[k], "overlapcheck") && !strcmp(arg[k+1], "yes"))
      error->fix_error(FLERR, this, "places the poses as given: 'overlapcheck yes' is not supported");
    if (!strcmp(arg[k], "orientation"))
      error->fix_error(FLERR, this, "takes the orientation from the file's axes: 'orientation' is not supported");
    if (!strcmp(arg[k], "all_in"))
      error->fix_error(FLERR, this, "places the poses as given: 'all_in' is not supported");
    if (!strcmp(arg[k], "nparticles") || !strcmp(arg[k], "mass") || !strcmp(arg[k], "particlerate") ||
        !strcmp(arg[k], "massrate"))
      error->fix_error(FLERR, this, "inserts one body per pose of its file: 'nparticles', 'mass', "
                                    "'particlerate' and 'massrate' are not supported");
  }
  // FixInsert has parsed its own keywords; iarg is at the first other one
  std::string path;
  while (iarg < narg) {
    const std::string keyword(arg[iarg]);
    if (keyword == "file") {
      if (iarg + 1 >= narg) error->fix_error(FLERR, this, "keyword 'file' needs a file name");
      path = arg[iarg+1];
      iarg += 2;
    } else {
      const std::string message = "unknown keyword '" + keyword + "' (its own: file; and fix insert's "
        "seed, distributiontemplate, insert_every once, vel, omega, start, verbose)";
      error->fix_error(FLERR, this, message.c_str());
    }
  }
  if (path.empty()) error->fix_error(FLERR, this, "'file <poses>' is required");

  check_ol_flag = 0;
  if (insert_every > 0)
    error->fix_error(FLERR, this, "inserts its poses once: use 'insert_every once' (or leave it out)");
  insert_every = 0;

  read_poses(path);
  ninsert = static_cast<int>(poses_.size()/values_per_pose);
  ninsert_exists = 1;
  ninsert_per = ninsert;
}

/* ----------------------------------------------------------------------
   rank 0 reads the file and broadcasts the poses, or the message that
   every rank then stops with
------------------------------------------------------------------------- */

void FixInsertPoses::read_poses(const std::string &path)
{
  std::string message;
  if (comm->me == 0) message = parse_poses(path, poses_);
  int length = static_cast<int>(message.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, world);
  if (length > 0) {
    message.resize(length);
    MPI_Bcast(&message[0], length, MPI_CHAR, 0, world);
    error->fix_error(FLERR, this, message.c_str());
  }
  int count = static_cast<int>(poses_.size());
  MPI_Bcast(&count, 1, MPI_INT, 0, world);
  poses_.resize(count);
  MPI_Bcast(&poses_[0], count, MPI_DOUBLE, 0, world);

  for (int n = 0; n < count/values_per_pose; ++n) {
    const double *x = &poses_[values_per_pose*n];
    for (int dim = 0; dim < 3; ++dim)
      if (x[dim] < domain->boxlo[dim] || x[dim] >= domain->boxhi[dim]) {
        std::ostringstream text;
        text << "pose " << n + 1 << " of '" << path << "' (" << x[0] << " " << x[1] << " " << x[2]
             << ") lies outside the simulation box";
        error->fix_error(FLERR, this, text.str().c_str());
      }
  }
}

/* ---------------------------------------------------------------------- */

void FixInsertPoses::quaternion_turning_x_onto(const double *axis, double *q)
{
  // q ~ (1 + x.a, x cross a): the rotation by the angle between x and a
  // about their common normal, from the half-angle identities
  const double w = 1.0 + axis[0];
  if (w < 1e-12) {
    q[0] = 0.0; q[1] = 0.0; q[2] = 0.0; q[3] = 1.0;
    return;
  }
  q[0] = w;
  q[1] = 0.0;
  q[2] = -axis[2];
  q[3] = axis[1];
  const double norm = std::sqrt(q[0]*q[0] + q[2]*q[2] + q[3]*q[3]);
  for (int k = 0; k < 4; ++k) q[k] /= norm;
}

/* ---------------------------------------------------------------------- */

void FixInsertPoses::calc_insertion_properties()
{
  // everything is known from the file (constructor)
}

int FixInsertPoses::calc_ninsert_this()
{
  return ninserted > 0 ? 0 : ninsert;
}

// each rank inserts the poses in its sub-domain (lo <= x < hi; every pose
// lies inside the box, read_poses); FixInsert checks that
// the counts add up to ninsert_this (MPI_Sum after generate_list)
int FixInsertPoses::distribute_ninsert_this(int ninsert_this)
{
  local_poses_.clear();
  if (ninsert_this == 0) return 0;
  for (int n = 0; n < ninsert; ++n)
    if (domain->is_in_subdomain(&poses_[values_per_pose*n])) local_poses_.push_back(n);
  return static_cast<int>(local_poses_.size());
}

double FixInsertPoses::insertion_fraction()
{
  return ninsert > 0 ? static_cast<double>(local_poses_.size())/ninsert : 0.0;
}

BoundingBox FixInsertPoses::getBoundingBox()
{
  // only used for an overlap check, which this style never makes
  return BoundingBox(domain->sublo[0], domain->subhi[0], domain->sublo[1], domain->subhi[1],
                     domain->sublo[2], domain->subhi[2]);
}

/* ----------------------------------------------------------------------
   the pose's position is the centroid of the sphere centres: LIGGGHTS
   places a clump by its centre of mass, which its template estimates by
   Monte Carlo (1.3e-5 m off the middle of a symmetric clump of three
   spheres of 3 mm, ntry 100000): far more than the overlaps of a settled
   packing. The whole body moves, its centre of mass with it.
------------------------------------------------------------------------- */

void FixInsertPoses::centre_on_pose(ParticleToInsert *pti, const double *pose)
{
  double centroid[3] = { 0.0, 0.0, 0.0 };
  for (int j = 0; j < pti->nparticles; ++j) vectorAdd3D(centroid, pti->x_ins[j], centroid);
  vectorScalarDiv3D(centroid, static_cast<double>(pti->nparticles));
  double shift[3];
  vectorSubtract3D(pose, centroid, shift);
  for (int j = 0; j < pti->nparticles; ++j) vectorAdd3D(pti->x_ins[j], shift, pti->x_ins[j]);
  ParticleToInsertMultisphere *body = dynamic_cast<ParticleToInsertMultisphere *>(pti);
  if (body) vectorAdd3D(body->xcm_ins, shift, body->xcm_ins);
}

/* ----------------------------------------------------------------------
   the distribution's k-th particle at the k-th local pose
------------------------------------------------------------------------- */

void FixInsertPoses::x_v_omega(int ninsert_this_local, int &ninserted_this_local,
                               int &ninserted_spheres_this_local, double &mass_inserted_this_local)
{
  ninserted_this_local = ninserted_spheres_this_local = 0;
  mass_inserted_this_local = 0.0;
  for (int k = 0; k < ninsert_this_local; ++k) {
    double *pose = &poses_[values_per_pose*local_poses_[k]];
    double quat[4], v[3];
    quaternion_turning_x_onto(pose + 3, quat);
    vectorCopy3D(v_insert, v);
    generate_random_velocity(v);  // adds the fluctuation of 'vel uniform|gaussian'
    ParticleToInsert *pti = fix_distribution->pti_list[k];
    ninserted_spheres_this_local += pti->set_x_v_omega(pose, v, omega_insert, quat);
    centre_on_pose(pti, pose);
    mass_inserted_this_local += pti->mass_ins;
    ++ninserted_this_local;
  }
}
