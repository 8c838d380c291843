// SPDX-License-Identifier: Apache-2.0
// The deviation vector plot of one plane of a grid (one per constant-Z plane of the monthly
// laser-tracker grid): every nominal point as a dot, its in-plane deviation as an arrow drawn
// magnified, and the tolerance as a circle of the same magnification around the point, so an
// arrow that leaves its circle is out of tolerance. Both axes at one scale (mm).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ncqual/charts/chart.hpp"

namespace ncqual::charts {

struct PlaneDeviation {
  double x = 0;  // nominal position in the plane (position unit, e.g. mm)
  double y = 0;
  double dx = 0;      // deviation (caller's unit; the same unit as the positions, e.g. mm, so that
  double dy = 0;      // a magnification of 1000 draws 10 µm as 10 mm)
  std::string label;  // the point's name, for its tooltip
  // Out of tolerance as the caller judged it (e.g. with its 3D deviation); without it: when
  // hypot(dx, dy) > tolerance.
  std::optional<bool> out_of_tolerance;
};

struct DeviationVectorPlot {
  std::string title;        // e.g. "Grid, plane Z = 250 mm"
  std::string description;  // appended to the generated <desc>
  std::string x_name = "X";
  std::string y_name = "Y";
  std::string position_unit = "mm";
  DisplayUnit unit;  // of the deviations, e.g. {1000, "µm"} for deviations in mm
  std::vector<PlaneDeviation> points;
  double tolerance = 0;  // radius (caller's unit); not finite or <= 0: no circles
  // Drawn arrow length = deviation × magnification (in position units). Without it the largest
  // nice value (1, 2, 5 × 10^k) that draws the largest arrow or circle at 40 % of the closest
  // spacing of the points.
  std::optional<double> magnification;
  Size size;  // default 560 × 560
};

inline constexpr Size kVectorPlotSize{560, 560};

// data-chart="deviation-vectors", data-magnification on the root. One <g class="vector pass|fail">
// per point with data-x, data-y, data-dx, data-dy and data-value (the in-plane length, caller's
// unit), holding the tolerance circle, the arrow and the nominal dot. A scale bar under the plot
// says what length of arrow is how many display units.
std::string deviation_vector_plot(const DeviationVectorPlot& chart);

// The magnification the plot uses for `chart` (the given one, or the automatic one).
double vector_magnification(const DeviationVectorPlot& chart);

}  // namespace ncqual::charts
