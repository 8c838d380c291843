// SPDX-License-Identifier: Apache-2.0
#include "ncqual/common/volumetric.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace ncqual::volumetric {

namespace {

constexpr std::array<std::string_view, kNameCount> kNames = {
    "EXX",     "EYX",     "EZX",    "EAX", "EBX", "ECX",  //
    "EXY",     "EYY",     "EZY",    "EAY", "EBY", "ECY",  //
    "EXZ",     "EYZ",     "EZZ",    "EAZ", "EBZ", "ECZ",  //
    "EC(0X)Y", "EB(0X)Z", "EA(0Y)Z"};

void check_range(double lo, double hi) {
  if (!(std::isfinite(lo) && std::isfinite(hi) && hi > lo)) {
    std::ostringstream os;
    os << "ErrorSeries: lo_mm = " << lo << ", hi_mm = " << hi
       << ": the axis range must be finite with hi_mm > lo_mm";
    throw std::invalid_argument(os.str());
  }
}

}  // namespace

int function_index(int axis, int component) {
  if (axis < 0 || axis > 2) {
    throw std::invalid_argument("function_index: axis = " + std::to_string(axis) +
                                ": expected 0 (X), 1 (Y) or 2 (Z)");
  }
  if (component < 0 || component > 5) {
    throw std::invalid_argument("function_index: component = " + std::to_string(component) +
                                ": expected 0..5 (X, Y, Z, A, B, C)");
  }
  return axis * 6 + component;
}

bool is_positioning(int index) {
  return index >= 0 && index < kFunctionCount && index % 6 == index / 6;
}
bool is_straightness(int index) {
  return index >= 0 && index < kFunctionCount && index % 6 < 3 && index % 6 != index / 6;
}
bool is_angular(int index) { return index >= 0 && index < kFunctionCount && index % 6 >= 3; }

std::string_view function_name(int index) {
  if (index < 0 || index >= kNameCount) {
    throw std::invalid_argument("function_name: index = " + std::to_string(index) +
                                ": expected 0..20");
  }
  return kNames[static_cast<std::size_t>(index)];
}

double legendre(int k, double u) {
  if (k < 0)
    throw std::invalid_argument("legendre: k = " + std::to_string(k) + ": expected k >= 0");
  if (k == 0) return 1.0;
  double p_prev = 1.0, p = u;
  for (int n = 1; n < k; ++n) {
    const double p_next = ((2.0 * n + 1.0) * u * p - n * p_prev) / (n + 1.0);
    p_prev = p;
    p = p_next;
  }
  return p;
}

double legendre_derivative(int k, double u) {
  if (k < 0) {
    throw std::invalid_argument("legendre_derivative: k = " + std::to_string(k) +
                                ": expected k >= 0");
  }
  // P'_{n+1} = P'_{n-1} + (2n + 1) P_n, with P'_0 = 0, P'_1 = 1.
  if (k == 0) return 0.0;
  double d_prev = 0.0, d = 1.0;  // P'_0, P'_1
  double p_prev = 1.0, p = u;    // P_0, P_1
  for (int n = 1; n < k; ++n) {
    const double d_next = d_prev + (2.0 * n + 1.0) * p;
    const double p_next = ((2.0 * n + 1.0) * u * p - n * p_prev) / (n + 1.0);
    d_prev = d;
    d = d_next;
    p_prev = p;
    p = p_next;
  }
  return d;
}

double normalized_coordinate(double q_mm, double lo_mm, double hi_mm) {
  check_range(lo_mm, hi_mm);
  return (2.0 * q_mm - lo_mm - hi_mm) / (hi_mm - lo_mm);
}

double ErrorSeries::value(double q_mm) const {
  if (coefficients.empty()) return 0.0;
  const double u = normalized_coordinate(q_mm, lo_mm, hi_mm);
  double sum = coefficients[0];
  double p_prev = 1.0, p = u;
  for (std::size_t k = 1; k < coefficients.size(); ++k) {
    sum += coefficients[k] * p;
    const double n = static_cast<double>(k);
    const double p_next = ((2.0 * n + 1.0) * u * p - n * p_prev) / (n + 1.0);
    p_prev = p;
    p = p_next;
  }
  return sum;
}

double ErrorSeries::derivative(double q_mm) const {
  if (coefficients.empty()) return 0.0;
  const double u = normalized_coordinate(q_mm, lo_mm, hi_mm);
  double sum = 0.0;
  for (std::size_t k = 1; k < coefficients.size(); ++k) {
    sum += coefficients[k] * legendre_derivative(static_cast<int>(k), u);
  }
  return sum * 2.0 / (hi_mm - lo_mm);
}

Eigen::Matrix3d rotation_from_vector(const Eigen::Vector3d& v_rad) {
  const double angle = v_rad.norm();
  if (angle == 0.0) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, v_rad / angle).toRotationMatrix();
}

Eigen::Vector3d actual_position(const RigidBodyErrors& errors,
                                const Eigen::Vector3d& commanded_xyz_mm,
                                const Eigen::Vector3d& tool_offset_mm) {
  const auto f = [&](int axis, int component) {
    return errors.functions[static_cast<std::size_t>(axis * 6 + component)].value(
        commanded_xyz_mm[axis]);
  };
  const double x = commanded_xyz_mm.x(), y = commanded_xyz_mm.y(), z = commanded_xyz_mm.z();
  const Eigen::Vector3d o_x(x + f(kAxisX, kAlongX), f(kAxisX, kAlongY), f(kAxisX, kAlongZ));
  const Eigen::Vector3d o_y(f(kAxisY, kAlongX) - errors.ec0xy_rad * y, y + f(kAxisY, kAlongY),
                            f(kAxisY, kAlongZ));
  const Eigen::Vector3d o_z(f(kAxisZ, kAlongX) + errors.eb0xz_rad * z,
                            f(kAxisZ, kAlongY) - errors.ea0yz_rad * z, z + f(kAxisZ, kAlongZ));
  const auto rot = [&](int axis) {
    return rotation_from_vector(
        Eigen::Vector3d(f(axis, kAboutX), f(axis, kAboutY), f(axis, kAboutZ)));
  };
  return o_x + rot(kAxisX) * (o_y + rot(kAxisY) * (o_z + rot(kAxisZ) * tool_offset_mm));
}

}  // namespace ncqual::volumetric
