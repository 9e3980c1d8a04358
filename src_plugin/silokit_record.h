/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   The record files the silokit fixes write (rank 0).
------------------------------------------------------------------------- */

#ifndef SILOKIT_RECORD_H
#define SILOKIT_RECORD_H

#include <cstdio>
#include <string>

namespace silokit {

// Opens the record file at `path`: anew (truncated) for a fresh run, for
// appending when the fix's state was read from a restart file, so that the
// pieces of a restarted run write one series and nothing already recorded
// is lost. `header` (its lines without the last newline) is written only
// to an empty file. NULL if the file cannot be opened.
inline FILE *open_record(const std::string &path, bool restored, const char *header)
{
  FILE *file = fopen(path.c_str(), restored ? "a" : "w");
  if (!file) return NULL;
  fseek(file, 0, SEEK_END);
  if (ftell(file) == 0) {
    fprintf(file, "%s\n", header);
    fflush(file);
  }
  return file;
}

}  // namespace silokit

#endif
