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
  // Drawn arrow length = deviation × magnification (in position units). Without it: from the
  // largest deviation and the closest spacing of the points (vector_magnification), never from
  // the tolerance, so that the arrows are seen whatever the tolerance. Tolerance circles whose
  // radius would pass half the spacing are not drawn (the legend and the <desc> say so; points
  // out of tolerance are red all the same).
  std::optional<double> magnification;
  Size size;  // default 560 × 560
};

inline constexpr Size kVectorPlotSize{560, 560};

// data-chart="deviation-vectors", data-magnification on the root. One <g class="vector pass|fail">
// per point with data-x, data-y, data-dx, data-dy and data-value (the in-plane length, caller's
// unit), holding the tolerance circle, the arrow and the nominal dot. A scale bar under the plot
// says what length of arrow is how many display units.
std::string deviation_vector_plot(const DeviationVectorPlot& chart);

// The magnification the plot uses for `chart`: the given one, or the largest value of the 1-2-5
// series that draws the largest deviation at most 0.8 of the closest spacing of the points (so
// at least 0.32 of it), raised along the series until that arrow is at least 8 px long when
// `px_per_unit` (the plot's pixels per position unit; 0: unknown) is given. Without a deviation
// the tolerance stands for it; without either, 1. The plot prints it: the legend ("deviation
// ×2000"), the scale bar (a nice length of deviation and "arrows ×2000"), data-magnification.
double vector_magnification(const DeviationVectorPlot& chart, double px_per_unit = 0);

}  // namespace ncqual::charts
