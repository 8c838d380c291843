// SPDX-License-Identifier: Apache-2.0
#include "ncqual/sim/contact.hpp"

#include <cmath>
#include <limits>
#include <vector>

namespace ncqual::sim {
namespace {

// Contact points computed in machine coordinates (~1e3 mm) carry rounding of ~1e-13 mm.
constexpr double kOnSurfaceTolMm = 1e-9;

}  // namespace

std::optional<double> ball_meets_plane(const BallMove& move, const Eigen::Vector3d& point,
                                       const Eigen::Vector3d& normal) {
  const double closing = -move.direction.dot(normal);  // rate at which the gap shrinks
  if (!(closing > 0)) return std::nullopt;
  const double gap = (move.start - point).dot(normal) - move.ball_radius_mm;
  if (gap < -kOnSurfaceTolMm) return std::nullopt;  // starts beyond the plane
  return std::max(0.0, gap / closing);
}

std::optional<double> ball_meets_bore(const BallMove& move, const Eigen::Vector2d& axis_xy,
                                      double bore_radius) {
  const double rho = bore_radius - move.ball_radius_mm;
  if (!(rho > 0)) return std::nullopt;  // the ball does not fit in the bore
  const Eigen::Vector2d h = move.start.head<2>() - axis_xy;
  const Eigen::Vector2d v = move.direction.head<2>();
  const double a = v.squaredNorm();
  const double b = h.dot(v);
  const double c = h.squaredNorm() - rho * rho;
  if (!(a > 0)) return std::nullopt;                       // vertical move: never meets the wall
  if (c > 2 * rho * kOnSurfaceTolMm) return std::nullopt;  // not inside the offset bore
  const double root = std::sqrt(std::max(0.0, b * b - a * c));
  // Larger root (-b + root) / a, written without cancellation when b > 0:
  //   (-b + root) / a = -c / (b + root).
  const double s = b > 0 ? -c / (b + root) : (-b + root) / a;
  return std::max(0.0, s);
}

double RingGaugePlate::half_width_mm() const {
  return width_mm > 0 ? width_mm / 2 : std::numeric_limits<double>::infinity();
}

bool RingGaugePlate::contains(const Eigen::Vector3d& p, double tol) const {
  const double half = half_width_mm();
  return p.z() <= face_z_mm + tol && p.z() >= underside_z_mm() - tol &&
         std::abs(p.x() - hole_centre_mm.x()) <= half + tol &&
         std::abs(p.y() - hole_centre_mm.y()) <= half + tol &&
         (p.head<2>() - hole_centre_mm).norm() >= hole_radius_mm - tol;
}

bool RingGaugePlate::overlaps_ball(const Eigen::Vector3d& centre, double radius) const {
  const double half = half_width_mm();
  const double margin = radius - kOnSurfaceTolMm;
  return centre.z() < face_z_mm + margin && centre.z() > underside_z_mm() - margin &&
         std::abs(centre.x() - hole_centre_mm.x()) < half + margin &&
         std::abs(centre.y() - hole_centre_mm.y()) < half + margin &&
         (centre.head<2>() - hole_centre_mm).norm() > hole_radius_mm - margin;
}

std::optional<Contact> first_contact(const RingGaugePlate& plate, const BallMove& move) {
  const double r = move.ball_radius_mm;
  std::optional<Contact> best;
  // Keeps the contact if its point is on the real plate and it comes first within the travel.
  auto consider = [&](const std::optional<double>& s, const char* surface,
                      const Eigen::Vector3d& point_offset_dir) {
    if (!s || *s > move.travel_mm) return;
    if (best && best->distance_mm <= *s) return;
    const Eigen::Vector3d centre = move.centre_at(*s);
    const Eigen::Vector3d point = centre + r * point_offset_dir;
    if (!plate.contains(point, kOnSurfaceTolMm)) return;
    best = Contact{*s, surface, centre, point};
  };

  // Bore wall: the contact point lies radially outward of the ball centre.
  if (const auto s = ball_meets_bore(move, plate.hole_centre_mm, plate.hole_radius_mm)) {
    Eigen::Vector3d outward = Eigen::Vector3d::Zero();
    outward.head<2>() = move.centre_at(*s).head<2>() - plate.hole_centre_mm;
    if (outward.norm() > 0) outward.normalize();
    consider(s, "hole_edge", outward);
  }
  // Planes, each with its outward normal n; the contact point is c - r n.
  struct Plane {
    const char* surface;
    Eigen::Vector3d point;
    Eigen::Vector3d normal;
  };
  const Eigen::Vector2d& a = plate.hole_centre_mm;
  std::vector<Plane> planes = {
      {"face", {a.x(), a.y(), plate.face_z_mm}, Eigen::Vector3d::UnitZ()},
      {"underside", {a.x(), a.y(), plate.underside_z_mm()}, -Eigen::Vector3d::UnitZ()},
  };
  if (plate.width_mm > 0) {
    const double h = plate.half_width_mm();
    planes.push_back({"edge_+x", {a.x() + h, a.y(), plate.face_z_mm}, Eigen::Vector3d::UnitX()});
    planes.push_back({"edge_-x", {a.x() - h, a.y(), plate.face_z_mm}, -Eigen::Vector3d::UnitX()});
    planes.push_back({"edge_+y", {a.x(), a.y() + h, plate.face_z_mm}, Eigen::Vector3d::UnitY()});
    planes.push_back({"edge_-y", {a.x(), a.y() - h, plate.face_z_mm}, -Eigen::Vector3d::UnitY()});
  }
  for (const auto& plane : planes) {
    consider(ball_meets_plane(move, plane.point, plane.normal), plane.surface, -plane.normal);
  }
  return best;
}

bool SetPointBlock::contains(const Eigen::Vector3d& p, double tol) const {
  const Eigen::Vector3d& c = corner_mm;
  return p.x() >= c.x() - tol && p.x() <= c.x() + size_mm + tol && p.y() >= c.y() - tol &&
         p.y() <= c.y() + size_mm + tol && p.z() <= c.z() + tol && p.z() >= c.z() - size_mm - tol;
}

std::optional<Contact> first_contact(const SetPointBlock& block, const BallMove& move) {
  const Eigen::Vector3d& c = block.corner_mm;
  const double s = block.size_mm;
  struct Plane {
    const char* surface;
    Eigen::Vector3d point;
    Eigen::Vector3d normal;
  };
  const Plane planes[] = {
      {"top", c, Eigen::Vector3d::UnitZ()},
      {"bottom", c - s * Eigen::Vector3d::UnitZ(), -Eigen::Vector3d::UnitZ()},
      {"-x", c, -Eigen::Vector3d::UnitX()},
      {"+x", c + s * Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitX()},
      {"-y", c, -Eigen::Vector3d::UnitY()},
      {"+y", c + s * Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitY()},
  };
  std::optional<Contact> best;
  for (const auto& plane : planes) {
    const auto distance = ball_meets_plane(move, plane.point, plane.normal);
    if (!distance || *distance > move.travel_mm) continue;
    if (best && best->distance_mm <= *distance) continue;
    const Eigen::Vector3d centre = move.centre_at(*distance);
    const Eigen::Vector3d point = centre - move.ball_radius_mm * plane.normal;
    if (!block.contains(point, kOnSurfaceTolMm)) continue;
    best = Contact{*distance, plane.surface, centre, point};
  }
  return best;
}

}  // namespace ncqual::sim
