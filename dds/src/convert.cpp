// SPDX-License-Identifier: Apache-2.0
#include "ncqual/dds/convert.hpp"

#include <algorithm>
#include <climits>

namespace ncqual::dds {
namespace {

// The IDL enums and the model enums share their numbering (see idl/ncqual.idl).
msg::CheckKind wire_kind(CheckKind k) { return static_cast<msg::CheckKind>(static_cast<int>(k)); }
msg::Verdict wire_verdict(Verdict v) { return static_cast<msg::Verdict>(static_cast<int>(v)); }

void note(std::string& error, const std::string& what) {
  if (error.empty()) error = what;
}

// A wire enum as the model's, whose values run from 0 to `last` with the same numbers: an
// unknown one is noted ("<field> = 7 is not a known <what>") and becomes `fallback`.
template <typename Model, typename Wire>
Model model_enum(Wire w, Model last, Model fallback, const std::string& field, const char* what,
                 std::string& error) {
  const auto raw = static_cast<std::uint32_t>(w);
  if (raw > static_cast<std::uint32_t>(last)) {
    note(error, field + " = " + std::to_string(raw) + " is not a known " + what);
    return fallback;
  }
  return static_cast<Model>(raw);
}

CheckKind model_kind(msg::CheckKind k, const char* field, std::string& error) {
  return model_enum(k, static_cast<CheckKind>(kCheckKindCount - 1), CheckKind::MonumentPositioning,
                    field, "check kind", error);
}

Verdict model_verdict(msg::Verdict v, const char* field, std::string& error) {
  return model_enum(v, Verdict::Invalid, Verdict::Invalid, field, "verdict", error);
}

msg::AxisPosition wire_axes(const AxisPosition& a) {
  msg::AxisPosition w;
  w.x_mm(a.x_mm);
  w.y_mm(a.y_mm);
  w.z_mm(a.z_mm);
  w.w_mm(a.w_mm);
  w.a_rad(a.a_rad);
  w.c_rad(a.c_rad);
  return w;
}
AxisPosition model_axes(const msg::AxisPosition& w) {
  return AxisPosition{w.x_mm(), w.y_mm(), w.z_mm(), w.w_mm(), w.a_rad(), w.c_rad()};
}
msg::Vector3 wire_vec(const Eigen::Vector3d& v) {
  msg::Vector3 w;
  w.x(v.x());
  w.y(v.y());
  w.z(v.z());
  return w;
}
Eigen::Vector3d model_vec(const msg::Vector3& w) { return {w.x(), w.y(), w.z()}; }

std::vector<msg::NamedValue> wire_values(const std::vector<NamedValue>& values) {
  std::vector<msg::NamedValue> w;
  w.reserve(values.size());
  for (const auto& o : values) {
    msg::NamedValue nv;
    nv.name(o.name);
    nv.value(o.value);
    nv.unit(o.unit);
    w.push_back(nv);
  }
  return w;
}
std::vector<NamedValue> model_values(const std::vector<msg::NamedValue>& w) {
  std::vector<NamedValue> values;
  values.reserve(w.size());
  for (const auto& o : w) values.push_back({o.name(), o.value(), o.unit()});
  return values;
}

msg::SoftwareCorrection wire_correction(const Correction& c) {
  msg::SoftwareCorrection w;
  w.target(c.target);
  w.offsets(wire_values(c.offsets));
  return w;
}
Correction model_correction(const msg::SoftwareCorrection& w) {
  Correction c;
  c.target = w.target();
  c.offsets = model_values(w.offsets());
  return c;
}

}  // namespace

msg::CheckRequest to_wire(const CheckRequest& v) {
  msg::CheckRequest w;
  w.machine_id(v.machine_id);
  w.request_id(v.request_id);
  w.kind(wire_kind(v.kind));
  w.requested_by(v.requested_by);
  w.time_ns(v.time_ns);
  w.attempt(v.attempt);
  w.parameters(wire_values(v.parameters));
  w.verifies_correction_of(v.verifies_correction_of);
  return w;
}
CheckRequest from_wire(const msg::CheckRequest& w, std::string& error) {
  CheckRequest v;
  v.machine_id = w.machine_id();
  v.request_id = w.request_id();
  v.kind = model_kind(w.kind(), "CheckRequest.kind", error);
  v.requested_by = w.requested_by();
  v.time_ns = w.time_ns();
  v.attempt = w.attempt();
  v.parameters = model_values(w.parameters());
  v.verifies_correction_of = w.verifies_correction_of();
  return v;
}

msg::CheckCommand to_wire(const CheckCommand& v) {
  msg::CheckCommand w;
  w.machine_id(v.machine_id);
  w.request_id(v.request_id);
  w.kind(wire_kind(v.kind));
  w.requested_by(v.requested_by);
  w.time_ns(v.time_ns);
  w.parameters(wire_values(v.parameters));
  return w;
}
CheckCommand from_wire(const msg::CheckCommand& w, std::string& error) {
  CheckCommand v;
  v.machine_id = w.machine_id();
  v.request_id = w.request_id();
  v.kind = model_kind(w.kind(), "CheckCommand.kind", error);
  v.requested_by = w.requested_by();
  v.time_ns = w.time_ns();
  v.parameters = model_values(w.parameters());
  return v;
}

msg::MeasurementSet to_wire(const MeasurementSet& v) {
  msg::MeasurementSet w;
  w.machine_id(v.machine_id);
  w.request_id(v.request_id);
  w.kind(wire_kind(v.kind));
  w.instrument(v.instrument);
  w.frame(v.frame);
  w.time_ns(v.time_ns);
  w.error(v.error);
  w.parameters(wire_values(v.parameters));
  w.touches().reserve(v.touches.size());
  for (const auto& t : v.touches) {
    msg::Touch wt;
    wt.feature(t.feature);
    wt.axes(wire_axes(t.axes));
    wt.approach(wire_vec(t.approach));
    w.touches().push_back(wt);
  }
  w.tracker_points().reserve(v.tracker_points.size());
  for (const auto& p : v.tracker_points) {
    msg::TrackerPoint wp;
    wp.label(p.label);
    wp.commanded(wire_axes(p.commanded));
    wp.measured_mm(wire_vec(p.measured_mm));
    w.tracker_points().push_back(wp);
  }
  return w;
}
MeasurementSet from_wire(const msg::MeasurementSet& w, std::string& error) {
  MeasurementSet v;
  v.machine_id = w.machine_id();
  v.request_id = w.request_id();
  v.kind = model_kind(w.kind(), "MeasurementSet.kind", error);
  v.instrument = w.instrument();
  v.frame = w.frame();
  v.time_ns = w.time_ns();
  v.error = w.error();
  v.parameters = model_values(w.parameters());
  v.touches.reserve(w.touches().size());
  for (const auto& t : w.touches()) {
    v.touches.push_back(Touch{t.feature(), model_axes(t.axes()), model_vec(t.approach())});
  }
  v.tracker_points.reserve(w.tracker_points().size());
  for (const auto& p : w.tracker_points()) {
    v.tracker_points.push_back(
        TrackerPoint{p.label(), model_axes(p.commanded()), model_vec(p.measured_mm())});
  }
  return v;
}

msg::CheckResult to_wire(const CheckResult& v) {
  msg::CheckResult w;
  w.machine_id(v.machine_id);
  w.request_id(v.request_id);
  w.kind(wire_kind(v.kind));
  w.verdict(wire_verdict(v.verdict));
  w.reason(v.reason);
  w.time_ns(v.time_ns);
  w.produced_by(v.produced_by);
  for (const auto& m : v.metrics) {
    msg::Metric wm;
    wm.name(m.name);
    wm.value(m.value);
    wm.unit(m.unit);
    wm.lower(m.lower);
    wm.upper(m.upper);
    wm.pass(m.pass);
    w.metrics().push_back(wm);
  }
  for (const auto& c : v.likely_causes) w.likely_causes().push_back(c);
  w.has_correction(v.correction.has_value());
  if (v.correction) w.correction(wire_correction(*v.correction));
  return w;
}
CheckResult from_wire(const msg::CheckResult& w, std::string& error) {
  CheckResult v;
  v.machine_id = w.machine_id();
  v.request_id = w.request_id();
  v.kind = model_kind(w.kind(), "CheckResult.kind", error);
  v.verdict = model_verdict(w.verdict(), "CheckResult.verdict", error);
  v.reason = w.reason();
  v.time_ns = w.time_ns();
  v.produced_by = w.produced_by();
  for (const auto& m : w.metrics()) {
    v.metrics.push_back(Metric{m.name(), m.value(), m.unit(), m.lower(), m.upper(), m.pass()});
  }
  for (const auto& c : w.likely_causes()) v.likely_causes.push_back(c);
  if (w.has_correction()) v.correction = model_correction(w.correction());
  return v;
}

msg::MachineStatus to_wire(const MachineStatus& v) {
  msg::MachineStatus w;
  w.machine_id(v.machine_id);
  w.request_id(v.request_id);
  w.state(static_cast<msg::MachineState>(static_cast<int>(v.state)));
  w.has_last_check(v.last_kind.has_value());
  if (v.last_kind) w.last_kind(wire_kind(*v.last_kind));
  w.last_verdict(wire_verdict(v.last_verdict.value_or(Verdict::Invalid)));
  w.detail(v.detail);
  w.time_ns(v.time_ns);
  return w;
}
MachineStatus from_wire(const msg::MachineStatus& w, std::string& error) {
  MachineStatus v;
  v.machine_id = w.machine_id();
  v.request_id = w.request_id();
  v.state =
      model_enum(w.state(), MachineState::Offline, v.state, "MachineStatus.state", "state", error);
  if (w.has_last_check()) {
    v.last_kind = model_kind(w.last_kind(), "MachineStatus.last_kind", error);
    v.last_verdict = model_verdict(w.last_verdict(), "MachineStatus.last_verdict", error);
  }
  v.detail = w.detail();
  v.time_ns = w.time_ns();
  return v;
}

msg::Intervention to_wire(const Intervention& v) {
  msg::Intervention w;
  w.machine_id(v.machine_id);
  w.intervention_id(v.intervention_id);
  w.kind(wire_kind(v.kind));
  w.note(v.note);
  w.operator_name(v.operator_name);
  w.time_ns(v.time_ns);
  return w;
}
Intervention from_wire(const msg::Intervention& w, std::string& error) {
  Intervention v;
  v.machine_id = w.machine_id();
  v.intervention_id = w.intervention_id();
  v.kind = model_kind(w.kind(), "Intervention.kind", error);
  v.note = w.note();
  v.operator_name = w.operator_name();
  v.time_ns = w.time_ns();
  return v;
}

msg::Compensation to_wire(const Compensation& v) {
  msg::Compensation w;
  w.machine_id(v.machine_id);
  w.request_id(v.request_id);
  w.correction(wire_correction(v.correction));
  w.time_ns(v.time_ns);
  return w;
}
Compensation from_wire(const msg::Compensation& w, std::string& /*error*/) {
  Compensation v;
  v.machine_id = w.machine_id();
  v.request_id = w.request_id();
  v.correction = model_correction(w.correction());
  v.time_ns = w.time_ns();
  return v;
}

msg::Heartbeat to_wire(const Heartbeat& v) {
  msg::Heartbeat w;
  w.machine_id(v.machine_id);
  w.service(v.service);
  w.instance(v.instance);
  w.state(v.state);
  w.time_ns(v.time_ns);
  w.health(v.health);
  w.health_detail(v.health_detail);
  w.outbox_depth(static_cast<std::int32_t>(std::min<std::int64_t>(v.outbox_depth, INT32_MAX)));
  w.oldest_unacknowledged_ns(v.oldest_unacknowledged_ns);
  return w;
}
Heartbeat from_wire(const msg::Heartbeat& w, std::string& /*error*/) {
  return Heartbeat{w.service(),       w.instance(),     w.machine_id(),
                   w.state(),         w.time_ns(),      w.health(),
                   w.health_detail(), w.outbox_depth(), w.oldest_unacknowledged_ns()};
}

msg::Acknowledgement to_wire(const Acknowledgement& v) {
  msg::Acknowledgement w;
  w.machine_id(v.machine_id);
  w.topic(v.topic);
  w.sample_id(v.sample_id);
  w.content_hash(v.content_hash);
  w.outcome(static_cast<msg::AckOutcome>(static_cast<int>(v.outcome)));
  w.by(v.by);
  w.instance(v.instance);
  w.detail(v.detail);
  w.time_ns(v.time_ns);
  return w;
}
Acknowledgement from_wire(const msg::Acknowledgement& w, std::string& error) {
  return Acknowledgement{w.machine_id(),
                         w.topic(),
                         w.sample_id(),
                         w.content_hash(),
                         model_enum(w.outcome(), AckOutcome::Accepted, AckOutcome::Refused,
                                    "outcome", "acknowledgement outcome", error),
                         w.by(),
                         w.instance(),
                         w.detail(),
                         w.time_ns()};
}

msg::Alarm to_wire(const Alarm& v) {
  msg::Alarm w;
  w.machine_id(v.machine_id);
  w.alarm_id(v.alarm_id);
  w.kind(static_cast<msg::AlarmKind>(static_cast<int>(v.kind)));
  w.active(v.active);
  w.source(v.source);
  w.instance(v.instance);
  w.text(v.text);
  w.time_ns(v.time_ns);
  return w;
}
Alarm from_wire(const msg::Alarm& w, std::string& error) {
  return Alarm{
      w.machine_id(),
      w.alarm_id(),
      model_enum(w.kind(), AlarmKind::Storage, AlarmKind::Conflict, "kind", "alarm kind", error),
      w.active(),
      w.source(),
      w.instance(),
      w.text(),
      w.time_ns()};
}

msg::TrendWarning to_wire(const TrendWarning& v) {
  msg::TrendWarning w;
  w.machine_id(v.machine_id);
  w.metric_name(v.metric);
  w.check_kind(wire_kind(v.check_kind));
  w.kind(v.kind);
  w.side(v.side);
  w.active(v.active);
  w.started_ns(v.started_ns);
  w.raised_by(v.raised_by);
  w.ended_by(v.ended_by);
  w.expected_crossing_ns(v.expected_crossing_ns.value_or(0));
  w.earliest_crossing_ns(v.earliest_crossing_ns.value_or(0));
  w.text(v.text);
  w.time_ns(v.time_ns);
  return w;
}
TrendWarning from_wire(const msg::TrendWarning& w, std::string& error) {
  const auto date = [](std::int64_t ns) {
    return ns == 0 ? std::nullopt : std::optional<std::int64_t>(ns);
  };
  TrendWarning v;
  v.machine_id = w.machine_id();
  v.metric = w.metric_name();
  v.check_kind = model_kind(w.check_kind(), "TrendWarning.check_kind", error);
  v.kind = w.kind();
  v.side = w.side();
  v.active = w.active();
  v.started_ns = w.started_ns();
  v.raised_by = w.raised_by();
  v.ended_by = w.ended_by();
  v.expected_crossing_ns = date(w.expected_crossing_ns());
  v.earliest_crossing_ns = date(w.earliest_crossing_ns());
  v.text = w.text();
  v.time_ns = w.time_ns();
  return v;
}

}  // namespace ncqual::dds
