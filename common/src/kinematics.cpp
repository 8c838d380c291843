// SPDX-License-Identifier: Apache-2.0
#include "ncqual/common/kinematics.hpp"

#include <algorithm>
#include <cmath>

namespace ncqual {

Eigen::Matrix3d wrist_rotation(double a_rad, double c_rad) {
  return (Eigen::AngleAxisd(c_rad, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(a_rad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d tool_direction(double a_rad, double c_rad) {
  return wrist_rotation(a_rad, c_rad) * Eigen::Vector3d(0, 0, -1);
}

Eigen::Vector3d stylus_ball_centre(const AxisPosition& axes, const ProbeGeometry& probe) {
  const Eigen::Vector3d pivot(axes.x_mm, axes.y_mm, axes.z_mm);
  const Eigen::Vector3d in_body(probe.stylus_offset_mm.x(), probe.stylus_offset_mm.y(),
                                -(probe.tool_length_mm + axes.w_mm));
  return pivot + wrist_rotation(axes.a_rad, axes.c_rad) * in_body;
}

Eigen::Matrix3d rotation_from_ypr(const Eigen::Vector3d& ypr_rad) {
  return (Eigen::AngleAxisd(ypr_rad[0], Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(ypr_rad[1], Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(ypr_rad[2], Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Vector3d tracker_spherical(const Eigen::Vector3d& p) {
  const double r = p.norm();
  return {r, std::atan2(p.y(), p.x()), std::asin(std::clamp(p.z() / r, -1.0, 1.0))};
}

Eigen::Vector3d tracker_cartesian(const Eigen::Vector3d& range_azimuth_elevation) {
  const Eigen::Vector3d& s = range_azimuth_elevation;
  const double ce = std::cos(s[2]);
  return {s[0] * ce * std::cos(s[1]), s[0] * ce * std::sin(s[1]), s[0] * std::sin(s[2])};
}

}  // namespace ncqual
