// SPDX-License-Identifier: Apache-2.0
// Truth for the tracker evaluation tests (master frame, grid), written independently of the code
// under test: a machine with scale, squareness and straightness errors of its linear axes, and a
// tracker placed anywhere.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <random>

namespace ncqual::solver::testing {

// A machine with linear axis errors and straightness, the target position as a function of the
// commanded one (machine frame, mm):
//   p = (1 + sx) c_x e_x + (1 + sy) c_y Rz(exy) e_y + (1 + sz) c_z Ry(ezx) Rx(eyz) e_z
//       + bow_x(c_x) + bow_y(c_y) + offset
// exy turns the Y motion about +Z, eyz the Z motion about +X, ezx the Z motion about +Y: by the
// ISO 230-1 definition, EC(0X)Y = exy, EA(0Y)Z = eyz, EB(0X)Z = ezx. The bows are quadratic
// sags, zero at the ends of the travel (+-half) and `b` in the middle: b (1 - (c/half)^2), in
// the two cross directions.
struct TruthMachine {
  double sx = 0, sy = 0, sz = 0;
  double exy = 0, eyz = 0, ezx = 0;
  double bow_x_in_y = 0, bow_x_in_z = 0, half_x = 1000;
  double bow_y_in_x = 0, bow_y_in_z = 0, half_y = 1000;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();

  Eigen::Vector3d x_motion() const { return (1 + sx) * Eigen::Vector3d::UnitX(); }
  Eigen::Vector3d y_motion() const {
    return (1 + sy) * (Eigen::AngleAxisd(exy, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d::UnitY());
  }
  Eigen::Vector3d z_motion() const {
    return (1 + sz) * (Eigen::AngleAxisd(ezx, Eigen::Vector3d::UnitY()) *
                       Eigen::AngleAxisd(eyz, Eigen::Vector3d::UnitX()) * Eigen::Vector3d::UnitZ());
  }
  Eigen::Vector3d position(const Eigen::Vector3d& c) const {
    const double sag_x = 1 - (c.x() / half_x) * (c.x() / half_x);
    const double sag_y = 1 - (c.y() / half_y) * (c.y() / half_y);
    return x_motion() * c.x() + y_motion() * c.y() + z_motion() * c.z() +
           Eigen::Vector3d(0, bow_x_in_y, bow_x_in_z) * sag_x +
           Eigen::Vector3d(bow_y_in_x, 0, bow_y_in_z) * sag_y + offset;
  }
};

// A tracker placement: machine = rotation * tracker + translation.
struct Placement {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d to_tracker(const Eigen::Vector3d& machine) const {
    return rotation.transpose() * (machine - translation);
  }
};

// A uniformly random orientation, the origin uniform in [-half_range, half_range]^3 mm.
inline Placement random_placement(std::mt19937_64& rng, double half_range) {
  std::normal_distribution<double> g(0, 1);
  Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  std::uniform_real_distribution<double> u(-half_range, half_range);
  Placement p;
  p.rotation = q.toRotationMatrix();
  p.translation = Eigen::Vector3d(u(rng), u(rng), u(rng));
  return p;
}

}  // namespace ncqual::solver::testing
