// SPDX-License-Identifier: Apache-2.0
// CMM reports (solver/instrument_files.hpp: read_cmm_results) and the part's inspection with its
// best-fit work offset (solver/part_inspection.hpp):
//  - one report of a bracket written as PC-DMIS's text report, a Calypso-like semicolon table
//    with decimal commas and signed lower tolerances, and an inch spreadsheet with the axis in
//    the feature name reads as the same characteristics;
//  - what cannot be read right is refused saying where and what to change;
//  - the offset fit against a hand-worked weighted mean and a constructed rigid displacement.
#include "ncqual/solver/part_inspection.hpp"

#include "ncqual/common/csv.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <optional>
#include <string>

namespace ncqual::solver {
namespace {

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(accepted)";
}

// The bracket, worked in inches (the mm files carry the same values times 25.4, rounded to
// 0.1 µm): PNT1 at (4, 2, 0.5) in, +-0.002 in, its Z 0.003 in high (out); CIR1 at (6, 3) in,
// +-0.004 in, its diameter 1 in +0.001/-0.
const char* kPcDmis =
    "\xEF\xBB\xBFPART NAME  : BRACKET-7\r\n"
    "REV NUMBER :  C          SER NUMBER :  0042\r\n"
    "\r\n"
    "DIM LOC1= LOCATION OF POINT PNT1  UNITS=MM ,$\r\n"
    "GRAPH=OFF  TEXT=OFF  MULT=10.00  OUTPUT=BOTH  HALF ANGLE=NO\r\n"
    "AX    NOMINAL       +TOL       -TOL       MEAS        DEV     OUTTOL\r\n"
    "X     101.6000     0.0508     0.0508   101.6254     0.0254     0.0000 ----#----\r\n"
    "Y      50.8000     0.0508     0.0508    50.7746    -0.0254     0.0000 ----#----\r\n"
    "Z      12.7000     0.0508     0.0508    12.7762     0.0762     0.0254 --------->\r\n"
    "END OF DIMENSION LOC1\r\n"
    "DIM LOC2= LOCATION OF CIRCLE CIR1  UNITS=MM ,$\r\n"
    "GRAPH=OFF  TEXT=OFF  MULT=10.00  OUTPUT=BOTH  HALF ANGLE=NO\r\n"
    "AX    NOMINAL       +TOL       -TOL       MEAS        DEV     OUTTOL\r\n"
    "X     152.4000     0.1016     0.1016   152.4127     0.0127     0.0000 ----#----\r\n"
    "Y      76.2000     0.1016     0.1016    76.2000     0.0000     0.0000 ----#----\r\n"
    "D      25.4000     0.0254     0.0000    25.4203     0.0203     0.0000 -------#-\r\n"
    "END OF DIMENSION LOC2\r\n";

const char* kCalypso =
    "# Units: mm\r\n"
    "Feature;Axis;Nominal;Actual;Deviation;Upper Tol;Lower Tol\r\n"
    "PNT1;X;101,6000;101,6254;0,0254;0,0508;-0,0508\r\n"
    "PNT1;Y;50,8000;50,7746;-0,0254;0,0508;-0,0508\r\n"
    "PNT1;Z;12,7000;12,7762;0,0762;0,0508;-0,0508\r\n"
    "CIR1;X;152,4000;152,4127;0,0127;0,1016;-0,1016\r\n"
    "CIR1;Y;76,2000;76,2000;0,0000;0,1016;-0,1016\r\n"
    "CIR1;D;25,4000;25,4203;0,0203;0,0254;0,0000\r\n";

const char* kInches =
    "Name,Nominal (in),Measured (in),+Tol (in),-Tol (in)\n"
    "PNT1.X,4.0000,4.0010,0.002,0.002\n"
    "PNT1_Y,2.0000,1.9990,0.002,0.002\n"
    "PNT1 Z,0.5000,0.5030,0.002,0.002\n"
    "CIR1.X,6.0000,6.0005,0.004,0.004\n"
    "CIR1.Y,3.0000,3.0000,0.004,0.004\n"
    "CIR1.D,1.0000,1.0008,0.001,0\n";

TEST(CmmResults, OneReportInThreeShapesReadsAsTheSameCharacteristics) {
  const CmmReport text = read_cmm_results(kPcDmis, "bracket.txt");
  const CmmReport table = read_cmm_results(kCalypso, "bracket_chr.txt");
  const CmmReport inches = read_cmm_results(kInches, "bracket.csv");
  EXPECT_EQ(text.format, "PC-DMIS text");
  EXPECT_EQ(table.format, "table");
  ASSERT_EQ(text.characteristics.size(), 6u);
  const char* const features[] = {"PNT1", "PNT1", "PNT1", "CIR1", "CIR1", "CIR1"};
  const char* const axes[] = {"X", "Y", "Z", "X", "Y", "D"};
  // In inches, worked by hand: nominal, deviation, band.
  const double nominal_in[] = {4, 2, 0.5, 6, 3, 1};
  const double deviation_in[] = {0.001, -0.001, 0.003, 0.0005, 0, 0.0008};
  const double lower_in[] = {-0.002, -0.002, -0.002, -0.004, -0.004, 0};
  const double upper_in[] = {0.002, 0.002, 0.002, 0.004, 0.004, 0.001};
  for (const CmmReport* r : {&text, &table, &inches}) {
    SCOPED_TRACE(r->format);
    ASSERT_EQ(r->characteristics.size(), 6u);
    for (std::size_t k = 0; k < 6; ++k) {
      const CmmCharacteristic& c = r->characteristics[k];
      EXPECT_EQ(c.feature, features[k]);
      EXPECT_EQ(c.axis, axes[k]);
      EXPECT_NEAR(c.nominal_mm, nominal_in[k] * 25.4, 1e-9);
      EXPECT_NEAR(c.deviation_mm(), deviation_in[k] * 25.4, 6e-5);  // the 0.1 µm rounding
      ASSERT_TRUE(c.lower_mm && c.upper_mm);
      EXPECT_NEAR(*c.lower_mm, lower_in[k] * 25.4, 1e-9);
      EXPECT_NEAR(*c.upper_mm, upper_in[k] * 25.4, 1e-9);
    }
  }
  EXPECT_EQ(text.characteristics[2].line, 9);
  EXPECT_EQ(inches.characteristics[5].line, 7);
  // Judged: PNT1's Z alone is out.
  const PartInspection p = inspect_part(inches);
  EXPECT_EQ(p.judged, 6);
  EXPECT_EQ(p.out_of_tolerance, 1);
  ASSERT_TRUE(p.pass);
  EXPECT_FALSE(*p.pass);
  EXPECT_FALSE(*p.characteristics[2].in_tolerance);
}

TEST(CmmResults, WhatCannotBeReadRightIsRefusedSayingWhatToChange) {
  // The deviation written as nominal - actual.
  EXPECT_EQ(error_of([] {
              read_cmm_results(
                  "Feature,Axis,Nominal (mm),Actual (mm),Deviation (mm)\n"
                  "P1,X,10.000,10.020,-0.020\n",
                  "r.csv");
            }),
            "r.csv:2:5: the report's deviation -0.02 mm is not actual - nominal (0.02 mm): a "
            "report that writes nominal - actual would be read with its signs backwards; export "
            "the deviation as actual - nominal, or leave the column out");
  // A length without a unit.
  EXPECT_EQ(error_of([] { read_cmm_results("Feature,Nominal,Actual\nP1.X,1,2\n", "r.csv"); }),
            "r.csv:1:2: column 'Nominal' names no unit: write it as 'Nominal (mm)', or declare "
            "the file's unit in a comment before the header ('# Units: mm')");
  // One side of the tolerance.
  EXPECT_NE(error_of([] {
              read_cmm_results("Feature,Nominal (mm),Actual (mm),+Tol (mm)\nP1.X,1,2,0.1\n",
                               "r.csv");
            }).find("r.csv:1: one side of the tolerance only"),
            std::string::npos);
  // The same characteristic twice.
  EXPECT_EQ(error_of([] {
              read_cmm_results("# Units: mm\nFeature,Nominal,Actual\nP1.X,1,2\np1_x,1,2\n",
                               "r.csv");
            }),
            "r.csv:4:1: feature 'p1' axis X repeats the characteristic of line 3");
  // An angle.
  EXPECT_NE(error_of([] {
              read_cmm_results("# Units: mm\nFeature,Axis,Nominal,Actual\nV1,A,90,90.1\n", "r.csv");
            }).find("r.csv:3:2: feature 'V1' axis A is an angle"),
            std::string::npos);
  // PC-DMIS: no unit on the DIM line; a value that is not a number.
  std::string no_unit = kPcDmis;
  no_unit.replace(no_unit.find("  UNITS=MM ,$"), 13, " ,$");
  EXPECT_EQ(error_of([&] { read_cmm_results(no_unit, "b.txt"); }),
            "b.txt:4: DIM PNT1 names no unit: expected UNITS=MM or UNITS=IN on its line");
  std::string bad = kPcDmis;
  bad.replace(bad.find("101.6254"), 8, "101.62x4");
  EXPECT_EQ(error_of([&] { read_cmm_results(bad, "b.txt"); }),
            "b.txt:7: DIM PNT1 axis X: MEAS = '101.62x4': expected a number");
  EXPECT_NE(error_of([] {
              read_cmm_results("# Units: mm\nFeature,Nominal,Actual\n", "e.csv");
            }).find("e.csv: no characteristics"),
            std::string::npos);
}

// Issue 37, point 9: a PC-DMIS report with a TRUE POSITION block, in the layout the issue quotes
// (MEAS second, blank tolerance cells on the X and Y rows, the TP row led by its material
// condition), and in the layout with MEAS after the tolerances and the bonus on the TP row. Before,
// the X row's missing cells refused the whole report ("DIM CIR2 axis X: no MEAS value").
// Worked by hand: CIR3 at (60.015, 29.980) against (60, 30) is off by (0.015, -0.020), 0.025 mm,
// a diametral true position of 0.050 mm, 0.010 over its 0.040 mm zone (RFS, no bonus).
const char* kTruePosition =
    "DIM LOC1= TRUE POSITION OF CIRCLE CIR2  UNITS=MM ,$\n"
    "GRAPH=OFF  TEXT=OFF  MULT=10.00  OUTPUT=BOTH  FIT TO DATUMS=ON  DEV PERPEN CENTERLINE=ON  "
    "DISPLAY=DIAMETER\n"
    "AX    NOMINAL       MEAS    +TOL    -TOL   BONUS     DEV  OUTTOL\n"
    "X     120.000    120.012                            0.012\n"
    "Y      45.000     44.991                            0.009\n"
    "DF     10.000     10.004   0.050   0.050   0.004   0.004   0.000\n"
    "TP     MMC        0.030    0.100                   0.030   0.000\n"
    "END OF DIMENSION LOC1\n"
    "DIM LOC3= TRUE POSITION OF CIRCLE CIR3  UNITS=MM ,$\n"
    "AX        NOMINAL       +TOL       -TOL      BONUS       MEAS        DEV     OUTTOL\n"
    "X         60.0000                                     60.0150     0.0150\n"
    "Y         30.0000                                     29.9800    -0.0200\n"
    "DF        12.0000     0.0500     0.0500               12.0300     0.0300     0.0000\n"
    "TP            RFS     0.0400                0.0000     0.0500     0.0500     0.0100 ---#\n"
    "END OF DIMENSION LOC3\n";

TEST(CmmResults, ATruePositionBlockIsReadRowByRow) {
  const CmmReport r = read_cmm_results(kTruePosition, "tp.txt");
  ASSERT_EQ(r.characteristics.size(), 8u);
  struct Expected {
    const char* feature;
    const char* axis;
    double nominal, actual;
    std::optional<double> lower, upper;
    int line;
  };
  const Expected expected[] = {
      {"CIR2", "X", 120.000, 120.012, std::nullopt, std::nullopt, 4},
      {"CIR2", "Y", 45.000, 44.991, std::nullopt, std::nullopt, 5},
      {"CIR2", "DF", 10.000, 10.004, -0.050, 0.050, 6},
      {"CIR2", "TP", 0, 0.030, 0, 0.100, 7},  // MMC; no bonus on its row
      {"CIR3", "X", 60.0, 60.015, std::nullopt, std::nullopt, 11},
      {"CIR3", "Y", 30.0, 29.980, std::nullopt, std::nullopt, 12},
      {"CIR3", "DF", 12.0, 12.030, -0.050, 0.050, 13},
      {"CIR3", "TP", 0, 0.050, 0, 0.040, 14},
  };
  for (std::size_t k = 0; k < 8; ++k) {
    SCOPED_TRACE(k);
    const CmmCharacteristic& c = r.characteristics[k];
    EXPECT_EQ(c.feature, expected[k].feature);
    EXPECT_EQ(c.axis, expected[k].axis);
    EXPECT_NEAR(c.nominal_mm, expected[k].nominal, 1e-12);
    EXPECT_NEAR(c.actual_mm, expected[k].actual, 1e-12);
    EXPECT_EQ(c.lower_mm.has_value(), expected[k].lower.has_value());
    if (c.lower_mm && expected[k].lower) {
      EXPECT_NEAR(*c.lower_mm, *expected[k].lower, 1e-12);
    }
    if (c.upper_mm && expected[k].upper) {
      EXPECT_NEAR(*c.upper_mm, *expected[k].upper, 1e-12);
    }
    EXPECT_EQ(c.line, expected[k].line);
  }
  // The TP of CIR3 by hand: 2 sqrt(0.015² + 0.020²) = 0.050, over its 0.040 zone.
  EXPECT_NEAR(2 * std::hypot(0.015, 0.020), r.characteristics[7].actual_mm, 1e-12);
  const PartInspection p = inspect_part(r);
  EXPECT_EQ(p.judged, 4);
  EXPECT_EQ(p.out_of_tolerance, 1);
  EXPECT_FALSE(*p.characteristics[7].in_tolerance);
  EXPECT_TRUE(*p.characteristics[3].in_tolerance);

  // A bonus on the TP row widens its zone: 0.040 + 0.015 holds 0.050, and its OUTTOL says so.
  std::string bonus = kTruePosition;
  bonus.replace(bonus.find("0.0000     0.0500     0.0500     0.0100"), 39,
                "0.0150     0.0500     0.0500     0.0000");
  const CmmReport with_bonus = read_cmm_results(bonus, "tp.txt");
  EXPECT_NEAR(*with_bonus.characteristics[7].upper_mm, 0.055, 1e-12);
  EXPECT_TRUE(*inspect_part(with_bonus).pass);
}

TEST(CmmResults, ARowThatCannotBeReadIsRefusedNamingLineAndWhatIsMissing) {
  // A position row without MEAS: NOMINAL + DEV is the measured position.
  std::string no_meas = kTruePosition;
  no_meas.replace(no_meas.find("60.0150     0.0150"), 18, "            0.0150");
  EXPECT_NEAR(read_cmm_results(no_meas, "tp.txt").characteristics[4].actual_mm, 60.015, 1e-12);
  // Neither MEAS nor DEV.
  std::string neither = kTruePosition;
  neither.replace(neither.find("60.0150     0.0150"), 18, "                  ");
  EXPECT_EQ(error_of([&] { read_cmm_results(neither, "tp.txt"); }),
            "tp.txt:11: DIM CIR3 axis X: no MEAS or DEV value (1 value on the line under 7 "
            "columns)");
  // The report's OUTTOL is not what the band read gives: a bonus the TP row does not print.
  std::string hidden_bonus = kTruePosition;
  hidden_bonus.replace(hidden_bonus.find("0.0500     0.0100 ---#"), 22, "0.0500     0.0000 ---#");
  EXPECT_EQ(error_of([&] { read_cmm_results(hidden_bonus, "tp.txt"); }),
            "tp.txt:14: DIM CIR3 axis TP: the report's OUTTOL 0 mm is not what the band 0 .. "
            "0.04 mm gives the deviation 0.05 mm (0.01 mm): a column is not where this reader "
            "looks, or the report counts a bonus its TP row does not print");
  // A deviation that is neither actual - nominal nor its magnitude.
  std::string wrong = kTruePosition;
  wrong.replace(wrong.find("29.9800    -0.0200"), 18, "29.9800    -0.0300");
  EXPECT_NE(error_of([&] { read_cmm_results(wrong, "tp.txt"); })
                .find("tp.txt:12: DIM CIR3 axis Y: the report's deviation -0.03 mm is not actual "
                      "- nominal (-0.02 mm)"),
            std::string::npos);
}

// Translation only (one feature per axis, no whole positions), worked by hand: X deviations
// 0.020 (band +-0.05, weight 1/0.05^2 = 400) and 0.000 (+-0.1, weight 100) give
// (0.020 * 400 + 0) / 500 = 0.016; Y one deviation -0.010; no Z.
TEST(PartInspection, TheOffsetIsTheToleranceWeightedMeanWithoutPositions) {
  CmmReport r;
  const auto add = [&](const std::string& f, const std::string& axis, double dev, double h) {
    CmmCharacteristic c;
    c.feature = f;
    c.axis = axis;
    c.nominal_mm = 100;
    c.actual_mm = 100 + dev;
    c.lower_mm = -h;
    c.upper_mm = h;
    r.characteristics.push_back(c);
  };
  add("A", "X", 0.020, 0.05);
  add("B", "X", 0.000, 0.1);
  add("C", "Y", -0.010, 0.05);
  add("H", "D", 0.5, 0.01);  // a diameter: judged, not fitted
  const PartInspection p = inspect_part(r);
  ASSERT_TRUE(p.fit);
  EXPECT_FALSE(p.fit->rotation_rad);
  EXPECT_NEAR(p.fit->translation_mm.x(), 0.016, 1e-12);
  EXPECT_NEAR(p.fit->translation_mm.y(), -0.010, 1e-12);
  EXPECT_EQ(p.fit->translation_mm.z(), 0);
  EXPECT_EQ(p.fit->axis_resolved, (std::vector<bool>{true, true, false}));
  EXPECT_EQ(p.fit->characteristics, 3);
  EXPECT_NEAR(*p.characteristics[0].after_offset_mm, 0.004, 1e-12);
  EXPECT_NEAR(*p.characteristics[1].after_offset_mm, -0.016, 1e-12);
  EXPECT_FALSE(p.characteristics[3].after_offset_mm);
  EXPECT_EQ(p.out_of_tolerance, 1);  // the diameter
  EXPECT_EQ(p.fit->out_of_tolerance_after, 0);
}

// Issue 37, point 9: one characteristic along Z is no best fit of Z; the fit says so, naming the
// direction and the count, and is silent for X (two characteristics).
TEST(PartInspection, ADirectionOneCharacteristicConstrainsIsWarnedOf) {
  CmmReport r;
  const auto add = [&](const std::string& f, const std::string& axis, double dev) {
    CmmCharacteristic c;
    c.feature = f;
    c.axis = axis;
    c.nominal_mm = 10;
    c.actual_mm = 10 + dev;
    c.lower_mm = -0.05;
    c.upper_mm = 0.05;
    r.characteristics.push_back(c);
  };
  add("A", "X", 0.010);
  add("B", "X", 0.020);
  add("P1", "Z", 0.030);
  const PartInspection p = inspect_part(r);
  ASSERT_TRUE(p.fit);
  EXPECT_EQ(p.fit->constraining, (std::vector<int>{2, 0, 1}));
  EXPECT_NEAR(p.fit->translation_mm.z(), 0.030, 1e-12);  // that one deviation
  ASSERT_EQ(p.fit->warnings.size(), 1u);
  EXPECT_EQ(p.fit->warnings[0],
            "Z: 1 characteristic (P1 Z) constrains the displacement along Z: dz is that "
            "feature's own deviation, not a best fit; measure more features along Z before "
            "correcting the work offset with it");
}

// A part displaced rigidly by t and turned by w about the report's origin: the features' X, Y, Z
// deviations are t + w x p exactly (constructed here from the definition of the cross product);
// the fit finds t and w whatever the weights, leaves nothing, and leaves out the feature whose
// position the report does not give whole.
TEST(PartInspection, ARigidDisplacementAndTurnAreFoundFromWholePositions) {
  const Eigen::Vector3d t(0.030, -0.020, 0.010);
  const Eigen::Vector3d w(50e-6, -80e-6, 120e-6);
  const Eigen::Vector3d corners[] = {
      {0, 0, 0}, {200, 0, 10}, {200, 100, 50}, {0, 100, 20}, {100, 50, -30}};
  CmmReport r;
  for (int i = 0; i < 5; ++i) {
    const Eigen::Vector3d& p = corners[i];
    const Eigen::Vector3d d =
        t + Eigen::Vector3d(w.y() * p.z() - w.z() * p.y(), w.z() * p.x() - w.x() * p.z(),
                            w.x() * p.y() - w.y() * p.x());
    for (int k = 0; k < 3; ++k) {
      CmmCharacteristic c;
      c.feature = "P" + std::to_string(i + 1);
      c.axis = std::string(1, static_cast<char>('X' + k));
      c.nominal_mm = p(k);
      c.actual_mm = p(k) + d(k);
      c.lower_mm = -(0.02 + 0.01 * i);  // uneven weights
      c.upper_mm = 0.02 + 0.01 * i;
      r.characteristics.push_back(c);
    }
  }
  CmmCharacteristic lone;  // only X of Q's position
  lone.feature = "Q";
  lone.axis = "X";
  lone.nominal_mm = 50;
  lone.actual_mm = 50.3;
  r.characteristics.push_back(lone);
  const PartInspection p = inspect_part(r);
  ASSERT_TRUE(p.fit);
  ASSERT_TRUE(p.fit->rotation_rad);
  EXPECT_LT((p.fit->translation_mm - t).norm(), 1e-12);
  EXPECT_LT((*p.fit->rotation_rad - w).norm(), 1e-14);
  EXPECT_LT(p.fit->max_abs_after_mm, 1e-12);
  EXPECT_EQ(p.fit->characteristics, 15);
  ASSERT_EQ(p.fit->left_out.size(), 1u);
  EXPECT_EQ(p.fit->left_out[0], "Q: not all of its X, Y and Z are in the report");
  EXPECT_FALSE(p.characteristics.back().after_offset_mm);
  // Three features in a line do not resolve a turn about it: translation only.
  CmmReport line;
  for (const CmmCharacteristic& c : r.characteristics) {
    if (c.feature == "P1" || c.feature == "P2") line.characteristics.push_back(c);
  }
  for (CmmCharacteristic c : r.characteristics) {
    if (c.feature != "P1") continue;
    c.feature = "P6";  // at the origin too: on the line through P1 and P2
    line.characteristics.push_back(c);
  }
  const PartInspection collinear = inspect_part(line);
  ASSERT_TRUE(collinear.fit);
  EXPECT_FALSE(collinear.fit->rotation_rad);
}

}  // namespace
}  // namespace ncqual::solver
