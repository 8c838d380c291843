// SPDX-License-Identifier: Apache-2.0
// The 21 rigid-body errors of the three linear axes X, Y, Z (ISO 230-1 names) and the actual
// position of a tool point they produce. Shared by the simulator (ground truth) and the solver
// (identification, ncqual/solver/volumetric_identification.hpp).
//
// Machine: X, Y, Z carry the tool (wrist pivot) over the bed; serial chain
// bed -> X carriage -> Y carriage -> Z carriage -> tool. The errors are those of the tool side
// relative to the bed (for a machine that moves the table instead, the signs of that axis'
// errors are those of the tool relative to the table).
//
// Error names per ISO 230-1: for axis K in {X, Y, Z} at its position q, EXK(q), EYK(q), EZK(q)
// are the translational error motions along X, Y, Z (EKK positioning, the other two
// straightness, mm) and EAK(q), EBK(q), ECK(q) the angular error motions about X, Y, Z (rad).
// Squareness (rad): EC(0X)Y (Y axis line rotated about Z from nominal, relative to X),
// EB(0X)Z (Z axis line rotated about Y, relative to X), EA(0Y)Z (Z axis line rotated about X,
// relative to Y).
//
// The actual position of a tool point whose offset from the pivot is t (machine axes at the
// commanded position, mm), at commanded axis positions (x, y, z):
//
//   p = o_X(x) + R_X(x) * ( o_Y(y) + R_Y(y) * ( o_Z(z) + R_Z(z) * t ) )
//   o_X(x) = ( x + EXX(x), EYX(x), EZX(x) )
//   o_Y(y) = ( EXY(y) - EC(0X)Y * y, y + EYY(y), EZY(y) )
//   o_Z(z) = ( EXZ(z) + EB(0X)Z * z, EYZ(z) - EA(0Y)Z * z, z + EZZ(z) )
//   R_K(q) = the rotation by the small rotation vector (EAK(q), EBK(q), ECK(q)),
//            exactly Eigen::AngleAxisd(|v|, v / |v|) (identity for v = 0).
//
// Squareness signs: each is a positive (right-handed) rotation of the second axis' line about
// the named axis. Y rotated by +g about Z moves along (-sin g, cos g, 0), so EC(0X)Y > 0 makes
// the angle between +X and +Y larger than 90 deg; Z rotated by +b about Y moves along
// (sin b, 0, cos b), so EB(0X)Z > 0 makes the angle between +X and +Z smaller than 90 deg;
// Z rotated by +a about X moves along (0, -sin a, cos a), so EA(0Y)Z > 0 makes the angle
// between +Y and +Z larger than 90 deg.
//
// Error functions: a Legendre series in the normalised coordinate u = (2q - lo - hi)/(hi - lo)
// over the axis range [lo, hi]: f(q) = sum_k c_k P_k(u). Outside [lo, hi] the series is simply
// extrapolated.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <string_view>
#include <vector>

namespace ncqual::volumetric {

// Axes and error-motion components, for the index axis * 6 + component.
inline constexpr int kAxisX = 0;
inline constexpr int kAxisY = 1;
inline constexpr int kAxisZ = 2;
inline constexpr int kAlongX = 0;  // translational error along X
inline constexpr int kAlongY = 1;
inline constexpr int kAlongZ = 2;
inline constexpr int kAboutX = 3;  // angular error about X (A)
inline constexpr int kAboutY = 4;  // about Y (B)
inline constexpr int kAboutZ = 5;  // about Z (C)
inline constexpr int kFunctionCount = 18;
// function_name() indices of the squareness errors, after the 18 functions.
inline constexpr int kSquarenessEC0XY = 18;
inline constexpr int kSquarenessEB0XZ = 19;
inline constexpr int kSquarenessEA0YZ = 20;
inline constexpr int kNameCount = 21;

// Index of the error function of `axis` (0..2 = X, Y, Z) and `component` (0..5 = X, Y, Z, A,
// B, C direction of the error motion): axis * 6 + component. Throws std::invalid_argument
// naming the argument when out of range.
int function_index(int axis, int component);

// True for the positioning errors EXX, EYY, EZZ; false for straightness and angular errors.
bool is_positioning(int index);
// True for the straightness errors (translational, across the axis).
bool is_straightness(int index);
// True for the angular errors EAK, EBK, ECK.
bool is_angular(int index);

// ISO 230-1 name: 0..17 -> "EXX", "EYX", "EZX", "EAX", "EBX", "ECX", "EXY", ..., "ECZ";
// 18, 19, 20 -> "EC(0X)Y", "EB(0X)Z", "EA(0Y)Z". Throws std::invalid_argument naming the index
// when outside 0..20.
std::string_view function_name(int index);

// Legendre polynomial P_k(u) (P_0 = 1, P_1 = u, (k+1) P_{k+1} = (2k+1) u P_k - k P_{k-1}), and
// its derivative dP_k/du. Any finite u (not limited to [-1, 1]). Throws std::invalid_argument
// naming k when k < 0.
double legendre(int k, double u);
double legendre_derivative(int k, double u);

// The normalised coordinate u = (2q - lo - hi)/(hi - lo). Throws std::invalid_argument naming
// lo_mm and hi_mm unless hi_mm > lo_mm (both finite).
double normalized_coordinate(double q_mm, double lo_mm, double hi_mm);

// One error function of one axis: f(q) = sum_k coefficients[k] P_k(u(q)) over [lo_mm, hi_mm].
// Coefficients c_0..c_n in mm for translational errors, rad for angular ones.
struct ErrorSeries {
  double lo_mm = 0, hi_mm = 0;
  std::vector<double> coefficients;
  // f(q): 0 when there are no coefficients (whatever the range); otherwise throws
  // std::invalid_argument naming lo_mm and hi_mm unless hi_mm > lo_mm.
  double value(double q_mm) const;
  // df/dq (per mm), same conventions.
  double derivative(double q_mm) const;
};

// The 21 rigid-body errors: functions[axis * 6 + component] (see function_index) and the three
// squareness errors (rad). Default: all zero (the nominal machine).
struct RigidBodyErrors {
  std::array<ErrorSeries, kFunctionCount> functions;
  double ec0xy_rad = 0, eb0xz_rad = 0, ea0yz_rad = 0;
};

// The rotation by the rotation vector v (rad): exactly Eigen::AngleAxisd(|v|, v/|v|), the
// identity for v = 0.
Eigen::Matrix3d rotation_from_vector(const Eigen::Vector3d& v_rad);

// Actual position (mm, machine frame) of the tool point with offset `tool_offset_mm` from the
// pivot at commanded axis positions `commanded_xyz_mm`: the exact chain in the header comment
// (no small-angle approximation). Refuses (std::invalid_argument, from ErrorSeries::value) a
// function with coefficients over an empty range.
Eigen::Vector3d actual_position(const RigidBodyErrors& errors,
                                const Eigen::Vector3d& commanded_xyz_mm,
                                const Eigen::Vector3d& tool_offset_mm);

}  // namespace ncqual::volumetric
