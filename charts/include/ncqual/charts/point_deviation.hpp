// SPDX-License-Identifier: Apache-2.0
// Deviation by point number: one deviation (e.g. the Z deviation of every point of a grid or of
// a part's set points) against the point's number, with the tolerance limits as dashed lines.
#pragma once

#include <string>
#include <vector>

#include "ncqual/charts/chart.hpp"
#include "ncqual/charts/trend.hpp"

namespace ncqual::charts {

struct NumberedDeviation {
  int number = 0;     // the point's number (x axis)
  double value = 0;   // the deviation, caller's unit
  std::string label;  // the marker's tooltip, e.g. the point's name
};

struct PointDeviationChart {
  std::string title;
  std::string description;             // appended to the generated <desc>
  std::string quantity = "deviation";  // the y axis' name, e.g. "Z deviation"
  DisplayUnit unit;                    // e.g. {1000, "µm"} for values in mm
  std::string number_title = "point number";
  std::vector<NumberedDeviation> points;  // any order; drawn joined in order of number
  ToleranceBand tolerance;                // only finite limits are drawn
  Size size;                              // default 720 × 320
};

inline constexpr Size kPointDeviationSize{720, 320};

// data-chart="point-deviation"; markers "point pass|fail" with data-point (the number) and
// data-value (caller's unit, exact). A point outside the tolerance is red and square.
std::string point_deviation_chart(const PointDeviationChart& chart);

}  // namespace ncqual::charts
