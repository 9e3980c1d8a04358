/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   Argument parsing the silokit fixes share.
------------------------------------------------------------------------- */

#ifndef SILOKIT_ARGS_H
#define SILOKIT_ARGS_H

#include "error.h"
#include "fix.h"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

namespace silokit {

// The finite number `text` given to `keyword` of `fix`. Stock
// force->numeric() does not say which keyword was wrong; this error does.
inline double keyword_number(LAMMPS_NS::Fix *fix, LAMMPS_NS::Error *error,
                             const char *text, const char *keyword)
{
  char *end = NULL;
  const double value = strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(value)) {
    const std::string message = std::string("'") + keyword + "' expects a number, got '" + text + "'";
    error->fix_error(FLERR, fix, message.c_str());
  }
  return value;
}

// The integer `text` given to `keyword` of `fix`; a clear error otherwise.
inline int keyword_integer(LAMMPS_NS::Fix *fix, LAMMPS_NS::Error *error,
                           const char *text, const char *keyword)
{
  const double value = keyword_number(fix, error, text, keyword);
  if (value != std::floor(value) || std::fabs(value) > std::numeric_limits<int>::max()) {
    const std::string message = std::string("'") + keyword + "' expects an integer, got '" + text + "'";
    error->fix_error(FLERR, fix, message.c_str());
  }
  return static_cast<int>(value);
}

}  // namespace silokit

#endif
