// SPDX-License-Identifier: Apache-2.0
// The polar plot of a circular test (ISO 230-4, ballbar): the radial deviation against the
// angle, drawn around a reference circle with the deviation magnified, one trace per direction
// (CCW and CW), rings at a round number of display units apart, angles labelled.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ncqual/charts/chart.hpp"

namespace ncqual::charts {

// One point of a trace: the angle (radians, counter-clockwise from +u, the plane's first axis)
// and the radial deviation from the reference circle (caller's unit; outwards positive).
struct PolarSample {
  double angle_rad = 0;
  double deviation = 0;
};

struct PolarTrace {
  std::string label;                 // "CCW", "CW"
  std::vector<PolarSample> samples;  // any order; drawn in order of angle
};

struct PolarChart {
  std::string title;
  std::string description;
  std::string u_name = "X";  // the plane's axes: 0° is +u, 90° is +v
  std::string v_name = "Y";
  DisplayUnit unit;  // of the deviations, e.g. {1000, "µm"}
  // The first trace accent and solid, the second black and dashed, any further grey, dotted.
  std::vector<PolarTrace> traces;
  // Display units between rings; without it a 1-2-5 step that puts the largest deviation
  // within three rings of the reference circle.
  std::optional<double> ring_step;
  Size size;  // default 520 × 560
};

inline constexpr Size kPolarSize{520, 560};

// Where the plot puts things (px): its centre, the radius of the reference circle (deviation
// 0), and px per display unit of deviation. A deviation d (caller's unit) at angle θ is drawn at
// radius reference_px + d × unit.scale × px_per_unit, at (cx + r cos θ, cy − r sin θ).
struct PolarGeometry {
  double cx = 0;
  double cy = 0;
  double outer_px = 0;      // the outermost ring
  double reference_px = 0;  // the reference circle
  double px_per_unit = 0;   // px per display unit of deviation
  double ring_step = 0;     // display units between rings
  int rings = 0;            // rings on each side of the reference circle
};
PolarGeometry polar_geometry(const PolarChart& chart);

// data-chart="polar"; one <path class="trace"> per trace with data-trace (its label) and
// data-points; rings as <circle class="ring"> with data-value (display units).
std::string polar_chart(const PolarChart& chart);

}  // namespace ncqual::charts
