/* ----------------------------------------------------------------------
   silokit - granular discharge through orifices, styles for LIGGGHTS 3.8
   GPL-2.0-or-later, like LIGGGHTS, into which it compiles.

   One row of a rain deposition, as plain geometry (no LIGGGHTS types):
   discs of given diameters placed along a segment without overlap, with
   random gaps. Used by fix insert/rain2d.
------------------------------------------------------------------------- */

#ifndef SILOKIT_RAIN_ROW_H
#define SILOKIT_RAIN_ROW_H

#include <algorithm>
#include <cstddef>
#include <vector>

namespace silokit {

// How many grains of mean diameter `mean_diameter` make a row of `length`
// filled to the fraction `fill` (sum of diameters / length), at least 1.
inline int rain_row_count(double length, double fill, double mean_diameter)
{
  const int count = static_cast<int>(fill*length/mean_diameter + 1e-9);
  return count < 1 ? 1 : count;
}

// Centres of discs with `diameters` (in this order, left to right) on the
// segment [lo, hi], each disc wholly inside it and none overlapping.
// The free length F = (hi - lo) - sum(diameters) is cut at the n points
// F*cuts[k] (cuts: n numbers in [0, 1), any order) into n + 1 gaps: before
// the first disc, between discs, after the last. With uniform random cuts
// this draws the gaps uniformly among all arrangements of the discs in this
// order (the n sorted cut points are the left edges of the discs with the
// discs' lengths taken out). Returns an empty vector when the discs do not
// fit (sum of diameters > hi - lo) or the sizes differ.
inline std::vector<double> rain_row_centres(const std::vector<double> &diameters,
                                            double lo, double hi,
                                            std::vector<double> cuts)
{
  std::vector<double> centres;
  const std::size_t n = diameters.size();
  if (cuts.size() != n) return centres;
  double occupied = 0.0;
  for (std::size_t k = 0; k < n; ++k) occupied += diameters[k];
  const double free_length = (hi - lo) - occupied;
  if (free_length < 0.0) return centres;
  std::sort(cuts.begin(), cuts.end());
  double discs_before = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double left_edge = lo + free_length*cuts[k] + discs_before;
    centres.push_back(left_edge + 0.5*diameters[k]);
    discs_before += diameters[k];
  }
  return centres;
}

}  // namespace silokit

#endif
