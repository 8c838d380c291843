// SPDX-License-Identifier: Apache-2.0
// Circular tests per ISO 230-4 (circular tests for numerically controlled machine tools): the
// machine interpolates a circle in one plane with two linear axes, clockwise and/or
// counter-clockwise, and an instrument (ballbar, grid encoder, tracker) records the actual path.
//
// Coordinates: (u, v) in mm are the plane's first and second axis (XY: u = X, v = Y; YZ: u = Y,
// v = Z; XZ: u = X, v = Z); the angle θ is measured counter-clockwise from +u towards +v.
// "ccw" is the path traced with increasing θ, "cw" with decreasing θ. (For XZ, θ from +X
// towards +Z is clockwise seen from +Y: the right-hand sense about +Y runs from Z to X.)
//
// Figures (mm unless named otherwise):
//   LSC          least-squares circle: the centre and radius minimising Σ (|p_i - c| - r)²
//                (solver::fit_circle: algebraic start, then Gauss-Newton/Levenberg-Marquardt).
//   G            circular deviation of one path: max r_i - min r_i of its points, r_i = |p_i - c|
//                about the LSC centre of that path (ISO 230-4 allows the LSC or the minimum zone
//                centre; this is the LSC one).
//   G(b)         bidirectional circular deviation: the same over the points of both paths about
//                the LSC centre fitted to both paths together.
//   H            circular hysteresis: the largest |r_ccw(θ) - r_cw(θ)| between the two paths,
//                both about the common (both-paths) LSC centre, each point of one path compared
//                with the other path's radius at the same θ (linear interpolation in θ between
//                its two neighbouring points).
//   F_max, F_min radial deviation: max and min of r_i - R0, with r_i about the nominal centre
//                when one is given, else about the LSC centre (of the path, or of both paths for
//                the test as a whole); R0 the nominal radius when given, else the LSC radius of
//                the same fit. The result says which reference it used. With neither given,
//                F_max - F_min = G (per path) and G(b) (both paths).
//
// Shape (scale mismatch and squareness): about the LSC centre, the radial residuals are fitted
// by least squares with
//     r(θ) - R = a0 + a1 cos θ + b1 sin θ + a2 cos 2θ + b2 sin 2θ.
// Derivation: let the machine move a commanded point p = R (cos θ, sin θ) (about the circle's
// centre) to p' = ((1 + s_u) u - ε v, (1 + s_v) v): axis scale errors s_u, s_v (actual travel /
// commanded - 1), and a v axis whose motion leans by ε towards -u, i.e. runs along (-ε, 1),
// at an angle of 90° + ε to the u motion (ε > 0: the angle between the axis motions exceeds
// 90°). To first order in s_u, s_v, ε:
//     |p'| = R + R (s_u cos²θ + s_v sin²θ - ε cos θ sin θ)
//          = R + R (s_u + s_v)/2 + R (s_u - s_v)/2 cos 2θ - (R ε / 2) sin 2θ,
// so a2 = R (s_u - s_v)/2 and b2 = -R ε / 2:
//     scale mismatch  s_u - s_v = 2 a2 / R   (reported in µm/m: × 1e6)
//     squareness      ε         = -2 b2 / R  (reported in µrad: × 1e6; > 0 when the angle
//                                             between the actual axis motions exceeds 90°)
// The common scale (s_u + s_v)/2 is in the LSC radius, a centre offset in the LSC centre; a1
// and b1 are zero about the LSC centre to first order and are reported as a check. A reversal
// error (backlash) of one axis also has a sin 2θ (or cos 2θ) component, of opposite signs in the
// two directions (e.g. a backlash b on u gives b2 = ±4b/(3π) for ccw/cw): the figures of one
// path carry it, those of both paths fitted together cancel it. Use the both-path figures for
// the axes' geometry when both directions were measured.
//
// Full circles and partial arcs. ISO 230-4 traces a full circle, or a partial arc where the
// machine cannot go round (its 90° and 220° tests, e.g. in a vertical plane a ballbar's arm
// cannot pass the table). A path whose largest angular gap between neighbouring points (about
// its LSC centre, the gap across 0 included) is at most 60° is a full circle: 60° leaves room
// above the 45° gaps of the smallest test (8 evenly spaced points, whose angles about a fitted
// centre jitter). A larger gap is the part of the circle the arc does not cover: the path is an
// arc of 360° - gap, from the point after the gap counter-clockwise to the point before it. G, F
// and G(b) are then those of the arc; H compares the two paths where both were measured (the
// overlap of their arcs), never across a gap; and the shape is given only where the points
// resolve it:
//   the 2θ terms are reported (scale mismatch, squareness, the harmonics) when the noise gain
//   of a2 and b2 is at most 3, the gain being the ratio of the coefficient's standard deviation
//   to that of the same number of points evenly spaced round a full circle (σ √(2/n)):
//   sqrt(n/2 [(AᵀA)⁻¹]_kk) of the design A above. A full circle has a gain about 1; a 220° arc
//   about 2; a 180° arc 4.3 and a 90° arc 51, so short arcs give G, F and H only. (Over an arc
//   the LSC centre and the first harmonics take up part of the 2θ shape; the gain says how much
//   noise is left in what remains.)
//
// Refusals (std::invalid_argument naming the field and value):
//   - fewer than 8 points in a direction: the harmonic fit has 5 coefficients and the second
//     harmonic (two periods per turn) needs at least 4 points per period to be resolved in both
//     its cos and sin parts; 8 evenly spaced points do that and leave 3 residual degrees of
//     freedom;
//   - points in more than one arc: a second gap above 60° besides the largest (a test measures
//     one circle or one arc; two arcs in one direction are two tests);
//   - non-finite coordinates, nominal radius or centre; a nominal radius <= 0;
//   - two points of one direction at the same angle (within 1e-9 rad) about the path's LSC
//     centre (a duplicated reading);
//   - points that admit no circle (fit_circle's refusals: collinear, coincident).
// Where a test departs from ISO 230-4 (an arc shorter than 90°, points sparser than one every
// 10° of arc, one direction only, directions over different arcs) it is still evaluated;
// iso230_4_conformance says so.
#pragma once

#include "ncqual/common/units.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual::solver {

enum class Plane { XY, YZ, XZ };
std::string_view to_string(Plane p);  // "XY", "YZ", "XZ"
// The plane named "XY", "YZ" or "XZ" in any case ("xy"), else nullopt; "YX", "ZY" and "ZX" are
// refused (they would swap u and v).
std::optional<Plane> parse_plane(std::string_view text);

enum class PathDirection { Ccw, Cw };
std::string_view to_string(PathDirection d);  // "ccw", "cw"

struct CircularPoint {
  Eigen::Vector2d uv_mm = Eigen::Vector2d::Zero();  // actual position in the plane
  PathDirection direction = PathDirection::Ccw;
};

// The point at angle theta_rad (counter-clockwise from +u) and radius_mm about (0, 0).
CircularPoint circular_point_from_polar(double theta_rad, double radius_mm,
                                        PathDirection direction);

struct CircularTestInput {
  Plane plane = Plane::XY;
  std::vector<CircularPoint> points;        // one or both directions, any order
  std::optional<double> nominal_radius_mm;  // R0
  std::optional<Eigen::Vector2d> nominal_centre_mm;
};

// Why the input cannot be evaluated: the point at fault (index into points; none for the input
// as a whole or for a direction with too few points), the earlier point a duplicate repeats, and
// a message naming fields and values but not indices (a file reader says lines instead).
struct CircularTestProblem {
  std::optional<std::size_t> index;
  std::optional<std::size_t> first_index;
  std::string message;
};

// The first problem of the list in the file comment, or nullopt when the input can be
// evaluated. For "fewer than 8 points" `index` is the last point of that direction.
std::optional<CircularTestProblem> find_circular_test_problem(const CircularTestInput& input);

// r(θ) - R = a0 + a1 cos θ + b1 sin θ + a2 cos 2θ + b2 sin 2θ (mm), about an LSC centre.
struct RadialHarmonics {
  double a0_mm = 0, a1_mm = 0, b1_mm = 0, a2_mm = 0, b2_mm = 0;
  double residual_rms_mm = 0;  // RMS of what the five terms leave
};

// Where F was measured from.
struct RadialReference {
  bool nominal_centre = false;  // true: the given nominal centre; false: the LSC centre
  bool nominal_radius = false;  // true: the given R0; false: the LSC radius
  Eigen::Vector2d centre_mm = Eigen::Vector2d::Zero();
  double radius_mm = 0;
};

// The part of the circle a path covers, about its LSC centre: a full circle (largest gap <= 60°)
// or the arc from `from_rad` (in [0, 2π), the point after the gap) counter-clockwise over
// `span_rad` (2π - the gap) to the point before the gap. A full circle has from 0, span 2π.
struct CircularArc {
  bool full_circle = true;
  double from_rad = 0;
  double span_rad = 2 * units::kPi;
};

// The figures of one path (one direction).
struct CircularPathFigures {
  PathDirection direction = PathDirection::Ccw;
  int point_count = 0;
  Eigen::Vector2d lsc_centre_mm = Eigen::Vector2d::Zero();
  double lsc_radius_mm = 0;
  double lsc_rms_mm = 0;  // RMS of |p_i - c| - r about the LSC
  double G_mm = 0;        // circular deviation about this path's LSC centre
  double F_max_mm = 0;    // radial deviation, reference in F_reference
  double F_min_mm = 0;
  RadialReference F_reference;
  double max_gap_rad = 0;  // largest angular gap between neighbouring points
  CircularArc arc;
  // The 2θ shape, when the points resolve it (see above), about this path's LSC centre.
  double shape_noise_gain = 1;                    // the larger gain of a2 and b2
  std::optional<RadialHarmonics> harmonics;       // about this path's LSC centre
  std::optional<double> scale_mismatch_um_per_m;  // 2 a2 / R × 1e6 (this path alone)
  std::optional<double> squareness_urad;          // -2 b2 / R × 1e6 (this path alone)
};

struct CircularTestResult {
  Plane plane = Plane::XY;
  std::optional<CircularPathFigures> ccw;
  std::optional<CircularPathFigures> cw;
  // LSC of all points (both paths, or the one path).
  Eigen::Vector2d lsc_centre_mm = Eigen::Vector2d::Zero();
  double lsc_radius_mm = 0;
  double G_mm = 0;               // the larger G of the measured paths
  std::optional<double> G_b_mm;  // both paths measured only
  std::optional<double> H_mm;    // both paths measured, over the angles both cover
  double H_overlap_rad = 0;      // the span of angles H compared (2π: all of a full circle)
  double F_max_mm = 0;           // over all points, about F_reference
  double F_min_mm = 0;
  RadialReference F_reference;  // nominal centre/R0 when given, else the all-points LSC
  CircularArc arc;              // of all points about the all-points LSC centre
  double shape_noise_gain = 1;
  std::optional<RadialHarmonics> harmonics;       // all points about the all-points LSC centre
  std::optional<double> scale_mismatch_um_per_m;  // u scale - v scale, from all points
  std::optional<double> squareness_urad;  // > 0: angle between the u and v motions exceeds 90°
};

// A point about a reference (the F of one point, for polar plots): its angle about the centre
// (counter-clockwise from +u, in [0, 2π)) and its radial deviation |p - c| - R0 (mm). F_max and
// F_min are the extremes of the deviations about F_reference.
struct RadialDeviation {
  double angle_rad = 0;
  double deviation_mm = 0;
};
RadialDeviation radial_deviation_about(const Eigen::Vector2d& p, const RadialReference& reference);

// Evaluates the test. Throws std::invalid_argument "evaluate_circular_test: points[k]: <problem>"
// for the problems find_circular_test_problem finds.
CircularTestResult evaluate_circular_test(const CircularTestInput& input);

// Where the evaluated test departs from ISO 230-4 (or from what its figures need), one sentence
// each, in the order: per direction an arc shorter than 90° and points sparser than one every
// 10° of arc (G is a max − min of the radii: at 10° it reads a shape of up to 4 lobes per turn
// within 6 %, 1 − cos 20°, and misses reversal spikes narrower than the spacing), a partial arc
// whose shape is not resolved; one direction only; two directions over different arcs. Empty
// when it conforms.
std::vector<std::string> iso230_4_conformance(const CircularTestResult& result);

}  // namespace ncqual::solver
