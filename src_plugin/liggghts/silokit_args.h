/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   Argument parsing the silokit fixes share.
------------------------------------------------------------------------- */

#ifndef SILOKIT_ARGS_H
#define SILOKIT_ARGS_H

#include "error.h"
#include "fix.h"
#include "math_extra_liggghts.h"

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
  char *end = nullptr;
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

// Whether LIGGGHTS' random generators (RanPark) take `seed`: they want a
// prime > 10000 and check it on rank 0 alone, with an error->one (a
// warning when liggghts runs with -seedtolerant). Our styles check the
// same rule first, on every rank (unless -seedtolerant), so that the
// error is a collective one that names the keyword.
inline bool liggghts_seed_accepted(int seed)
{
  return seed > 10000 && MathExtraLiggghts::isPrime(seed);
}

}  // namespace silokit

#endif
