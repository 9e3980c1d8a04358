/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   Argument parsing shared by our LAMMPS styles: a value for a keyword,
   or an ERROR (on every rank: the arguments are the same everywhere)
   naming the style, the keyword and the text it got.
------------------------------------------------------------------------- */

#ifndef SILOKIT_LAMMPS_ARGS_H
#define SILOKIT_LAMMPS_ARGS_H

#include "error.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

namespace silokit_lammps {

// a finite number for `keyword`
inline double parse_number(LAMMPS_NS::Error *error, const char *style, const std::string &keyword,
                           const char *text)
{
  char *end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(value))
    error->all(FLERR, "{}: {} expects a number, got '{}'", style, keyword, text);
  return value;
}

// yes or no for `keyword`
inline bool parse_yes_no(LAMMPS_NS::Error *error, const char *style, const std::string &keyword,
                         const char *text)
{
  if (std::strcmp(text, "yes") == 0) return true;
  if (std::strcmp(text, "no") == 0) return false;
  error->all(FLERR, "{}: {} expects yes or no, got '{}'", style, keyword, text);
  return false;
}

}    // namespace silokit_lammps

#endif
