/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   and LAMMPS. GPL-2.0-or-later, like both hosts.

   What the host-free parts of our fixes (reinject_logic.h,
   rain2d_logic.h) share: a keyword's value as a number, or the text of
   the error naming the keyword, and writing a fix's global restart data.
------------------------------------------------------------------------- */

#ifndef SILOKIT_FIX_COMMON_H
#define SILOKIT_FIX_COMMON_H

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

namespace silokit {

// `text` as a finite number for `keyword`, or the error's text
inline std::string number_for(const std::string &keyword, const std::string &text, double &value)
{
  char *end = nullptr;
  value = strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !std::isfinite(value))
    return "'" + keyword + "' expects a number, got '" + text + "'";
  return "";
}

// `text` as an int for `keyword` (no fraction, within range), or the error's text
inline std::string integer_for(const std::string &keyword, const std::string &text, int &value)
{
  double number = 0.0;
  const std::string problem = number_for(keyword, text, number);
  if (!problem.empty()) return problem;
  if (number != std::floor(number) || std::fabs(number) > std::numeric_limits<int>::max())
    return "'" + keyword + "' expects an integer, got '" + text + "'";
  value = static_cast<int>(number);
  return "";
}

// A fix's global restart data as both hosts read it back: its size in
// bytes, then the values (rank 0 writes it).
inline void write_restart_data(FILE *file, const std::vector<double> &list)
{
  const int size = static_cast<int>(list.size()*sizeof(double));
  fwrite(&size, sizeof(int), 1, file);
  fwrite(list.data(), sizeof(double), list.size(), file);
}

}  // namespace silokit

#endif
