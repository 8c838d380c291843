// SPDX-License-Identifier: Apache-2.0
// The rigid-body error model of the three linear axes: Legendre series, names, and the exact
// chain of actual_position checked error by error against hand-worked geometry.
#include "ncqual/common/volumetric.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace ncqual::volumetric {
namespace {

constexpr double kTight = 1e-12;

ErrorSeries series(double lo, double hi, std::vector<double> c) {
  ErrorSeries s;
  s.lo_mm = lo;
  s.hi_mm = hi;
  s.coefficients = std::move(c);
  return s;
}

// One function of an otherwise perfect machine, constant `value` over [0, 1000].
RigidBodyErrors only(int index, double value) {
  RigidBodyErrors e;
  e.functions[static_cast<std::size_t>(index)] = series(0, 1000, {value});
  return e;
}

// Angle (rad) between two vectors, computed with atan2 so that it is accurate near 90 deg.
double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

TEST(VolumetricModel, LegendreValuesAndDerivatives) {
  // P2(u) = (3u^2 - 1)/2, P3 = (5u^3 - 3u)/2, P4 = (35u^4 - 30u^2 + 3)/8 at u = 0.5.
  EXPECT_DOUBLE_EQ(legendre(0, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(legendre(1, 0.5), 0.5);
  EXPECT_NEAR(legendre(2, 0.5), -0.125, kTight);
  EXPECT_NEAR(legendre(3, 0.5), -0.4375, kTight);
  EXPECT_NEAR(legendre(4, 0.5), -0.2890625, kTight);
  for (int k = 0; k <= 8; ++k) {
    EXPECT_NEAR(legendre(k, 1.0), 1.0, kTight) << k;
    EXPECT_NEAR(legendre(k, -1.0), (k % 2 == 0) ? 1.0 : -1.0, kTight) << k;
    EXPECT_NEAR(legendre_derivative(k, 1.0), k * (k + 1) / 2.0, 1e-10) << k;  // P'_k(1)
  }
  // P3'(u) = (15u^2 - 3)/2, P4'(u) = (140u^3 - 60u)/8.
  EXPECT_NEAR(legendre_derivative(3, 0.5), 0.375, kTight);
  EXPECT_NEAR(legendre_derivative(4, -0.3), (140 * -0.027 + 18) / 8, kTight);
  // Orthogonality on [-1, 1]: int P2 P4 = 0, int P3^2 = 2/7 (Simpson, 2000 panels).
  const int n = 2000;
  double i24 = 0, i33 = 0;
  for (int i = 0; i <= n; ++i) {
    const double u = -1.0 + 2.0 * i / n;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    i24 += w * legendre(2, u) * legendre(4, u);
    i33 += w * legendre(3, u) * legendre(3, u);
  }
  i24 *= (2.0 / n) / 3.0;
  i33 *= (2.0 / n) / 3.0;
  EXPECT_NEAR(i24, 0.0, 1e-9);
  EXPECT_NEAR(i33, 2.0 / 7.0, 1e-9);
}

TEST(VolumetricModel, ErrorSeriesEvaluatesOverItsRange) {
  const ErrorSeries s = series(0, 1000, {1.0, 2.0, 3.0});
  // q = 750 -> u = 0.5: 1 + 2 * 0.5 + 3 * (-0.125).
  EXPECT_NEAR(s.value(750), 1.625, kTight);
  EXPECT_NEAR(s.value(0), 1 - 2 + 3, kTight);
  // df/dq = (2 + 3 * 3u) * 2 / 1000 at u = 0.5.
  EXPECT_NEAR(s.derivative(750), (2 + 4.5) * 0.002, kTight);
  EXPECT_DOUBLE_EQ(ErrorSeries{}.value(123.0), 0.0);  // no coefficients: zero, any range
  EXPECT_NEAR(normalized_coordinate(-200, -200, 600), -1.0, kTight);
  EXPECT_NEAR(normalized_coordinate(200, -200, 600), 0.0, kTight);
}

TEST(VolumetricModel, NamesFollowIso230) {
  EXPECT_EQ(function_name(0), "EXX");
  EXPECT_EQ(function_name(1), "EYX");
  EXPECT_EQ(function_name(5), "ECX");
  EXPECT_EQ(function_name(6), "EXY");
  EXPECT_EQ(function_name(11), "ECY");
  EXPECT_EQ(function_name(14), "EZZ");
  EXPECT_EQ(function_name(17), "ECZ");
  EXPECT_EQ(function_name(kSquarenessEC0XY), "EC(0X)Y");
  EXPECT_EQ(function_name(kSquarenessEB0XZ), "EB(0X)Z");
  EXPECT_EQ(function_name(kSquarenessEA0YZ), "EA(0Y)Z");
  EXPECT_EQ(function_index(kAxisY, kAboutZ), 11);
  EXPECT_TRUE(is_positioning(7));
  EXPECT_FALSE(is_positioning(8));
  EXPECT_TRUE(is_straightness(8));
  EXPECT_FALSE(is_straightness(7));
  EXPECT_TRUE(is_angular(15));
  EXPECT_FALSE(is_angular(14));
}

TEST(VolumetricModel, ZeroErrorsGiveCommandedPlusOffset) {
  const Eigen::Vector3d c(1200, -300, 450), t(15, -20, -350);
  EXPECT_TRUE(actual_position(RigidBodyErrors{}, c, t).isApprox(c + t, kTight));
  EXPECT_TRUE(rotation_from_vector(Eigen::Vector3d::Zero()).isIdentity());
}

TEST(VolumetricModel, TranslationalErrorsAddAlongTheirDirection) {
  const Eigen::Vector3d c(1000, 250, 500), t(10, 20, -300);
  // Positioning of X with a scale term: EXX = 0.01 P1(u), u(1000) = 1 over [0, 1000].
  RigidBodyErrors e;
  e.functions[0] = series(0, 1000, {0.0, 0.01});
  EXPECT_TRUE(actual_position(e, c, t).isApprox(c + t + Eigen::Vector3d(0.01, 0, 0), kTight));
  // Each translational function alone adds its value along its own direction.
  for (int axis = 0; axis < 3; ++axis) {
    for (int dir = 0; dir < 3; ++dir) {
      const int i = function_index(axis, dir);
      Eigen::Vector3d expected = c + t;
      expected[dir] += 0.004;
      EXPECT_TRUE(actual_position(only(i, 0.004), c, t).isApprox(expected, kTight))
          << function_name(i);
    }
  }
}

TEST(VolumetricModel, AngularErrorsTurnEverythingDownstreamOfTheirAxis) {
  const double a = 2e-3;  // large enough to see the exact (not first-order) rotation
  const double ca = std::cos(a), sa = std::sin(a);
  // EAX: turns the Y/Z carriages and the tool about X, not the X motion itself.
  {
    const Eigen::Vector3d c(700, 0, 500), t(0, 0, 0);
    const Eigen::Vector3d p = actual_position(only(3, a), c, t);
    EXPECT_NEAR(p.x(), 700, kTight);
    EXPECT_NEAR(p.y(), -500 * sa, kTight);
    EXPECT_NEAR(p.z(), 500 * ca, 1e-10);
  }
  // EAX also turns the straightness of Y (Y carriage sits on X): o_Y = (0, y, s).
  {
    RigidBodyErrors e = only(3, a);
    e.functions[8] = series(0, 1000, {0.05});  // EZY = 0.05 mm
    const Eigen::Vector3d p =
        actual_position(e, Eigen::Vector3d(0, 400, 0), Eigen::Vector3d::Zero());
    EXPECT_NEAR(p.y(), 400 * ca - 0.05 * sa, 1e-10);
    EXPECT_NEAR(p.z(), 400 * sa + 0.05 * ca, 1e-10);
  }
  // EBY: the Z lever arm and tool about Y: R_y(b) (0, 0, z) = (z sin b, 0, z cos b).
  {
    const Eigen::Vector3d p =
        actual_position(only(10, a), Eigen::Vector3d(100, 200, 300), Eigen::Vector3d(0, 0, -50));
    EXPECT_NEAR(p.x(), 100 + 250 * sa, 1e-10);
    EXPECT_NEAR(p.y(), 200, kTight);
    EXPECT_NEAR(p.z(), 250 * ca, 1e-10);
  }
  // ECY acts only through the tool offset: nothing with t along Z, a turn of t = (100, 0, 0).
  {
    const Eigen::Vector3d c(100, 200, 300);
    EXPECT_TRUE(actual_position(only(11, a), c, Eigen::Vector3d(0, 0, -400))
                    .isApprox(c + Eigen::Vector3d(0, 0, -400), kTight));
    const Eigen::Vector3d p = actual_position(only(11, a), c, Eigen::Vector3d(100, 0, 0));
    EXPECT_NEAR(p.x(), 100 + 100 * ca, 1e-10);
    EXPECT_NEAR(p.y(), 200 + 100 * sa, 1e-10);
  }
  // ECZ: turns only the tool offset about Z.
  {
    const Eigen::Vector3d c(100, 200, 300);
    const Eigen::Vector3d p = actual_position(only(17, a), c, Eigen::Vector3d(0, 100, 0));
    EXPECT_NEAR(p.x(), 100 - 100 * sa, 1e-10);
    EXPECT_NEAR(p.y(), 200 + 100 * ca, 1e-10);
    EXPECT_NEAR(p.z(), 300, kTight);
  }
  // The exact rotation: a rotation vector of 90 deg about Z maps X onto Y.
  const Eigen::Matrix3d r = rotation_from_vector(Eigen::Vector3d(0, 0, M_PI / 2));
  EXPECT_TRUE((r * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY(), kTight));
}

TEST(VolumetricModel, SquarenessSignsFollowTheRotationOfTheSecondAxisLine) {
  const double g = 50e-6;
  const Eigen::Vector3d t(0, 0, -300);
  // Motions of the tool point for 1000 mm of X, of Y and of Z alone, from the origin.
  struct Motions {
    Eigen::Vector3d x, y, z;
  };
  const auto motions = [&](const RigidBodyErrors& e) {
    const Eigen::Vector3d p0 = actual_position(e, Eigen::Vector3d::Zero(), t);
    Motions m;
    m.x = actual_position(e, Eigen::Vector3d(1000, 0, 0), t) - p0;
    m.y = actual_position(e, Eigen::Vector3d(0, 1000, 0), t) - p0;
    m.z = actual_position(e, Eigen::Vector3d(0, 0, 1000), t) - p0;
    return m;
  };
  RigidBodyErrors e;
  e.ec0xy_rad = g;
  Motions m = motions(e);
  // Y rotated +g about Z: the Y motion goes along (-sin g, cos g, 0); angle(X, Y) = 90 deg + g.
  EXPECT_NEAR(angle_between(m.x, m.y), M_PI / 2 + g, 1e-12);
  EXPECT_NEAR(m.y.x(), -1000 * g, kTight);
  e = RigidBodyErrors{};
  e.eb0xz_rad = g;
  m = motions(e);
  // Z rotated +g about Y: (sin g, 0, cos g); angle(X, Z) = 90 deg - g.
  EXPECT_NEAR(angle_between(m.x, m.z), M_PI / 2 - g, 1e-12);
  EXPECT_NEAR(m.z.x(), 1000 * g, kTight);
  e = RigidBodyErrors{};
  e.ea0yz_rad = g;
  m = motions(e);
  // Z rotated +g about X: (0, -sin g, cos g); angle(Y, Z) = 90 deg + g.
  EXPECT_NEAR(angle_between(m.y, m.z), M_PI / 2 + g, 1e-12);
  EXPECT_NEAR(m.z.y(), -1000 * g, kTight);
}

TEST(VolumetricModel, Refusals) {
  EXPECT_THROW(function_name(21), std::invalid_argument);
  EXPECT_THROW(function_name(-1), std::invalid_argument);
  EXPECT_THROW(function_index(3, 0), std::invalid_argument);
  EXPECT_THROW(function_index(0, 6), std::invalid_argument);
  EXPECT_THROW(legendre(-1, 0.0), std::invalid_argument);
  try {
    series(500, 500, {1.0}).value(0);
    FAIL() << "an empty range was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("lo_mm = 500"), std::string::npos) << e.what();
  }
  RigidBodyErrors e;
  e.functions[4] = series(0, 0, {1e-5});
  EXPECT_THROW(actual_position(e, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()),
               std::invalid_argument);
}

}  // namespace
}  // namespace ncqual::volumetric
