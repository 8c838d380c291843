// SPDX-License-Identifier: Apache-2.0
#include "validate.hpp"

#include "ncqual/storage/database.hpp"

#include <cmath>
#include <sstream>
#include <string>
#include <string_view>

namespace ncqual::storage::validate {
namespace {

std::string quoted(std::string_view text) { return "'" + std::string(text) + "'"; }

// NaN and the infinities by name; finite values with enough digits to find them again.
std::string describe(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
}

// Every message reads "<field> is <what>", then the sample it belongs to in `owner` when the
// field is nested, e.g. " (CheckResult 'r-17')".
void non_empty(const std::string& value, const std::string& field, const std::string& owner = {}) {
  if (value.empty()) throw StorageError(field + " is empty" + owner);
}

// SQLite stores NaN as NULL, so a NaN would come back as something else (or break NOT NULL):
// refused everywhere but in a metric's value (kept as NULL, read back as NaN: a result is never
// refused for a figure it could not evaluate). Infinity is refused where it can only be a fault
// (a measured value).
void finite(double value, const std::string& field, const std::string& owner) {
  if (!std::isfinite(value)) throw StorageError(field + " is " + describe(value) + owner);
}

void not_nan(double value, const std::string& field, const std::string& owner) {
  if (std::isnan(value)) throw StorageError(field + " is NaN" + owner);
}

void kind(CheckKind value, const std::string& field) {
  if (!is_check_kind(value)) {
    throw StorageError(field + " is " + std::to_string(static_cast<int>(value)) +
                       ", not a check kind");
  }
}

void verdict(Verdict value, const std::string& field) {
  const int number = static_cast<int>(value);
  if (number < 0 || number > static_cast<int>(Verdict::Invalid)) {
    throw StorageError(field + " is " + std::to_string(number) + ", not a verdict");
  }
}

void state(MachineState value, const std::string& field) {
  const int number = static_cast<int>(value);
  if (number < 0 || number > static_cast<int>(MachineState::Offline)) {
    throw StorageError(field + " is " + std::to_string(number) + ", not a machine state");
  }
}

// `field` is e.g. "Touch.axes", `which` " of touch 3 'hole_edge'".
void axes(const AxisPosition& axes, const std::string& field, const std::string& which,
          const std::string& owner) {
  finite(axes.x_mm, field + ".x_mm" + which, owner);
  finite(axes.y_mm, field + ".y_mm" + which, owner);
  finite(axes.z_mm, field + ".z_mm" + which, owner);
  finite(axes.w_mm, field + ".w_mm" + which, owner);
  finite(axes.a_rad, field + ".a_rad" + which, owner);
  finite(axes.c_rad, field + ".c_rad" + which, owner);
}

void vector3(const Eigen::Vector3d& v, const std::string& field, const std::string& which,
             const std::string& owner) {
  finite(v.x(), field + ".x" + which, owner);
  finite(v.y(), field + ".y" + which, owner);
  finite(v.z(), field + ".z" + which, owner);
}

void correction(const Correction& correction, const std::string& field, const std::string& owner) {
  non_empty(correction.target, field + ".target", owner);
  for (std::size_t i = 0; i < correction.offsets.size(); ++i) {
    const NamedValue& offset = correction.offsets[i];
    non_empty(offset.name, "NamedValue.name of offset " + std::to_string(i), owner);
    finite(offset.value, "NamedValue.value of " + quoted(offset.name), owner);
  }
}

void parameters(const std::vector<NamedValue>& values, const std::string& field,
                const std::string& owner) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    non_empty(values[i].name, field + "[" + std::to_string(i) + "].name", owner);
    finite(values[i].value,
           field + "[" + std::to_string(i) + "].value (" + quoted(values[i].name) + ")", owner);
  }
}

}  // namespace

bool is_check_kind(CheckKind value) {
  const int number = static_cast<int>(value);
  return number >= 0 && number < kCheckKindCount;
}

void check(const CheckRequest& request) {
  non_empty(request.request_id, "CheckRequest.request_id");
  non_empty(request.machine_id, "CheckRequest.machine_id");
  kind(request.kind, "CheckRequest.kind");
  parameters(request.parameters, "CheckRequest.parameters",
             " (CheckRequest " + quoted(request.request_id) + ")");
}

void check(const MeasurementSet& set) {
  non_empty(set.request_id, "MeasurementSet.request_id");
  non_empty(set.machine_id, "MeasurementSet.machine_id");
  kind(set.kind, "MeasurementSet.kind");
  const std::string owner = " (MeasurementSet " + quoted(set.request_id) + ")";
  parameters(set.parameters, "MeasurementSet.parameters", owner);
  for (std::size_t i = 0; i < set.touches.size(); ++i) {
    const Touch& touch = set.touches[i];
    const std::string which = " of touch " + std::to_string(i) + " " + quoted(touch.feature);
    axes(touch.axes, "Touch.axes", which, owner);
    vector3(touch.approach, "Touch.approach", which, owner);
  }
  for (std::size_t i = 0; i < set.tracker_points.size(); ++i) {
    const TrackerPoint& point = set.tracker_points[i];
    const std::string which = " of tracker point " + std::to_string(i) + " " + quoted(point.label);
    axes(point.commanded, "TrackerPoint.commanded", which, owner);
    vector3(point.measured_mm, "TrackerPoint.measured_mm", which, owner);
  }
}

void check(const CheckResult& result) {
  non_empty(result.request_id, "CheckResult.request_id");
  non_empty(result.machine_id, "CheckResult.machine_id");
  kind(result.kind, "CheckResult.kind");
  verdict(result.verdict, "CheckResult.verdict");
  const std::string owner = " (CheckResult " + quoted(result.request_id) + ")";
  for (std::size_t i = 0; i < result.metrics.size(); ++i) {
    const Metric& metric = result.metrics[i];
    non_empty(metric.name, "Metric.name of metric " + std::to_string(i), owner);
    const std::string which = " of " + quoted(metric.name);
    // A value that could not be evaluated (NaN, infinite) is stored as NULL: the result is kept
    // (its verdict and reason say what happened), never refused.
    // An infinite bound is a one-sided tolerance band (e.g. flatness <= 0.01 mm).
    not_nan(metric.lower, "Metric.lower" + which, owner);
    not_nan(metric.upper, "Metric.upper" + which, owner);
  }
  for (std::size_t i = 0; i < result.likely_causes.size(); ++i) {
    non_empty(result.likely_causes[i], "CheckResult.likely_causes[" + std::to_string(i) + "]",
              owner);
  }
  if (result.correction) correction(*result.correction, "CheckResult.correction", owner);
}

void check(const MachineStatus& status) {
  non_empty(status.machine_id, "MachineStatus.machine_id");
  state(status.state, "MachineStatus.state");
  if (status.last_kind) kind(*status.last_kind, "MachineStatus.last_kind");
  if (status.last_verdict) verdict(*status.last_verdict, "MachineStatus.last_verdict");
}

void check(const Intervention& intervention) {
  non_empty(intervention.intervention_id, "Intervention.intervention_id");
  non_empty(intervention.machine_id, "Intervention.machine_id");
  kind(intervention.kind, "Intervention.kind");
}

void check(const Compensation& compensation) {
  non_empty(compensation.request_id, "Compensation.request_id");
  non_empty(compensation.machine_id, "Compensation.machine_id");
  correction(compensation.correction, "Compensation.correction",
             " (Compensation " + quoted(compensation.request_id) + ")");
}

void check(const Heartbeat& heartbeat) {
  non_empty(heartbeat.service, "Heartbeat.service");
  non_empty(heartbeat.instance, "Heartbeat.instance");
}

}  // namespace ncqual::storage::validate
