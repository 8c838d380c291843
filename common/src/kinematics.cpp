#include "ncqual/kinematics.hpp"

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

}  // namespace ncqual
