// SPDX-License-Identifier: Apache-2.0
// Nominal kinematics of the five-axis post mill: X, Y, Z move the wrist pivot (the point where
// the A and C axes meet); C turns the head about the machine's Z axis; A turns the body about
// the head's own axis (parallel to machine X when C = 0); W moves the spindle along the tool
// axis. At home (A = C = 0) the tool points along -Z.
//
//   tool direction   d(a, c) = Rz(c) * Rx(a) * (0, 0, -1)
//   stylus tip       p = P + Rz(c) * Rx(a) * ( (ox, oy, 0) - (L + w) * e_z )
//
// where P = (x, y, z), L the composite tool length from the A axis to the stylus ball centre
// at W = 0, and (ox, oy) the stylus offset from the tool axis in the body frame.
// The simulator evaluates this with the true (erroneous) parameters, the solver with the
// nominal ones; the difference is what the checks measure.
#pragma once

#include "ncqual/common/model.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ncqual {

struct ProbeGeometry {
  double tool_length_mm = 0;  // L: A axis to stylus ball centre, W at home
  double ball_radius_mm = 0;  // stylus ball radius
  Eigen::Vector2d stylus_offset_mm = Eigen::Vector2d::Zero();  // (ox, oy) in the body frame
};

// Rotation of the wrist, body frame to machine frame.
Eigen::Matrix3d wrist_rotation(double a_rad, double c_rad);

// Unit vector along the tool, from the spindle towards the stylus tip, in the machine frame.
Eigen::Vector3d tool_direction(double a_rad, double c_rad);

// Position of the stylus ball centre in the machine frame.
Eigen::Vector3d stylus_ball_centre(const AxisPosition& axes, const ProbeGeometry& probe);

// An instrument's orientation from yaw, pitch, roll (rad): Rz(yaw) Ry(pitch) Rx(roll), the
// rotation from the instrument's frame to the machine's. The tracker simulator and the
// verification uncertainty model place the laser tracker with it.
Eigen::Matrix3d rotation_from_ypr(const Eigen::Vector3d& ypr_rad);

// A laser tracker's spherical coordinates of a point in its own frame: (range, azimuth about its
// z from its x, elevation from its xy plane), and back. Its encoder noise lives in these.
Eigen::Vector3d tracker_spherical(const Eigen::Vector3d& p);
Eigen::Vector3d tracker_cartesian(const Eigen::Vector3d& range_azimuth_elevation);

}  // namespace ncqual
