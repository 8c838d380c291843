// SPDX-License-Identifier: Apache-2.0
#include "ncqual/common/global_check.hpp"

#include "ncqual/common/units.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace ncqual {
namespace {

AxisPosition pivot(const Eigen::Vector3d& p) {
  AxisPosition a;
  a.x_mm = p.x();
  a.y_mm = p.y();
  a.z_mm = p.z();
  return a;
}

std::string indexed(const char* stem, std::size_t i) { return stem + std::to_string(i); }

void append_master_frame_runs(const GlobalCheckConfig& c, std::vector<TrackerMove>& moves) {
  for (std::size_t i = 0; i < c.x_run_mm.size(); ++i) {
    moves.push_back(
        {indexed("x_run:", i), pivot({c.x_run_mm[i], c.x_run_at_mm.x(), c.x_run_at_mm.y()}), 0});
  }
  for (std::size_t i = 0; i < c.y_run_mm.size(); ++i) {
    moves.push_back(
        {indexed("y_run:", i), pivot({c.y_run_at_mm.x(), c.y_run_mm[i], c.y_run_at_mm.y()}), 0});
  }
}

// A rotary check at the configured pivot position: the axis `stepped` takes each of `steps` in
// turn (move `<stem><i>`) while the axis `held`, if any, stays at `held_at`.
using Axis = double AxisPosition::*;
void append_rotary_check(const GlobalCheckConfig& c, const char* stem, Axis stepped,
                         const std::vector<double>& steps, std::vector<TrackerMove>& moves,
                         Axis held = nullptr, double held_at = 0) {
  for (std::size_t i = 0; i < steps.size(); ++i) {
    AxisPosition a = pivot(c.rotary_at_mm);
    if (held) a.*held = held_at;
    a.*stepped = steps[i];
    moves.push_back({indexed(stem, i), a, 0});
  }
}

// Circle in the plane of axes (u, v) about the configured centre: ccw from angle 0, then cw back.
void append_circle(const CircleTestConfig& c, int u, int v, std::vector<TrackerMove>& moves) {
  auto at = [&](double angle) {
    Eigen::Vector3d p = c.centre_mm;
    p[u] += c.radius_mm * std::cos(angle);
    p[v] += c.radius_mm * std::sin(angle);
    return pivot(p);
  };
  const double step = 2 * units::kPi / c.points;
  // Approach angle 0 from below (as the ccw path continues) so the first point arrives like
  // the others.
  moves.push_back({"", at(-step), 0});
  for (int i = 0; i < c.points; ++i) moves.push_back({indexed("ccw:", i), at(i * step), 0});
  if (!c.bidirectional) return;
  moves.push_back({"", at(c.points * step), 0});  // past the last ccw point, to angle 0 again
  for (int i = c.points - 1; i >= 0; --i) moves.push_back({indexed("cw:", i), at(i * step), 0});
}

}  // namespace

std::vector<TrackerMove> global_check_program(CheckKind kind, const GlobalCheckConfig& c) {
  if (!is_tracker_check(kind)) {
    throw std::invalid_argument("check kind '" + std::string(to_string(kind)) +
                                "' is not a laser-tracker check");
  }
  std::vector<TrackerMove> moves;
  // The linear run is measured from its own station on the axis line (interferometer mode): the
  // master-frame runs of the session would be in another frame, so it has none.
  if (kind != CheckKind::LinearAxisRun) append_master_frame_runs(c, moves);
  switch (kind) {
    case CheckKind::GlobalMasterFrame: break;
    case CheckKind::GlobalGrid: {
      const std::size_t nx = c.grid_x_mm.size(), ny = c.grid_y_mm.size();
      for (std::size_t k = 0; k < c.targets.size(); ++k) {
        for (std::size_t iz = 0; iz < c.grid_z_mm.size(); ++iz) {
          for (std::size_t iy = 0; iy < ny; ++iy) {
            for (std::size_t ix = 0; ix < nx; ++ix) {
              const std::size_t i = (iz * ny + iy) * nx + ix;
              moves.push_back({"grid:" + std::to_string(i) + ":t" + std::to_string(k),
                               pivot({c.grid_x_mm[ix], c.grid_y_mm[iy], c.grid_z_mm[iz]}),
                               static_cast<int>(k)});
            }
          }
        }
      }
      break;
    }
    case CheckKind::RotaryC:  // C steps with A tilted
      append_rotary_check(c, "c:", &AxisPosition::c_rad, c.c_check_c_rad, moves,
                          &AxisPosition::a_rad, c.c_check_a_rad);
      break;
    case CheckKind::RotaryA:  // A steps with C held
      append_rotary_check(c, "a:", &AxisPosition::a_rad, c.a_check_a_rad, moves,
                          &AxisPosition::c_rad, c.a_check_c_rad);
      break;
    case CheckKind::RotaryW:  // W steps at A = C = 0
      append_rotary_check(c, "w:", &AxisPosition::w_mm, c.w_check_w_mm, moves);
      break;
    case CheckKind::CircleXY: append_circle(c.circle, 0, 1, moves); break;
    case CheckKind::CircleYZ: append_circle(c.circle, 1, 2, moves); break;
    case CheckKind::CircleXZ: append_circle(c.circle, 0, 2, moves); break;
    case CheckKind::LinearAxisRun: {
      const LinearRunConfig& r = c.linear_run;
      auto at = [&](double q) {
        Eigen::Vector3d p = r.at_mm;
        p[r.axis] = q;
        return pivot(p);
      };
      const std::size_t n = r.targets_mm.size();
      for (int cycle = 1; cycle <= r.cycles; ++cycle) {
        // ISO 230-2 standard test cycle: approach every target upwards, overrun, then every
        // target downwards, overrun below the first.
        moves.push_back({"", at(r.targets_mm.front() - r.overrun_mm), 0});
        for (std::size_t i = 0; i < n; ++i) {
          moves.push_back({"run:" + std::to_string(cycle) + ":up:" + std::to_string(i),
                           at(r.targets_mm[i]), 0});
        }
        moves.push_back({"", at(r.targets_mm.back() + r.overrun_mm), 0});
        for (std::size_t i = n; i-- > 0;) {
          moves.push_back({"run:" + std::to_string(cycle) + ":down:" + std::to_string(i),
                           at(r.targets_mm[i]), 0});
        }
      }
      break;
    }
    default: break;
  }
  return moves;
}

}  // namespace ncqual
