// SPDX-License-Identifier: Apache-2.0
#include "ncqual/sim/contact.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace ncqual::sim {
namespace {

double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

Eigen::Vector3d random_unit(std::mt19937_64& rng) {
  Eigen::Vector3d v;
  do {
    v = Eigen::Vector3d(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
  } while (v.norm() < 0.1 || v.norm() > 1);
  return v.normalized();
}

RingGaugePlate test_plate() {
  RingGaugePlate p;
  p.hole_centre_mm = Eigen::Vector2d(1200, 800);
  p.hole_radius_mm = 25;
  p.face_z_mm = 150;
  p.thickness_mm = 20;
  p.width_mm = 200;
  return p;
}

TEST(Contact, BallMeetsPlaneAtDistanceRadiusFromIt) {
  std::mt19937_64 rng(11);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector3d point(uniform(rng, -500, 500), uniform(rng, -500, 500),
                                uniform(rng, -500, 500));
    const Eigen::Vector3d normal = random_unit(rng);
    BallMove move;
    move.ball_radius_mm = uniform(rng, 0, 5);
    move.start = point + normal * (move.ball_radius_mm + uniform(rng, 0, 50)) +
                 normal.unitOrthogonal() * uniform(rng, -50, 50);
    move.direction = random_unit(rng);
    const auto s = ball_meets_plane(move, point, normal);
    if (move.direction.dot(normal) >= 0) {
      EXPECT_FALSE(s) << "moving away from the plane cannot meet it";
      continue;
    }
    ASSERT_TRUE(s);
    EXPECT_GE(*s, 0);
    EXPECT_NEAR((move.centre_at(*s) - point).dot(normal), move.ball_radius_mm, 1e-9);
  }
}

TEST(Contact, BallInsideBoreMeetsWallAtRadiusLessBall) {
  std::mt19937_64 rng(12);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector2d axis(uniform(rng, -2000, 2000), uniform(rng, -2000, 2000));
    const double bore = uniform(rng, 5, 60);
    BallMove move;
    move.ball_radius_mm = uniform(rng, 0, 0.9 * bore);
    const double rho = bore - move.ball_radius_mm;
    const double start_r = uniform(rng, 0, 0.99 * rho);
    const double start_angle = uniform(rng, 0, 6.3);
    move.start = Eigen::Vector3d(axis.x() + start_r * std::cos(start_angle),
                                 axis.y() + start_r * std::sin(start_angle), uniform(rng, -5, 5));
    move.direction = random_unit(rng);
    const auto s = ball_meets_bore(move, axis, bore);
    ASSERT_TRUE(s);
    const Eigen::Vector3d c = move.centre_at(*s);
    EXPECT_NEAR((c.head<2>() - axis).norm(), rho, 1e-9);
    // It is the first meeting: just before it the ball is still inside.
    EXPECT_LT((move.centre_at(*s * (1 - 1e-6)).head<2>() - axis).norm(), rho);
  }
}

TEST(Contact, BallOutsideBoreOrMovingVerticallyNeverMeetsIt) {
  BallMove move;
  move.ball_radius_mm = 3;
  move.start = Eigen::Vector3d(30, 0, 0);
  move.direction = Eigen::Vector3d(-1, 0, 0);
  EXPECT_FALSE(ball_meets_bore(move, Eigen::Vector2d::Zero(), 25));
  move.start = Eigen::Vector3d(1, 0, 0);
  move.direction = Eigen::Vector3d(0, 0, -1);
  EXPECT_FALSE(ball_meets_bore(move, Eigen::Vector2d::Zero(), 25));
  move.ball_radius_mm = 30;  // larger than the bore
  move.direction = Eigen::Vector3d(1, 0, 0);
  EXPECT_FALSE(ball_meets_bore(move, Eigen::Vector2d::Zero(), 25));
}

TEST(Contact, PlateEdgeTouchLandsOnTheWall) {
  const RingGaugePlate plate = test_plate();
  BallMove move;
  move.ball_radius_mm = 3;
  move.start = Eigen::Vector3d(1200, 800, 145);
  move.direction = Eigen::Vector3d(0, 1, 0);
  move.travel_mm = 30;
  const auto c = first_contact(plate, move);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->surface, "hole_edge");
  EXPECT_NEAR(c->distance_mm, 22, 1e-12);
  EXPECT_NEAR(c->point.y(), 825, 1e-12);
  // Travel too short: no contact.
  move.travel_mm = 21.9;
  EXPECT_FALSE(first_contact(plate, move));
}

TEST(Contact, PlateFaceAndEdgesAndUnderside) {
  const RingGaugePlate plate = test_plate();
  BallMove move;
  move.ball_radius_mm = 2;
  move.travel_mm = 50;
  // Down onto the face beside the hole.
  move.start = Eigen::Vector3d(1240, 800, 170);
  move.direction = Eigen::Vector3d(0, 0, -1);
  auto c = first_contact(plate, move);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->surface, "face");
  EXPECT_NEAR(c->ball_centre.z(), 152, 1e-12);
  // Down above the hole: falls through (rims not modelled, the bore is wide enough).
  move.start = Eigen::Vector3d(1200, 800, 170);
  EXPECT_FALSE(first_contact(plate, move));
  // From outside the plate along -X onto its +X edge.
  move.start = Eigen::Vector3d(1330, 800, 140);
  move.direction = Eigen::Vector3d(-1, 0, 0);
  c = first_contact(plate, move);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->surface, "edge_+x");
  EXPECT_NEAR(c->ball_centre.x(), 1302, 1e-12);
  // Below the plate along -X: passes under it.
  move.start = Eigen::Vector3d(1330, 800, 120);
  EXPECT_FALSE(first_contact(plate, move));
  // Up onto the underside.
  move.start = Eigen::Vector3d(1250, 850, 110);
  move.direction = Eigen::Vector3d(0, 0, 1);
  c = first_contact(plate, move);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->surface, "underside");
  EXPECT_NEAR(c->ball_centre.z(), 128, 1e-12);
}

TEST(Contact, FirstContactIsTheNearestOfSeveral) {
  // A diagonal move out of the hole near the face meets the wall; the plane of the underside
  // lies behind the ball and must not be chosen.
  const RingGaugePlate plate = test_plate();
  std::mt19937_64 rng(13);
  for (int i = 0; i < 500; ++i) {
    BallMove move;
    move.ball_radius_mm = uniform(rng, 0.5, 4);
    const double angle = uniform(rng, 0, 6.3);
    move.start = Eigen::Vector3d(1200, 800, uniform(rng, 131, 149));
    move.direction =
        Eigen::Vector3d(std::cos(angle), std::sin(angle), uniform(rng, -0.05, 0.05)).normalized();
    move.travel_mm = 40;
    const auto c = first_contact(plate, move);
    if (!c) {
      // Only allowed when the wall contact point would leave the plate's thickness.
      const double s = *ball_meets_bore(move, plate.hole_centre_mm, plate.hole_radius_mm);
      const double z = move.centre_at(s).z();
      EXPECT_TRUE(z > plate.face_z_mm || z < plate.underside_z_mm()) << "z = " << z;
      continue;
    }
    EXPECT_EQ(c->surface, "hole_edge");
    EXPECT_NEAR((c->point.head<2>() - plate.hole_centre_mm).norm(), plate.hole_radius_mm, 1e-9);
  }
}

TEST(Contact, OverlapDetectsBallInsideMaterial) {
  const RingGaugePlate plate = test_plate();
  EXPECT_FALSE(plate.overlaps_ball(Eigen::Vector3d(1200, 800, 145), 3));
  EXPECT_TRUE(plate.overlaps_ball(Eigen::Vector3d(1223, 800, 145), 3));  // cuts the wall
  EXPECT_TRUE(plate.overlaps_ball(Eigen::Vector3d(1250, 800, 152), 3));  // cuts the face
  EXPECT_FALSE(plate.overlaps_ball(Eigen::Vector3d(1250, 800, 153.5), 3));
  EXPECT_FALSE(plate.overlaps_ball(Eigen::Vector3d(1350, 800, 145), 3));  // beside the plate
}

}  // namespace
}  // namespace ncqual::sim
