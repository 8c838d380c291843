// SPDX-License-Identifier: Apache-2.0
// A small historian for the report's tests (unit and CLI): the machine of
// deploy/machines/pm1.yaml under a chosen id, with
//  - a monthly grid, an XY circle and an ISO 230-2 run measured by a "tracker" whose frame is the
//    machine's and whose readings are the nominal target positions (stylus_ball_centre of the
//    programs' commanded axes) plus deviations worked here by hand, judged by the solver;
//  - twelve daily monument checks of center_dx_mm (the last one FAIL, with causes and a
//    correction), a status, a trend warning and an intervention.
// Times are days after kT0 (2026-03-02 00:00 UTC).
#pragma once

#include "ncqual/common/config.hpp"
#include "ncqual/common/global_check.hpp"
#include "ncqual/common/kinematics.hpp"
#include "ncqual/solver/solve.hpp"
#include "ncqual/storage/database.hpp"
#include "ncqual/storage/trend.hpp"

#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace ncqual::report::testing {

inline constexpr std::int64_t kDay = 86'400'000'000'000;
inline constexpr std::int64_t kT0 = 1'772'409'600'000'000'000;  // 2026-03-02T00:00Z

// The hand-worked deviations (mm, machine frame = master frame).
inline const Eigen::Vector3d kGrid7Deviation{0.012, -0.005, 0.003};  // |dxy| = 0.013 mm
inline const Eigen::Vector3d kGrid20Deviation{0.160, 0, 0};          // beyond the 0.15 mm limit
inline constexpr double kBacklashHalfMm = 0.002;    // the run reads +2 µm going up, -2 µm down
inline constexpr double kCircleOvalMm = 0.004;      // radial 4 µm cos 2θ, both directions
inline constexpr double kCircleCwOffsetMm = 0.002;  // and the clockwise path 2 µm out

inline MachineConfig report_machine(const std::string& machine_id) {
  MachineConfig m = load_machine_config(NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml");
  m.machine_id = machine_id;
  return m;
}

// A tracker set of `kind` whose reading of each labelled move is its nominal target plus
// `deviation(label, move)`.
template <typename Deviation>
MeasurementSet tracker_set(const MachineConfig& m, CheckKind kind, const std::string& id,
                           std::int64_t time_ns, Deviation deviation) {
  MeasurementSet set;
  set.machine_id = m.machine_id;
  set.request_id = id;
  set.kind = kind;
  set.instrument = "laser_tracker";
  set.frame = "tracker";
  set.time_ns = time_ns;
  const GlobalCheckConfig& gc = *m.global_check;
  for (const TrackerMove& move : global_check_program(kind, gc)) {
    if (move.label.empty()) continue;
    TrackerPoint p;
    p.label = move.label;
    p.commanded = move.commanded;
    p.measured_mm = stylus_ball_centre(move.commanded, gc.targets.at(move.target)) +
                    deviation(move.label, move);
    set.tracker_points.push_back(p);
  }
  return set;
}

inline void store_checked(storage::Database& db, const MachineConfig& m, MeasurementSet set,
                          DataOrigin origin = DataOrigin::Unknown) {
  set.origin = origin;
  CheckRequest request;
  request.machine_id = m.machine_id;
  request.request_id = set.request_id;
  request.kind = set.kind;
  request.requested_by = "scheduler";
  request.time_ns = set.time_ns - 3'600'000'000'000;
  db.store(request);
  db.store(set);
  db.store(solver::solve(set, m, set.time_ns + 60'000'000'000));
}

inline CheckResult monument_result(const std::string& machine_id, int day, double dx_mm) {
  CheckResult r;
  r.machine_id = machine_id;
  r.request_id = "daily-" + std::to_string(day);
  r.kind = CheckKind::MonumentPositioning;
  Metric metric{"center_dx_mm", dx_mm, "mm", -0.025, 0.025, std::abs(dx_mm) <= 0.025};
  r.metrics.push_back(metric);
  r.verdict = metric.pass ? Verdict::Pass : Verdict::Fail;
  r.time_ns = kT0 + day * kDay + 6 * 3'600'000'000'000;
  r.produced_by = "test";
  if (!metric.pass) {
    r.reason = "center_dx_mm = 0.0300 mm outside [-0.025, 0.025]";
    r.likely_causes = {"monument moved (loose clamping)", "probe stylus bent"};
    r.correction = Correction{"machine:work_offset", {{"dx", -0.030, "mm"}}};
  }
  return r;
}

// The historian described above, at `path` (created).
// `origin`: what every stored set and result says it is (Unknown: as stored before schema 11).
inline void build_report_historian(const std::string& path, const MachineConfig& m,
                                   DataOrigin origin = DataOrigin::Unknown) {
  storage::Database db = storage::Database::open(path);
  // Twelve daily checks drifting up to a failure on day 12.
  for (int day = 1; day <= 12; ++day) {
    const double dx = day == 12 ? 0.030 : 0.001 * day - 0.004 + (day % 2 ? 0.0005 : -0.0005);
    CheckResult daily = monument_result(m.machine_id, day, dx);
    daily.origin = origin;
    db.store(daily);
  }
  // The monthly checks on day 13.
  const std::int64_t monthly = kT0 + 13 * kDay;
  store_checked(db, m,
                tracker_set(m, CheckKind::GlobalGrid, "monthly-grid", monthly,
                            [](const std::string& label, const TrackerMove&) {
                              if (label == "grid:7:t0") return kGrid7Deviation;
                              if (label == "grid:20:t0") return kGrid20Deviation;
                              return Eigen::Vector3d::Zero().eval();
                            }),
                origin);
  // The circle: an oval along X (4 µm cos 2θ) and the clockwise path 2 µm further out.
  const Eigen::Vector3d centre = m.global_check->circle.centre_mm;
  store_checked(db, m,
                tracker_set(m, CheckKind::CircleXY, "monthly-circle-xy", monthly + kDay / 24,
                            [&](const std::string& label, const TrackerMove& move) {
                              const Eigen::Vector3d radial =
                                  Eigen::Vector3d(move.commanded.x_mm - centre.x(),
                                                  move.commanded.y_mm - centre.y(), 0)
                                      .normalized();
                              const double theta = std::atan2(radial.y(), radial.x());
                              const bool cw = label.rfind("cw:", 0) == 0;
                              return (radial * (kCircleOvalMm * std::cos(2 * theta) +
                                                (cw ? kCircleCwOffsetMm : 0)))
                                  .eval();
                            }),
                origin);
  store_checked(db, m,
                tracker_set(m, CheckKind::LinearAxisRun, "monthly-linear", monthly + kDay / 12,
                            [](const std::string& label, const TrackerMove&) {
                              const bool up = label.find(":up:") != std::string::npos;
                              return Eigen::Vector3d(up ? kBacklashHalfMm : -kBacklashHalfMm, 0, 0);
                            }),
                origin);
  MachineStatus status;
  status.machine_id = m.machine_id;
  status.request_id = "daily-12";
  status.state = MachineState::NeedsIntervention;
  status.last_kind = CheckKind::MonumentPositioning;
  status.last_verdict = Verdict::Fail;
  status.detail = "daily 3 failed: center_dx_mm out of tolerance";
  status.time_ns = kT0 + 14 * kDay;
  db.store(status);
  Intervention i;
  i.machine_id = m.machine_id;
  i.intervention_id = "fix-1";
  i.kind = CheckKind::MonumentPositioning;
  i.note = "monument re-clamped";
  i.operator_name = "tester";
  i.time_ns = kT0 + 6 * kDay;
  db.store(i);
  storage::TrendWarningRecord w;
  w.machine_id = m.machine_id;
  w.metric = "center_dx_mm";
  w.check_kind = CheckKind::MonumentPositioning;
  w.kind = "forecast";
  w.side = "above";
  w.started_ns = kT0 + 10 * kDay;
  w.text = "center_dx_mm heads for its upper limit";
  storage::apply_trend_warnings(db, m.machine_id, "center_dx_mm", {w}, "daily-10", kT0 + 10 * kDay);
}

}  // namespace ncqual::report::testing
