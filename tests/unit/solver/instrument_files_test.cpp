// SPDX-License-Identifier: Apache-2.0
// Readers of instrument exports: good files of each format (extra columns, comments, CRLF, any
// column order) and every kind of bad file, with the exact "<file>:<line>:<column>: " of the
// refusal.
#include "ncqual/solver/instrument_files.hpp"

#include "ncqual/common/config.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <tuple>
#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace ncqual::solver {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The what() of the CsvError that `f` throws, or "(accepted)".
std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const CsvError& e) {
    return e.what();
  }
  return "(accepted)";
}

bool starts_with(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}

// ---- ISO 230-2 ----------------------------------------------------------------------------------

// Example 1 of iso230_2_test.cpp (µm deviations at 0, 100, 200 mm; E = 8 µm, B̄ = 8/3 µm) with
// the columns in another order, an extra column, comments, CRLF and mixed case directions.
const char* kGoodRun =
    "# laser run, axis X\r\n"
    "cycle,direction,target_mm,temperature_C,measured_mm\r\n"  // line 2
    "1,up,0,20.1,0.001\r\n"                                    // line 3
    "2,Up,0,20.1,0.002\r\n"
    "3,UP,0,20.1,0.003\r\n"
    "1,up,100,20.1,100.004\r\n"
    "2,up,100,20.1,100.006\r\n"
    "3,up,100,20.1,100.008\r\n"
    "1,up,200,20.1,199.999\r\n"
    "2,up,200,20.1,200.000\r\n"
    "3,up,200,20.1,200.001\r\n"
    "\r\n"
    "# return\r\n"
    "1,down,0,20.2,-0.002\r\n"  // line 14
    "2,down,0,20.2,-0.001\r\n"
    "3,down,0,20.2,0.000\r\n"
    "1,down,100,20.2,100.002\r\n"
    "2,down,100,20.2,100.003\r\n"
    "3,down,100,20.2,100.004\r\n"
    "1,down,200,20.2,199.997\r\n"
    "2,down,200,20.2,199.998\r\n"
    "3,down,200,20.2,199.999\r\n";  // line 22

TEST(InstrumentFiles, ReadsAnIso230_2Run) {
  const Iso230_2File f = read_iso230_2_csv(kGoodRun, "run.csv");
  EXPECT_EQ(f.file, "run.csv");
  ASSERT_EQ(f.readings.size(), 18u);
  ASSERT_EQ(f.lines.size(), 18u);
  EXPECT_EQ(f.lines.front(), 3);
  EXPECT_EQ(f.lines[9], 14);
  EXPECT_EQ(f.lines.back(), 22);
  EXPECT_EQ(f.readings[1].cycle, 2);
  EXPECT_EQ(f.readings[1].direction, Approach::Up);
  EXPECT_EQ(f.readings[9].direction, Approach::Down);
  EXPECT_DOUBLE_EQ(f.readings[5].target_mm, 100);
  EXPECT_DOUBLE_EQ(f.readings[5].measured_mm, 100.008);
  const Iso230_2Result r = evaluate_iso230_2(f.readings);
  EXPECT_NEAR(*r.E_mm, 0.008, 1e-12);
  EXPECT_NEAR(*r.B_mean_mm, 0.008 / 3, 1e-12);
}

std::string run_error(const std::string& text) {
  return error_of([&] { read_iso230_2_csv(text, "run.csv"); });
}

const char* kRunHeader = "target_mm,cycle,direction,measured_mm\n";

TEST(InstrumentFiles, Iso230_2MissingColumn) {
  EXPECT_EQ(run_error("# x\ntarget_mm,cycle,direction,measured\n0,1,up,0\n"),
            "run.csv:2:4: column 'measured' names no unit: write it as measured_mm, measured_um "
            "or measured_in, or declare the file's unit in a comment before the header ('# "
            "Units: mm')");
}

TEST(InstrumentFiles, Iso230_2NonNumericCell) {
  EXPECT_EQ(run_error(std::string(kRunHeader) + "0,1,up,0.001\n0,2,up,abc\n"),
            "run.csv:3:4: column 'measured_mm' = 'abc': expected a number");
  EXPECT_EQ(run_error(std::string(kRunHeader) + "0,1,up,0.001\n0,1.5,up,0\n"),
            "run.csv:3:2: column 'cycle' = '1.5': expected an integer");
  EXPECT_EQ(run_error(std::string(kRunHeader) + "nan,1,up,0.001\n"),
            "run.csv:2:1: column 'target_mm' = 'nan': expected a finite number");
}

TEST(InstrumentFiles, Iso230_2BadDirectionWord) {
  EXPECT_EQ(run_error(std::string(kRunHeader) + "0,1,up,0\n0,2,left,0\n"),
            "run.csv:3:3: column 'direction' = 'left': expected one of up, +, fwd, forward, pos, "
            "positive, down, -, bwd, back, backward, rev, reverse, neg, negative");
}

TEST(InstrumentFiles, Iso230_2WrongCellCount) {
  EXPECT_EQ(run_error(std::string(kRunHeader) + "0,1,up,0\n0,2,up\n"),
            "run.csv:3:4: 3 cells, but the header (line 1) has 4 columns: target_mm, cycle, "
            "direction, measured_mm");
}

TEST(InstrumentFiles, Iso230_2DuplicateNamesBothLines) {
  std::string text = kGoodRun;
  text += "2,up,100,20.3,100.005\r\n";  // line 23 repeats line 7 (100 mm, cycle 2, up)
  EXPECT_EQ(run_error(text),
            "run.csv:23: target_mm = 100, cycle = 2, direction = up: a second reading of the "
            "same target, cycle and direction (first at line 7)");
}

TEST(InstrumentFiles, Iso230_2TooFewPoints) {
  // One target only: reported at the last data line.
  EXPECT_EQ(run_error(std::string(kRunHeader) + "0,1,up,0\n0,2,up,0\n\n# end\n"),
            "run.csv:3: only 1 target (target_mm = 0); ISO 230-2 needs at least 2 targets");
  // Header only.
  EXPECT_EQ(run_error(std::string("# nothing yet\n") + kRunHeader), "run.csv:2: no readings");
  // One cycle at a target and direction: the line of that reading.
  EXPECT_EQ(run_error(std::string(kRunHeader) + "0,1,up,0\n0,2,up,0\n100,1,up,100\n"),
            "run.csv:4: target_mm = 100, direction = up: 1 cycle; at least 2 are needed for the "
            "standard uncertainty s (n - 1 in its denominator)");
  // A target measured one way only.
  EXPECT_EQ(run_error(std::string(kRunHeader) +
                      "0,1,up,0\n0,2,up,0\n0,1,down,0\n0,2,down,0\n100,1,up,100\n100,2,up,100\n"),
            "run.csv:6: target_mm = 100 has up readings but no down readings, while other "
            "targets do");
}

// ---- Circle -------------------------------------------------------------------------------------

// The hand-worked case of circular_test_test.cpp as a polar file: 8 angles, radius 10 mm plus
// ccw 2 cos 2θ µm and cw 1 + sin 2θ µm (G ccw 0.004, G cw 0.002, G(b) 0.004, H 0.003 mm).
// Data lines 3..10 are ccw, 11..18 cw.
std::string polar_file(bool with_direction = true) {
  std::string text = "# ballbar\n";
  text += with_direction ? "angle_deg,radius_mm,direction,feed_mm_min\n" : "angle_deg,radius_mm\n";
  const double ccw[] = {2, 0, -2, 0, 2, 0, -2, 0}, cw[] = {1, 2, 1, 0, 1, 2, 1, 0};
  for (int dir = 0; dir < (with_direction ? 2 : 1); ++dir) {
    for (int k = 0; k < 8; ++k) {
      char line[96];
      std::snprintf(line, sizeof line, "%d,%.4f", 45 * k, 10 + (dir == 0 ? ccw[k] : cw[k]) * 1e-3);
      text += line;
      if (with_direction) text += dir == 0 ? ",ccw,1000" : ",CW,1000";
      text += "\n";
    }
  }
  return text;
}

TEST(InstrumentFiles, ReadsAPolarCircle) {
  const CircleFile f = read_circle_csv(polar_file(), "c.csv", Plane::XY);
  EXPECT_TRUE(f.polar);
  EXPECT_EQ(f.input.plane, Plane::XY);
  ASSERT_EQ(f.input.points.size(), 16u);
  EXPECT_EQ(f.lines.front(), 3);
  EXPECT_EQ(f.lines.back(), 18);
  EXPECT_EQ(f.input.points[7].direction, PathDirection::Ccw);
  EXPECT_EQ(f.input.points[8].direction, PathDirection::Cw);
  // 90 deg, 9.998 mm -> (0, 9.998).
  EXPECT_NEAR(f.input.points[2].uv_mm.x(), 0, 1e-12);
  EXPECT_NEAR(f.input.points[2].uv_mm.y(), 9.998, 1e-12);
  EXPECT_FALSE(f.input.nominal_radius_mm || f.input.nominal_centre_mm);
  const CircularTestResult r = evaluate_circular_test(f.input);
  EXPECT_NEAR(*r.G_b_mm, 0.004, 1e-9);
  EXPECT_NEAR(*r.H_mm, 0.003, 1e-9);
  // Without a direction column every point is ccw.
  const CircleFile one = read_circle_csv(polar_file(false), "c.csv", Plane::YZ);
  ASSERT_EQ(one.input.points.size(), 8u);
  EXPECT_EQ(one.input.points[5].direction, PathDirection::Ccw);
  EXPECT_EQ(one.input.plane, Plane::YZ);
}

// 12 points of a circle of radius 50 about (100, -20) in the given columns.
std::string coordinate_file(const std::string& header) {
  std::string text = header + "\n";
  for (int k = 0; k < 12; ++k) {
    const double t = k * kPi / 6;
    char line[96];
    std::snprintf(line, sizeof line, "%.9f,%.9f", 100 + 50 * std::cos(t), -20 + 50 * std::sin(t));
    text += line;
    text += "\n";
  }
  return text;
}

TEST(InstrumentFiles, ReadsCoordinateCirclesAndTheirPlane) {
  const CircleFile xz = read_circle_csv(coordinate_file("x_mm,z_mm"), "c.csv", std::nullopt);
  EXPECT_FALSE(xz.polar);
  EXPECT_EQ(xz.input.plane, Plane::XZ);
  const CircularTestResult r = evaluate_circular_test(xz.input);
  EXPECT_NEAR(r.lsc_centre_mm.x(), 100, 1e-6);
  EXPECT_NEAR(r.lsc_centre_mm.y(), -20, 1e-6);
  EXPECT_NEAR(r.lsc_radius_mm, 50, 1e-6);
  EXPECT_EQ(read_circle_csv(coordinate_file("y_mm,z_mm"), "c.csv", Plane::YZ).input.plane,
            Plane::YZ);
  EXPECT_EQ(read_circle_csv(coordinate_file("u_mm,v_mm"), "c.csv", Plane::XZ).input.plane,
            Plane::XZ);
  // x, y and z: the plane argument picks the pair.
  std::string xyz = "x_mm,y_mm,z_mm\n";
  for (int k = 0; k < 8; ++k) {
    xyz += std::to_string(5 * std::cos(k * kPi / 4)) + ",7," +
           std::to_string(5 * std::sin(k * kPi / 4)) + "\n";
  }
  const CircleFile f = read_circle_csv(xyz, "c.csv", Plane::XZ);
  EXPECT_EQ(f.input.plane, Plane::XZ);
  EXPECT_NEAR(f.input.points[2].uv_mm.y(), 5, 1e-6);
  EXPECT_EQ(error_of([&] { read_circle_csv(xyz, "c.csv", std::nullopt); }),
            "c.csv:1: x_mm, y_mm and z_mm name more than one plane: pass the plane (XY, YZ or "
            "XZ); the header has: x_mm, y_mm, z_mm");
}

std::string circle_error(const std::string& text, std::optional<Plane> plane = Plane::XY) {
  return error_of([&] { read_circle_csv(text, "c.csv", plane); });
}

TEST(InstrumentFiles, CirclePlaneMismatchAndMissingPlane) {
  EXPECT_EQ(circle_error(coordinate_file("x_mm,z_mm"), Plane::YZ),
            "c.csv:1:1: the header's x_mm, z_mm name plane XZ, but plane YZ was asked for");
  EXPECT_EQ(circle_error(coordinate_file("u_mm,v_mm"), std::nullopt),
            "c.csv:1: u_mm, v_mm do not name the plane: pass the plane (XY, YZ or XZ); the "
            "header has: u_mm, v_mm");
  EXPECT_EQ(circle_error(polar_file(), std::nullopt),
            "c.csv:2: angle_deg, radius_mm do not name the plane: pass the plane (XY, YZ or "
            "XZ); the header has: angle_deg, radius_mm, direction, feed_mm_min");
}

TEST(InstrumentFiles, CircleMissingColumns) {
  EXPECT_EQ(circle_error("angle_deg,r_mm\n0,10\n"),
            "c.csv:1: an angle but no radius column: expected 'radius_mm' ('Radius (mm)'), or "
            "the radial deviation from the nominal radius ('Deviation (um)'); the header has: "
            "angle_deg, r_mm");
  EXPECT_EQ(circle_error("x_mm,q_mm\n0,10\n"),
            "c.csv:1: no circle columns: expected an angle and a radius ('angle_deg,radius_mm'), "
            "an angle and the radial deviation ('Angle (deg),Deviation (um)' with the radius "
            "declared), or a coordinate pair x_mm,y_mm | y_mm,z_mm | x_mm,z_mm | u_mm,v_mm (any "
            "length unit: mm, um, in); the header has: x_mm, q_mm");
  EXPECT_EQ(circle_error("angle_deg,radius_mm,x_mm,y_mm\n0,10,1,1\n"),
            "c.csv:1: both polar (angle, radius or deviation) and coordinate columns; a circle "
            "file has one layout; the header has: angle_deg, radius_mm, x_mm, y_mm");
  EXPECT_EQ(circle_error("angle_deg,radius_mm,deviation_um\n0,10,1\n"),
            "c.csv:1: both a radius and a radial deviation column; a circle file has one; the "
            "header has: angle_deg, radius_mm, deviation_um");
  // A length without a unit, none declared: refused at the column.
  EXPECT_EQ(circle_error("X,Y\n0,10\n"),
            "c.csv:1:1: column 'X' names no unit: write it as 'X (mm)' (or um, in), or declare "
            "the file's unit in a comment before the header ('# Units: mm')");
  EXPECT_EQ(circle_error("Angle (deg),Deviation (um)\n0,10\n"),
            "c.csv:1:2: column 'Deviation (um)' holds radial deviations from the nominal "
            "radius, which the file does not declare: declare it in a comment before the header "
            "('# Radius: 150 mm') or pass it (--nominal-radius-mm)");
  EXPECT_EQ(circle_error("# Radius: about 150\nAngle (deg),Deviation (um)\n0,10\n"),
            "c.csv:1: the comment declares radius 'about150': expected a number > 0 and its "
            "unit, e.g. '# Radius: 150 mm' (mm, um, in)");
  EXPECT_EQ(circle_error("# Plane: XZ\nangle_deg,radius_mm\n0,10\n", Plane::XY),
            "c.csv:1: the comment declares plane XZ, but plane XY was asked for");
}

TEST(InstrumentFiles, CircleNonNumericAndBadWords) {
  std::string text = polar_file();
  text.replace(text.find("90,9.9980"), 9, "90,9.998x");  // line 5
  EXPECT_EQ(circle_error(text), "c.csv:5:2: column 'radius_mm' = '9.998x': expected a number");
  text = polar_file();
  text.replace(text.find(",CW,"), 4, ",cc,");  // line 11
  EXPECT_EQ(circle_error(text),
            "c.csv:11:3: column 'direction' = 'cc': expected one of ccw, counterclockwise, "
            "counter-clockwise, anticlockwise, anti-clockwise, g3, cw, clockwise, g2");
  text = polar_file();
  text.replace(text.find("90,9.9980"), 9, "90,-9.998");
  EXPECT_EQ(circle_error(text), "c.csv:5:2: column 'radius_mm' = '-9.998': a radius must be > 0");
}

TEST(InstrumentFiles, CircleWrongCellCount) {
  std::string text = polar_file();
  text.replace(text.find("90,9.9980,ccw,1000"), 18, "90,9.9980,ccw");
  EXPECT_EQ(circle_error(text),
            "c.csv:5:4: 3 cells, but the header (line 2) has 4 columns: angle_deg, radius_mm, "
            "direction, feed_mm_min");
}

TEST(InstrumentFiles, CircleTooFewPointsAtTheLastLineOfTheDirection) {
  std::string text = polar_file();
  text.erase(text.rfind("315,"));  // drop the last cw line: 7 cw points, the last on line 17
  EXPECT_EQ(circle_error(text),
            "c.csv:17: direction cw: 7 points; a circular test needs at least 8 per direction "
            "(the fit of the 2θ shape has 5 terms)");
}

TEST(InstrumentFiles, CircleDuplicateAngleNamesBothLines) {
  std::string text = polar_file();
  text += "360,10.0020,ccw,1000\n";  // line 19, 360 = 0 deg of line 3
  EXPECT_EQ(circle_error(text),
            "c.csv:19:1: column 'angle_deg' = 360, direction ccw: the same angle as line 3");
  // A repeated coordinate point (found by the evaluation's check).
  std::string coords = coordinate_file("x_mm,y_mm");
  coords += "150.000000000,-20.000000000\n";  // line 14 repeats line 2 (0 deg)
  const std::string why = circle_error(coords);
  EXPECT_TRUE(starts_with(why, "c.csv:14: direction ccw: u_mm = 150")) << why;
  EXPECT_NE(why.find("the same angle as another point (first at line 2)"), std::string::npos)
      << why;
}

TEST(InstrumentFiles, CircleOfTwoArcsIsRefusedAtTheLineAfterTheSecondGap) {
  // 0..80 and 180..260 deg: two arcs, gaps of 100 deg each.
  std::string text = "angle_deg,radius_mm\n";
  for (int k = 0; k < 5; ++k) text += std::to_string(20 * k) + ",10\n";
  for (int k = 0; k < 5; ++k) text += std::to_string(180 + 20 * k) + ",10\n";
  const std::string why = circle_error(text);
  EXPECT_NE(why.find("the points form more than one arc"), std::string::npos) << why;
  EXPECT_TRUE(starts_with(why, "c.csv:")) << why;
}

TEST(InstrumentFiles, AHalfCircleIsAPartialArc) {
  std::string text = "angle_deg,radius_mm\n";
  for (int k = 0; k < 10; ++k) text += std::to_string(20 * k) + ",10\n";  // 0..180 deg
  const CircleFile f = read_circle_csv(text, "c.csv", Plane::XY);
  const CircularTestResult r = evaluate_circular_test(f.input);
  ASSERT_TRUE(r.ccw);
  EXPECT_FALSE(r.ccw->arc.full_circle);
  EXPECT_NEAR(r.ccw->arc.span_rad, kPi, 1e-9);
}

// ---- Grid ---------------------------------------------------------------------------------------

const char* kGrid =
    "# tracker run 2024-05-01\n"
    "point,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas,rms_um\n"
    "P1,0,0,0,1000.010,2000.020,-3.000,2\n"
    "\"P 2\",500,0,0,1500.012,2000.021,-2.998,2\n"
    "P3,500,400,-100,1500.009,2400.030,-103.001,3\n";

TEST(InstrumentFiles, ReadsAGridRun) {
  const std::vector<GridFilePoint> g = read_grid_csv(kGrid, "g.csv");
  ASSERT_EQ(g.size(), 3u);
  EXPECT_EQ(g[0].point, "P1");
  EXPECT_EQ(g[1].point, "P 2");
  EXPECT_EQ(g[2].line, 5);
  EXPECT_DOUBLE_EQ(g[2].commanded_mm.z(), -100);
  EXPECT_DOUBLE_EQ(g[2].measured_mm.y(), 2400.030);
  EXPECT_DOUBLE_EQ(g[1].measured_mm.x(), 1500.012);
}

std::string grid_error(const std::string& text) {
  return error_of([&] { read_grid_csv(text, "g.csv"); });
}

TEST(InstrumentFiles, GridDuplicatePointNamesBothLines) {
  EXPECT_EQ(grid_error(std::string(kGrid) + "P1,900,0,0,1,2,3,1\n"),
            "g.csv:6:1: point 'P1' repeats line 3");
  EXPECT_EQ(grid_error(std::string(kGrid) + "P4,500,400,-100,1,2,3,1\n"),
            "g.csv:6:2: point 'P4': commanded position (500, 400, -100) repeats point 'P3' on "
            "line 5");
}

TEST(InstrumentFiles, GridMissingColumnNonNumericAndEmpty) {
  EXPECT_EQ(grid_error("point,x_cmd,y_cmd,z_cmd,x_meas,y_meas\nP1,0,0,0,1,2\n"),
            "g.csv:1: missing column 'z_meas'; the header has: point, x_cmd, y_cmd, z_cmd, "
            "x_meas, y_meas");
  EXPECT_EQ(grid_error("point,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas\nP1,0,0,0,1,two,3\n"),
            "g.csv:2:6: column 'y_meas' = 'two': expected a number");
  EXPECT_EQ(grid_error("point,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas\n,0,0,0,1,2,3\n"),
            "g.csv:2:1: column 'point' is empty: name the point");
  EXPECT_EQ(grid_error("# none\npoint,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas\n"),
            "g.csv:2: no points after the header");
  EXPECT_EQ(grid_error(std::string(kGrid) + "P9,1,2,3,4,5,6\n"),
            "g.csv:6:8: 7 cells, but the header (line 2) has 8 columns: point, x_cmd, y_cmd, "
            "z_cmd, x_meas, y_meas, z_meas, rms_um");
}

// A finite but absurd reading (1e300 mm) would pass as a number and turn every figure into inf
// and nan; it is refused at its cell in each format.
TEST(InstrumentFiles, ReadingsNoInstrumentCouldMakeAreRefusedAtTheirCell) {
  EXPECT_EQ(run_error(std::string(kRunHeader) + "0,1,up,0.001\n100,1,up,1e300\n"),
            "run.csv:3:4: column 'measured_mm' = '1e300': beyond \u00b11e+06 mm: no machine or "
            "instrument reaches 1 km");
  EXPECT_EQ(run_error(std::string(kRunHeader) + "-2e6,1,up,0.001\n"),
            "run.csv:2:1: column 'target_mm' = '-2e6': beyond \u00b11e+06 mm: no machine or "
            "instrument reaches 1 km");
  EXPECT_EQ(circle_error("angle_deg,radius_mm\n0,50\n90,1e300\n"),
            "c.csv:3:2: column 'radius_mm' = '1e300': beyond \u00b11e+06 mm: no machine or "
            "instrument reaches 1 km");
  EXPECT_EQ(circle_error("angle_deg,radius_mm\n0,50\n1e300,50\n"),
            "c.csv:3:1: column 'angle_deg' = '1e300': beyond \u00b1100000 deg: a circle test "
            "turns a few times, not hundreds");
  EXPECT_EQ(circle_error("x_mm,y_mm\n50,0\n0,-1e300\n"),
            "c.csv:3:2: column 'y_mm' = '-1e300': beyond \u00b11e+06 mm: no machine or "
            "instrument reaches 1 km");
  EXPECT_EQ(grid_error("point,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas\ng0,0,0,0,0,0,1e300\n"),
            "g.csv:2:7: column 'z_meas' = '1e300': beyond \u00b11e+06 mm: no machine or "
            "instrument reaches 1 km");
  // A kilometre is the bound, not a machine's travel: 1e6 mm itself is still read.
  EXPECT_EQ(run_error(std::string(kRunHeader) + "1e6,1,up,0.001\n").find("beyond"),
            std::string::npos);
}

// ---- Plausibility against the machine -----------------------------------------------------------

// A machine of X 0..2000, Y 0..1000, Z 0..500: span 2000 mm, so positions may lie up to 20000 mm
// beyond the box and deviations may reach 200 mm (a tenth of the span).
Envelope envelope_2000() {
  Envelope e;
  e.hi_mm = Eigen::Vector3d(2000, 1000, 500);
  return e;
}

TEST(InstrumentFiles, EnvelopeRefusesARunInAnotherUnitAtItsCell) {
  const Envelope e = envelope_2000();
  EXPECT_DOUBLE_EQ(e.span_mm(), 2000);
  const CsvTable good = read_csv(kGoodRun, "run.csv");
  EXPECT_EQ(error_of([&] { check_iso230_2_envelope(good, 0, e); }), "(accepted)");
  // On Z (0..500) a target may reach 500 + 20000 mm: 22000 is beyond.
  EXPECT_TRUE(starts_with(error_of([&] {
                            check_iso230_2_envelope(
                                read_csv("target_mm,measured_mm\n0,0\n22000,22000\n", "z.csv"), 2,
                                e);
                          }),
                          "z.csv:3:1: column 'target_mm' = '22000': beyond -20000..20500 mm"));
  // The same on X (0..2000: up to 22000) is accepted.
  EXPECT_EQ(error_of([&] {
              check_iso230_2_envelope(
                  read_csv("target_mm,measured_mm\n0,0\n22000,22000\n", "x.csv"), 0, e);
            }),
            "(accepted)");
  // A run in micrometres read as millimetres: 100 mm = 100000.
  EXPECT_TRUE(starts_with(
      error_of([&] {
        check_iso230_2_envelope(
            read_csv("cycle,target_mm,measured_mm\n1,0,0.5\n1,100000,100004\n", "um.csv"), 0, e);
      }),
      "um.csv:3:2: column 'target_mm' = '100000': beyond -20000..22000 mm"));
  // A deviation of 200.5 mm (more than a tenth of the span) at the measured cell.
  const std::string deviation = error_of([&] {
    check_iso230_2_envelope(read_csv("target_mm,measured_mm\n100,100.001\n300,500.5\n", "d.csv"), 0,
                            e);
  });
  EXPECT_TRUE(starts_with(deviation,
                          "d.csv:3:2: column 'measured_mm' = '500.5': 200.5 mm from "
                          "target_mm 300, more than 200 mm"))
      << deviation;
}

TEST(InstrumentFiles, EnvelopeRefusesACircleBeyondTenSpans) {
  const Envelope e = envelope_2000();
  EXPECT_EQ(error_of([&] {
              check_circle_envelope(read_csv("angle_deg,radius_mm\n0,150\n90,150.001\n", "c.csv"),
                                    e);
            }),
            "(accepted)");
  const std::string far = error_of([&] {
    check_circle_envelope(read_csv("x_mm,y_mm\n150,0\n0,150000\n-150,0\n", "um.csv"), e);
  });
  EXPECT_TRUE(starts_with(far, "um.csv:3:2: column 'y_mm' = '150000': beyond -20000..20000 mm"))
      << far;
}

TEST(InstrumentFiles, EnvelopeRefusesAGridWhoseDistancesAreNotTheCommandedOnes) {
  const Envelope e = envelope_2000();
  // The tracker frame is the machine frame turned by 90 degrees about Z and moved: distances
  // from the first point are kept (500 and 1000 mm; measured 500.002 and 999.998).
  const char* good =
      "point,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas\n"
      "g0,0,0,0,3000,2000,-400\n"
      "g1,500,0,0,3000,2500.002,-400\n"
      "g2,500,1000,0,2000.002,2500,-400\n";
  const auto check = [&](const char* text, const char* file) {
    const CsvTable table = read_csv(text, file);
    check_grid_envelope(table, read_grid_csv(table), e);
  };
  EXPECT_EQ(error_of([&] { check(good, "g.csv"); }), "(accepted)");
  // g2 measured 1e4 mm away in micrometres: |1118.04 - 11180.3| mm apart, far beyond 200 mm.
  const char* bad =
      "point,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas\n"
      "g0,0,0,0,0,0,0\n"
      "g1,500,0,0,500,0,0\n"
      "g2,500,1000,0,5000,10000,0\n";
  const std::string err = error_of([&] { check(bad, "g.csv"); });
  EXPECT_TRUE(starts_with(err,
                          "g.csv:4:5: measured 11180.3 mm from the first point (g0, line 2) "
                          "where commanded 1118.03 mm"))
      << err;
  // A commanded position beyond ten spans: y_cmd 1e5.
  EXPECT_TRUE(starts_with(
      error_of([&] {
        check("point,x_cmd,y_cmd,z_cmd,x_meas,y_meas,z_meas\ng0,0,100000,0,0,0,0\n", "c.csv");
      }),
      "c.csv:2:3: column 'y_cmd' = '100000': beyond -20000..21000 mm"));
}

TEST(InstrumentFiles, TheMachineEnvelopeHoldsEveryProgrammedPosition) {
  // pm1's grid (deploy/machines/pm1.yaml) lies inside the envelope; the box's corners are
  // programmed positions (no slack), and nothing is empty.
  const MachineConfig m = load_machine_config(NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml");
  ASSERT_TRUE(m.global_check);
  const GlobalCheckConfig& gc = *m.global_check;
  const Envelope e = machine_envelope(gc);
  for (double x : gc.grid_x_mm) {
    EXPECT_GE(x, e.lo_mm.x());
    EXPECT_LE(x, e.hi_mm.x());
  }
  for (double z : gc.grid_z_mm) {
    EXPECT_GE(z, e.lo_mm.z());
    EXPECT_LE(z, e.hi_mm.z());
  }
  const auto [gx_lo, gx_hi] = std::minmax_element(gc.grid_x_mm.begin(), gc.grid_x_mm.end());
  EXPECT_LE(e.lo_mm.x(), *gx_lo);
  EXPECT_GE(e.hi_mm.x(), *gx_hi);
  EXPECT_GE(e.span_mm(), *gx_hi - *gx_lo);
}

}  // namespace
// Issue 14: interferometer exports as they really come. Each file of tests/data/instrument/corpus
// is the twin of iso230-2_x.csv written as another instrument or spreadsheet writes it
// (make_corpus.py); each must give the long form's readings and figures.
TEST(InstrumentFiles, Iso230_2ExportsAsTheyComeGiveTheFiguresOfTheirLongFormTwin) {
  const std::string dir = NCQUAL_SOURCE_DIR "/tests/data/instrument/";
  const Iso230_2File long_form = read_iso230_2_csv(read_csv_file(dir + "iso230-2_x.csv"));
  const Iso230_2Result expected = evaluate_iso230_2(long_form.readings);
  struct Twin {
    const char* file;
    double resolution_mm;  // of the twin's numbers
  } twins[] = {
      {"corpus/iso230-2_x_semicolon_um.csv", 1e-9},  // BOM, CRLF, ';', decimal comma, um, +/-
      {"corpus/iso230-2_x_inch_tab.txt", 2e-7},      // tab, inch to 8 decimals, fwd/bwd
      // The wide form, one column per run and direction: deviations in um named by the header
      // ("Run 1 Fwd (µm)", "# Values: deviation"); positions in inches named only by the
      // instrument's header comments ("Cycle 1 +", "# Units: in", "# Values: measured").
      {"corpus/iso230-2_x_wide_um.csv", 1e-9},
      {"corpus/iso230-2_x_wide_declared_in.txt", 2e-7},
  };
  // The readings in one order (the wide form lists them target by target).
  const auto sorted = [](std::vector<PositioningReading> v) {
    std::sort(v.begin(), v.end(), [](const PositioningReading& a, const PositioningReading& b) {
      return std::tie(a.target_mm, a.cycle, a.direction) <
             std::tie(b.target_mm, b.cycle, b.direction);
    });
    return v;
  };
  const std::vector<PositioningReading> want = sorted(long_form.readings);
  for (const Twin& twin : twins) {
    SCOPED_TRACE(twin.file);
    const Iso230_2File f = read_iso230_2_csv(read_csv_file(dir + twin.file));
    ASSERT_EQ(f.readings.size(), long_form.readings.size());
    const std::vector<PositioningReading> got = sorted(f.readings);
    for (std::size_t k = 0; k < got.size(); ++k) {
      const PositioningReading &a = got[k], &b = want[k];
      EXPECT_NEAR(a.target_mm, b.target_mm, twin.resolution_mm) << k;
      EXPECT_NEAR(a.measured_mm, b.measured_mm, twin.resolution_mm) << k;
      EXPECT_EQ(a.cycle, b.cycle) << k;
      EXPECT_EQ(a.direction, b.direction) << k;
    }
    const Iso230_2Result r = evaluate_iso230_2(f.readings);
    ASSERT_EQ(r.targets.size(), expected.targets.size());
    for (const auto& [got, want] :
         {std::pair{r.A_mm, expected.A_mm}, std::pair{r.E_mm, expected.E_mm},
          std::pair{r.M_mm, expected.M_mm}, std::pair{r.R_mm, expected.R_mm},
          std::pair{r.B_mm, expected.B_mm}}) {
      ASSERT_TRUE(got && want);
      EXPECT_NEAR(*got, *want, 4 * twin.resolution_mm);
    }
  }
}

// Circle exports as a ballbar's software, a tracker in inches and a 220 deg partial-arc test
// write them (tests/data/instrument/make_corpus.py), each the twin of circle_xy.csv or of its
// points from -20 to 200 deg.
TEST(InstrumentFiles, CircleExportsAsTheyComeGiveTheFiguresOfTheirTwin) {
  const std::string dir = NCQUAL_SOURCE_DIR "/tests/data/instrument/";
  const CircleFile long_form = read_circle_csv(read_csv_file(dir + "circle_xy.csv"), std::nullopt);
  struct Twin {
    const char* file;
    std::optional<Plane> plane;
    double resolution_mm;  // of the twin's numbers at R 150 mm
  } twins[] = {
      // Angle (deg) to 1e-6 deg (2.6e-6 mm at R), Deviation (µm) to 1e-4 µm, '# Radius: 150 mm',
      // '# Plane: XY', ';' and the decimal comma, Anticlockwise/Clockwise.
      {"corpus/circle_xy_ballbar_um.csv", std::nullopt, 3e-6},
      // X, Y in inches to 8 decimals ('# Units: in'), tab, CCW/CW.
      {"corpus/circle_xy_inch_tab.txt", std::nullopt, 2e-7},
      // The 220 deg arc: angle_deg, deviation_um, the radius declared, the plane passed.
      {"corpus/circle_xy_arc220_um.txt", Plane::XY, 3e-6},
  };
  for (const Twin& twin : twins) {
    SCOPED_TRACE(twin.file);
    const CircleFile f = read_circle_csv(read_csv_file(dir + twin.file), twin.plane);
    EXPECT_EQ(f.input.plane, Plane::XY);
    const bool arc = std::string(twin.file).find("arc220") != std::string::npos;
    // The twin: every long-form point, or those of the arc, in file order.
    CircularTestInput want;
    want.plane = Plane::XY;
    for (const CircularPoint& p : long_form.input.points) {
      double deg = std::atan2(p.uv_mm.y(), p.uv_mm.x()) * 180 / kPi;  // -180 .. 180
      if (deg < -90) deg += 360;                                      // -90 .. 270
      if (!arc || (deg >= -20.5 && deg <= 200.5)) want.points.push_back(p);
    }
    ASSERT_EQ(f.input.points.size(), want.points.size());
    for (std::size_t k = 0; k < want.points.size(); ++k) {
      EXPECT_NEAR((f.input.points[k].uv_mm - want.points[k].uv_mm).norm(), 0, twin.resolution_mm)
          << k;
      EXPECT_EQ(f.input.points[k].direction, want.points[k].direction) << k;
    }
    // A declared radius is the nominal radius; the figures are the twin's.
    const bool declared = std::string(twin.file).find("_um.") != std::string::npos;
    EXPECT_EQ(f.input.nominal_radius_mm, declared ? std::optional<double>(150) : std::nullopt);
    want.nominal_radius_mm = f.input.nominal_radius_mm;
    const CircularTestResult r = evaluate_circular_test(f.input);
    const CircularTestResult e = evaluate_circular_test(want);
    EXPECT_NEAR(r.G_mm, e.G_mm, 2 * twin.resolution_mm);
    EXPECT_NEAR(*r.G_b_mm, *e.G_b_mm, 2 * twin.resolution_mm);
    EXPECT_NEAR(*r.H_mm, *e.H_mm, 4 * twin.resolution_mm);
    EXPECT_NEAR(r.F_max_mm, e.F_max_mm, 2 * twin.resolution_mm);
    EXPECT_NEAR(*r.squareness_urad, *e.squareness_urad, 0.1);
    EXPECT_EQ(r.arc.full_circle, !arc);
    if (arc) {
      // 220 deg from -20 deg, and the shape still resolved: circle_xy.csv's injected X scale
      // +15 µm/m against Y and squareness -20 µrad (X moves with Y: the angle under 90°), within
      // 5 σ = 5 (2/R) σ_r √(2/n) g = 4.5 µm/m or µrad for σ_r 0.4 µm, n 442 and the noise gain
      // g < 2.5 of this arc (2.44; the gain depends on where the arc lies against the axes).
      EXPECT_NEAR(r.arc.span_rad * 180 / kPi, 220, 0.01);
      EXPECT_NEAR(r.arc.from_rad * 180 / kPi, 340, 0.01);
      EXPECT_LT(r.shape_noise_gain, 2.5);
      EXPECT_NEAR(*r.scale_mismatch_um_per_m, 15, 4.5);
      EXPECT_NEAR(*r.squareness_urad, -20, 4.5);
      EXPECT_TRUE(iso230_4_conformance(r).empty());
    }
  }
}

// ---- Tracker point exports ---------------------------------------------------------------------

// A tracker's export of pm1's monthly grid session: every x_run, y_run and grid point (main
// target) named as an operator's tracker software names them ("X_RUN_03", "Grid 17"), in inches
// and a tracker frame turned 90 deg about Z and moved, plus a drift nest "NEST1". Each file and
// its twin in the grid format (commanded from the program, measured in mm) give the same points.
TEST(InstrumentFiles, TrackerPointExportsArePairedWithTheProgramByName) {
  const MachineConfig m = load_machine_config(NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml");
  const GlobalCheckConfig& gc = *m.global_check;
  const auto tracker = [](const Eigen::Vector3d& p) {  // machine -> tracker frame, mm
    return Eigen::Vector3d(p.y() + 2500, -(p.x() - 2200), p.z() - 1000);
  };
  std::map<std::string, std::string> exports;  // prefix -> export text
  std::map<std::string, std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>> expected;
  for (const char* prefix : {"x_run", "y_run", "grid"}) {
    exports[prefix] = "# Units: in\nName\tX\tY\tZ\tRMS\n";
  }
  exports["grid"] += "NEST1\t1.0\t2.0\t3.0\t0.0001\n";
  for (const TrackerMove& mv : global_check_program(CheckKind::GlobalGrid, gc)) {
    if (mv.target != 0) continue;
    const std::string label = mv.label;
    const std::size_t colon = label.find(':');
    const std::string prefix = label.substr(0, colon);
    const int index = std::stoi(label.substr(colon + 1));
    if (!exports.count(prefix)) continue;
    const Eigen::Vector3d nominal = stylus_ball_centre(mv.commanded, gc.targets.front());
    // 1 µm off in x per point, so that a wrong pairing shows.
    const Eigen::Vector3d measured = tracker(nominal) + Eigen::Vector3d(0.001 * index, 0, 0);
    char name[32];
    if (prefix == "grid") {
      std::snprintf(name, sizeof name, "Grid %d", index);
    } else {
      std::snprintf(name, sizeof name, "%s_%02d", prefix == "x_run" ? "X_RUN" : "Y_RUN", index);
    }
    char line[160];
    std::snprintf(line, sizeof line, "%s\t%.8f\t%.8f\t%.8f\t0.0001\n", name, measured.x() / 25.4,
                  measured.y() / 25.4, measured.z() / 25.4);
    exports[prefix] += line;
    expected[prefix].push_back({nominal, measured});
  }
  for (const char* prefix : {"x_run", "y_run", "grid"}) {
    SCOPED_TRACE(prefix);
    const CsvTable table = read_csv(exports[prefix], std::string(prefix) + ".txt");
    EXPECT_TRUE(is_tracker_point_export(table));
    const GridFromExport part = grid_points_from_export(table, prefix, gc);
    const auto& want = expected[prefix];
    ASSERT_EQ(part.points.size(), want.size());
    ASSERT_FALSE(want.empty());
    for (std::size_t k = 0; k < want.size(); ++k) {
      EXPECT_NEAR((part.points[k].commanded_mm - want[k].first).norm(), 0, 1e-12) << k;
      EXPECT_NEAR((part.points[k].measured_mm - want[k].second).norm(), 0, 1e-6) << k;
    }
    EXPECT_EQ(part.ignored.size(), std::string(prefix) == "grid" ? 1u : 0u);
  }
  EXPECT_EQ(grid_points_from_export(read_csv(exports["grid"], "grid.txt"), "grid", gc)
                .ignored.front()
                .name,
            "NEST1");
  EXPECT_FALSE(is_tracker_point_export(read_csv(kGrid, "g.csv")));
  // A point of the program missing: refused, naming it.
  std::string short_run = exports["x_run"];
  short_run.erase(short_run.find("X_RUN_04"), short_run.find('\n', short_run.find("X_RUN_04")) -
                                                  short_run.find("X_RUN_04") + 1);
  EXPECT_TRUE(starts_with(
      error_of([&] { grid_points_from_export(read_csv(short_run, "x.txt"), "x_run", gc); }),
      "x.txt:" + std::to_string(std::count(short_run.begin(), short_run.end(), '\n')) +
          ": 1 of the program's 11 x_run points are not in the export (x_run:4): name each point "
          "as the program labels it ('x_run:0'; case, separators and leading zeros do not "
          "matter: 'X_RUN_00')"))
      << error_of([&] { grid_points_from_export(read_csv(short_run, "x.txt"), "x_run", gc); });
  // The same export declared in millimetres: every distance 25.4 times too short, refused at
  // the first point further from X_RUN_00 than a tenth of the envelope's span.
  std::string wrong_unit = exports["x_run"];
  wrong_unit.replace(0, wrong_unit.find('\n'), "# Units: mm");
  const CsvTable wrong = read_csv(wrong_unit, "x.txt");
  const Envelope envelope = machine_envelope(gc);
  const std::string refused = error_of([&] {
    check_grid_envelope(wrong, grid_points_from_export(wrong, "x_run", gc).points, envelope);
  });
  EXPECT_TRUE(starts_with(refused, "x.txt:")) << refused;
  EXPECT_NE(refused.find(":2: measured "), std::string::npos) << refused;
  EXPECT_NE(refused.find(" from the first point (X_RUN_00, line 3) where the program commands "),
            std::string::npos)
      << refused;
  const CsvTable right = read_csv(exports["x_run"], "x.txt");
  EXPECT_EQ(error_of([&] {
              check_grid_envelope(right, grid_points_from_export(right, "x_run", gc).points,
                                  envelope);
            }),
            "(accepted)");
  // Two names the program compares as one; a coordinate without a unit.
  EXPECT_EQ(error_of([&] {
              read_tracker_points_csv(
                  read_csv("Point,X (mm),Y (mm),Z (mm)\nx_run:3,1,2,3\nX_RUN_03,1,2,3\n", "p.csv"));
            }),
            "p.csv:3:1: point 'X_RUN_03' repeats the point of line 2");
  EXPECT_EQ(
      error_of([&] { read_tracker_points_csv(read_csv("Point,X,Y,Z\nP1,1,2,3\n", "p.csv")); }),
      "p.csv:1:2: column 'X' names no unit: write it as 'X (mm)' (or um, in), or declare "
      "the file's unit in a comment before the header ('# Units: mm')");
}

// The wide form takes what its columns do not say from the instrument's header comments, and
// refuses, saying what to write, what neither says.
TEST(InstrumentFiles, Iso230_2WideFormSaysItsUnitAndValuesOrIsRefused) {
  const Iso230_2File f = read_iso230_2_csv(
      "# Units: um\nTarget,Run 1 Up Error,Run 1 Down Error,Run 2 Up Error,"
      "Run 2 Down Error,Run 3 Up Error,Run 3 Down Error\n0,1,-1,2,0,1,0\n"
      "1000,3,,4,2,3,1\n",
      "wide.csv");
  ASSERT_EQ(f.readings.size(), 11u) << "the empty cell is a reading not taken";
  EXPECT_DOUBLE_EQ(f.readings[6].target_mm, 1.0);
  EXPECT_DOUBLE_EQ(f.readings[6].measured_mm, 1.003);
  EXPECT_EQ(f.readings[7].cycle, 2);
  EXPECT_EQ(f.readings[7].direction, Approach::Up);
  EXPECT_EQ(f.lines[7], 4);  // the second data row, after the comment and the header
  EXPECT_EQ(run_error("Target (mm),Run 1 Fwd,Run 1 Bwd\n0,1,2\n"),
            "run.csv:1:2: column 'Run 1 Fwd' names no unit: write it as 'Run 1 Fwd (um)' (or "
            "mm, in), or declare the file's unit in a comment before the header ('# Units: um')");
  EXPECT_EQ(run_error("Target (mm),Run 1 Fwd (um),Run 1 Bwd (um)\n0,1,2\n"),
            "run.csv:1:2: column 'Run 1 Fwd (um)' does not say whether it holds deviations from "
            "the target or measured positions: name it like 'Run 1 Fwd Error (um)' or 'Run 1 "
            "Fwd Measured (mm)', or say it in a comment before the header ('# Values: "
            "deviation' or '# Values: measured')");
  EXPECT_EQ(run_error("# Units: furlong\nTarget,Run 1 Fwd Error\n0,1\n"),
            "run.csv:1: the comment declares unit 'furlong': expected mm, um or in");
}

// A unit the header does not name is not guessed; a decimal comma only where ',' cannot separate.
TEST(InstrumentFiles, Iso230_2UnitsComeFromTheHeaderAndAreNeverGuessed) {
  EXPECT_EQ(run_error("Target;cycle;direction;measured_mm\n0;1;up;0\n"),
            "run.csv:1:1: column 'Target' names no unit: write it as target_mm, target_um or "
            "target_in ('Target (mm)'), or declare the file's unit in a comment before the "
            "header ('# Units: mm')");
  EXPECT_EQ(run_error("target (ft),cycle,direction,measured_mm\n0,1,up,0\n"),
            "run.csv:1:1: column 'target (ft)': unit 'ft' is not mm, um or in");
  EXPECT_EQ(run_error("target_mm;cycle;direction;error_um\n0;1;up;1.234,5\n"),
            "run.csv:2:4: column 'error_um' = '1.234,5': expected a number with one decimal "
            "comma (no thousands separators)");
  // With ',' separating, "0,5" is two cells.
  EXPECT_EQ(run_error("target_mm,cycle,direction,measured_mm\n0,1,up,0,5\n"),
            "run.csv:2:5: 5 cells, but the header (line 1) has 4 columns: target_mm, cycle, "
            "direction, measured_mm");
  // The deviation form: measured = target + error, in the error's unit.
  const Iso230_2File f = read_iso230_2_csv(
      "target_in;cycle;dir;deviation_um\n1;1;+;2,5\n1;2;+;3\n1;1;-;-1\n1;2;-;0\n"
      "2;1;+;0\n2;2;+;0\n2;1;-;0\n2;2;-;0\n",
      "dev.csv");
  ASSERT_EQ(f.readings.size(), 8u);
  EXPECT_DOUBLE_EQ(f.readings[0].target_mm, 25.4);
  EXPECT_NEAR(f.readings[0].measured_mm, 25.4025, 1e-12);
  EXPECT_EQ(f.readings[2].direction, Approach::Down);
}

}  // namespace ncqual::solver
