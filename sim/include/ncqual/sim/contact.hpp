// SPDX-License-Identifier: Apache-2.0
// The touch engine: where a stylus ball moving along a straight line first meets a surface.
//
// The ball centre moves along c(s) = c0 + s u (u a unit vector, s >= 0 the distance moved).
// A ball of radius r touches a surface when its centre is at distance r from it, so each contact
// is the intersection of the line with the surface offset by r, solved in closed form:
//   plane (point p0, normal n towards free space):  (c(s) - p0) . n = r
//   vertical bore (axis (ax, ay), radius R), ball inside:  |c_xy(s) - a|^2 = (R - r)^2
// A primitive's contact counts only when the contact point lies on the part of the surface the
// body really has (e.g. the bore wall only between the plate's underside and its face). Rims and
// corners are not modelled: a move that would first meet one is reported as meeting nothing.
#pragma once

#include <Eigen/Core>

#include <optional>
#include <string>

namespace ncqual::sim {

struct BallMove {
  Eigen::Vector3d start = Eigen::Vector3d::Zero();       // ball centre at s = 0
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // unit vector
  double travel_mm = 0;                                  // longest distance moved
  double ball_radius_mm = 0;

  Eigen::Vector3d centre_at(double s) const { return start + s * direction; }
};

// Distance s >= 0 at which the ball meets the plane through `point` with unit `normal` pointing
// away from the material, coming from the free side; std::nullopt when it moves parallel to or
// away from the plane or starts beyond it.
//   s = ((c0 - p0) . n - r) / (-u . n),  needs u . n < 0
std::optional<double> ball_meets_plane(const BallMove& move, const Eigen::Vector3d& point,
                                       const Eigen::Vector3d& normal);

// Distance s >= 0 at which a ball inside a vertical bore (axis parallel to Z through `axis_xy`,
// radius `bore_radius`) meets its wall; std::nullopt when it does not start inside the offset
// bore (radius R - r) or moves vertically. With h = c0_xy - a, v = u_xy, rho = R - r:
//   |h + s v|^2 = rho^2  <=>  (v.v) s^2 + 2 (h.v) s + (h.h - rho^2) = 0,
// whose larger root is the exit from the offset bore (the other root lies behind the start).
std::optional<double> ball_meets_bore(const BallMove& move, const Eigen::Vector2d& axis_xy,
                                      double bore_radius);

struct Contact {
  double distance_mm = 0;  // s at contact
  std::string surface;     // which surface of the body was met
  Eigen::Vector3d ball_centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // contact point on the surface
};

// The monument's ring gauge: a plate whose top face is parallel to XY, with a vertical
// cylindrical hole through it and vertical edges at x = hole_x +- width/2 (and, the plate
// being square, y = hole_y +- width/2). Everything in the machine frame, mm.
struct RingGaugePlate {
  Eigen::Vector2d hole_centre_mm = Eigen::Vector2d::Zero();
  double hole_radius_mm = 0;
  double face_z_mm = 0;
  double thickness_mm = 0;
  double width_mm = 0;  // <= 0: the plate has no lateral edges (unbounded)

  double underside_z_mm() const { return face_z_mm - thickness_mm; }
  double half_width_mm() const;  // +inf when unbounded
  // Whether p lies in the closed plate (within `tol`).
  bool contains(const Eigen::Vector3d& p, double tol) const;
  // Whether a ball of `radius` at `centre` cuts into the plate. Conservative at the plate's
  // outer corners and the hole's rims (it treats the plate grown by r as a box minus a bore).
  bool overlaps_ball(const Eigen::Vector3d& centre, double radius) const;
};

// The first surface of the plate the ball meets within the move's travel: the bore wall
// ("hole_edge"), the face ("face"), the underside ("underside") or an edge ("edge_+x",
// "edge_-x", "edge_+y", "edge_-y"); std::nullopt when it meets none.
std::optional<Contact> first_contact(const RingGaugePlate& plate, const BallMove& move);

// A set-point block: an axis-parallel cube of side `size_mm` whose reference corner `corner_mm`
// is at its least X, least Y and top Z (the block extends along +X, +Y and down -Z from it).
struct SetPointBlock {
  Eigen::Vector3d corner_mm = Eigen::Vector3d::Zero();
  double size_mm = 50.0;

  bool contains(const Eigen::Vector3d& p, double tol) const;
};

// The first face of the block the ball meets within the move's travel: "top", "-x", "+x",
// "-y", "+y" or "bottom"; std::nullopt when it meets none (edges and corners not modelled).
std::optional<Contact> first_contact(const SetPointBlock& block, const BallMove& move);

}  // namespace ncqual::sim
