/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   MPI helpers the silokit fixes share.
------------------------------------------------------------------------- */

#ifndef SILOKIT_MPI_H
#define SILOKIT_MPI_H

#include <mpi.h>
#include <vector>

namespace silokit {

// All ranks' values, concatenated in rank order, on every rank.
inline std::vector<double> allgather(const std::vector<double> &local, MPI_Comm world)
{
  int nprocs = 1;
  MPI_Comm_size(world, &nprocs);
  const int count = static_cast<int>(local.size());
  std::vector<int> counts(nprocs), offsets(nprocs, 0);
  MPI_Allgather(const_cast<int *>(&count), 1, MPI_INT, &counts[0], 1, MPI_INT, world);
  for (int p = 1; p < nprocs; ++p) offsets[p] = offsets[p-1] + counts[p-1];
  std::vector<double> all(offsets[nprocs-1] + counts[nprocs-1] + 1);  // +1: never empty
  MPI_Allgatherv(count ? const_cast<double *>(&local[0]) : nullptr, count, MPI_DOUBLE,
                 &all[0], &counts[0], &offsets[0], MPI_DOUBLE, world);
  all.pop_back();
  return all;
}

}  // namespace silokit

#endif
