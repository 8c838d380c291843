// SPDX-License-Identifier: Apache-2.0
// The workpiece holding fixture: a pogo fixture (Universal Holding Fixture), its configurations for
// the weekly checks, and the names the acquisition and the solver share for its touches and its
// zero offsets.
//
// Patent ("Probe Checks of Fixture"): "the fixture has the extendable and retractable pogos
// arranged in a rectangular array of rows that extend parallel to the X axis of the machine and
// columns that extend parallel to the Y axis of the machine. The pogos in each column are mounted
// on a column member that can be translated ... in the X axis direction. The fixture also includes
// actuators ... for translating individual pogos ... along their column member in the Y axis
// direction. Each pogo is also extendable and retractable along the Z axis direction."
//
// Geometry, in the fixture frame (axes parallel to the machine's; its origin is at `origin_mm` in
// the machine frame, so machine = origin + fixture):
//   - column c (1-based) has its pogo axes at X = its commanded X, home X = column_home_x_mm[c-1];
//   - pogo r (1-based row) of every column moves in Y along its column, home Y =
//   row_home_y_mm[r-1];
//   - each pogo extends in Z; its commanded Z is the Z of the top reference face of the vacuum
//     assembly's reference block (the rigid surface the workpiece is pulled against);
//   - the reference block is a square prism centred on the pogo axis: side faces at
//     +- block_size/2 from the axis in X and in Y, top face at the pogo's Z, height block_height
//     below it. Side faces are probed probe_depth below the top face.
//
// Configurations (weekly checks, patent "pre-calibration" and "post-calibration"):
//   - pre-calibration configuration k, 0 <= k < 2 n (n = number of constant-Z planes, 5 by default,
//     so ten configurations in rotation): k < n puts the ODD rows (1, 3, 5, ...) at Z plane k,
//     k >= n puts the EVEN rows (2, 4, ...) at Z plane k - n; every column at its home X, every
//     pogo at its home Y; the rows put at the plane are the ones probed (alternate rows, as in the
//     patent). The other rows stay retracted and are not probed.
//   - post-calibration: every combination of the `postcalibration` Z values (absolute), Y offsets
//     (from each row's home) and X offsets (from each column's home): by default 2 Z x 2 Y x 3 X =
//     12 configurations, index j = (iz * nY + iy) * nX + ix.
//
// Units: mm inside; the config may write inches ("24 in", or keys ending in _in).
#pragma once

#include <Eigen/Core>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual {

// Where the post-calibration puts the pogos (fixture frame, mm).
struct PostCalibrationPattern {
  std::vector<double> z_mm;          // absolute commanded Z of the top reference faces
  std::vector<double> y_offsets_mm;  // from each row's home Y
  std::vector<double> x_offsets_mm;  // from each column's home X
};

struct FixtureConfig {
  std::string fixture_id;  // the Correction target is "fixture:<fixture_id>"
  Eigen::Vector3d origin_mm = Eigen::Vector3d::Zero();  // fixture frame origin, machine frame
  std::vector<double> column_home_x_mm;                 // per column (1-based index c at [c-1])
  std::vector<double> row_home_y_mm;  // per row (1-based index r at [r-1]), same on every column
  std::vector<double> z_planes_mm;    // constant-Z planes, default 0, 6, 12, 18, 24 in
  double block_size_mm = 0;           // reference block: side faces at +- size/2
  double block_height_mm = 0;         // side faces extend this far below the top face
  double probe_depth_mm = 0;          // side touches this far below the top face
  PostCalibrationPattern postcalibration;

  int columns() const { return static_cast<int>(column_home_x_mm.size()); }
  int rows() const { return static_cast<int>(row_home_y_mm.size()); }
  double block_half_size_mm() const { return block_size_mm / 2; }
  // 2 n: odd rows at each of the n planes, then even rows at each.
  int precalibration_configuration_count() const {
    return 2 * static_cast<int>(z_planes_mm.size());
  }
  int postcalibration_configuration_count() const {
    return static_cast<int>(postcalibration.z_mm.size() * postcalibration.y_offsets_mm.size() *
                            postcalibration.x_offsets_mm.size());
  }
  // machine = origin + fixture (the fixture's axes are nominally the machine's).
  Eigen::Vector3d to_machine(const Eigen::Vector3d& fixture_mm) const {
    return origin_mm + fixture_mm;
  }
};

// ---- Pogo labels: "C<column>R<row>", both 1-based, e.g. "C2R3" ----------------------------------
struct PogoId {
  int column = 0;
  int row = 0;
};
std::string pogo_label(int column, int row);
// Parses the grammar only (digits without leading zeros, both >= 1); std::nullopt otherwise.
std::optional<PogoId> parse_pogo_label(std::string_view label);
bool fixture_has_pogo(const FixtureConfig& fixture, const PogoId& pogo);

// One pogo placed by the fixture's control unit: its commanded position in the fixture frame
// (X of its column, Y along the column, Z of the top reference face).
struct PogoPlacement {
  std::string pogo;  // "C2R3"
  int column = 0;    // 1-based
  int row = 0;       // 1-based
  Eigen::Vector3d commanded_mm = Eigen::Vector3d::Zero();
};

enum class RowSelection { All, Odd, Even };
std::string_view to_string(RowSelection rows);
bool row_selected(RowSelection rows, int row);  // row 1-based
// The rows pre-calibration configuration k places and probes: Odd for k < n, Even for k >= n.
RowSelection precalibration_rows(const FixtureConfig& fixture, int k);

// Pre-calibration configuration k (0 <= k < precalibration_configuration_count()): the probed
// pogos, column by column, rows ascending. Throws std::out_of_range naming k and the range.
std::vector<PogoPlacement> precalibration_configuration(const FixtureConfig& fixture, int k);

// Every post-calibration configuration, in index order j = (iz * nY + iy) * nX + ix, each with the
// pogos of the selected rows, column by column, rows ascending.
std::vector<std::vector<PogoPlacement>> postcalibration_configurations(
    const FixtureConfig& fixture, RowSelection rows = RowSelection::All);

// ---- Touch features: "pogo:<label>:cfg<index>:<face>" -------------------------------------------
// e.g. "pogo:C2R3:cfg4:x-". <index> is the configuration index (pre-calibration: k; post-
// calibration: j), decimal without leading zeros. <face> names the reference block face touched
// by its outward normal, and fixes the direction of approach:
//   top  the top reference face, normal +Z, approached along -Z;
//   x-   side face at X - size/2, normal -X, approached along +X;
//   x+   side face at X + size/2, normal +X, approached along -X;
//   y-   side face at Y - size/2, normal -Y, approached along +Y;
//   y+   side face at Y + size/2, normal +Y, approached along -Y.
enum class PogoFace { Top, XMinus, XPlus, YMinus, YPlus };
inline constexpr PogoFace kPogoFaces[] = {PogoFace::Top, PogoFace::XMinus, PogoFace::XPlus,
                                          PogoFace::YMinus, PogoFace::YPlus};
std::string_view to_string(PogoFace face);
Eigen::Vector3d outward_normal(PogoFace face);  // unit, machine frame
// The direction a touch of the face moves in: minus the outward normal, e.g. (1, 0, 0) for x-.
Eigen::Vector3d approach_direction(PogoFace face);
// The face's point on the pogo: top centre + this (block half size h, depth d below the top for
// the sides): top (0, 0, 0); x- (-h, 0, -d); x+ (h, 0, -d); y- (0, -h, -d); y+ (0, h, -d).
Eigen::Vector3d face_offset(const FixtureConfig& fixture, PogoFace face);

struct PogoTouchFeature {
  std::string pogo;  // label
  PogoId id;
  int configuration = 0;
  PogoFace face = PogoFace::Top;
};
std::string pogo_touch_feature(std::string_view pogo, int configuration, PogoFace face);
std::optional<PogoTouchFeature> parse_pogo_touch_feature(std::string_view feature);

// ---- Zero offsets: Correction offsets named "<label>.d<axis>", e.g. "C2R3.dx", unit "mm" --------
// Value: the delta measured - commanded along that axis. The fixture's control unit subtracts the
// accumulated offsets of a pogo from what it commands that pogo's actuators to.
std::string zero_offset_name(std::string_view pogo, int axis);  // axis 0, 1, 2 = x, y, z
struct ZeroOffsetName {
  std::string pogo;
  PogoId id;
  int axis = 0;
};
std::optional<ZeroOffsetName> parse_zero_offset_name(std::string_view name);

// The `fixture:` section of a machine config (see deploy/machines/pm1.yaml for every key) is read
// into FixtureConfig by the configuration layer (common/src/config/fixture_section.cpp).

}  // namespace ncqual
