// SPDX-License-Identifier: Apache-2.0
// The wire types generated from idl/ncqual.idl and the model, converted field by field from the
// field lists of ncqual/common/model.hpp (NCQUAL_FIELDS_*): each X field by its type below, each S
// field by hand beside its struct's conversion.
#include "ncqual/dds/convert.hpp"

#include <algorithm>
#include <climits>
#include <type_traits>

namespace ncqual::dds {
namespace {

void note(std::string& error, const std::string& what) {
  if (error.empty()) error = what;
}

// ---- Enumerations: the model's and the IDL's share their numbering (idl/ncqual.idl). From the
// wire one out of range is noted ("<Struct.field> = 7 is not a known <what>") and read as
// `fallback`.
template <typename Model>
struct OnWire;
template <>
struct OnWire<CheckKind> {
  using Wire = msg::CheckKind;
  static constexpr auto kLast = static_cast<CheckKind>(kCheckKindCount - 1);
  static constexpr auto kFallback = CheckKind::MonumentPositioning;
  static constexpr const char* kWhat = "check kind";
};
template <>
struct OnWire<Verdict> {
  using Wire = msg::Verdict;
  static constexpr auto kLast = Verdict::Invalid;
  static constexpr auto kFallback = Verdict::Invalid;
  static constexpr const char* kWhat = "verdict";
};
template <>
struct OnWire<MachineState> {
  using Wire = msg::MachineState;
  static constexpr auto kLast = MachineState::Offline;
  static constexpr auto kFallback = MachineState::Unknown;
  static constexpr const char* kWhat = "state";
};
template <>
struct OnWire<DataOrigin> {
  using Wire = msg::DataOrigin;
  static constexpr auto kLast = DataOrigin::Simulated;
  static constexpr auto kFallback = DataOrigin::Unknown;
  static constexpr const char* kWhat = "data origin";
};
template <>
struct OnWire<AckOutcome> {
  using Wire = msg::AckOutcome;
  static constexpr auto kLast = AckOutcome::Accepted;
  static constexpr auto kFallback = AckOutcome::Refused;
  static constexpr const char* kWhat = "acknowledgement outcome";
};
template <>
struct OnWire<AlarmKind> {
  using Wire = msg::AlarmKind;
  static constexpr auto kLast = AlarmKind::Storage;
  static constexpr auto kFallback = AlarmKind::Conflict;
  static constexpr const char* kWhat = "alarm kind";
};

// Where a field is, for a note: "CheckResult.verdict".
struct Field {
  const char* type;
  const char* name;
  std::string text() const { return std::string(type) + "." + name; }
};

// ---- To the wire, by type -------------------------------------------------------------------
template <typename T, std::enable_if_t<std::is_arithmetic_v<T>, int> = 0>
T wire_value(T v) {
  return v;
}
const std::string& wire_value(const std::string& v) { return v; }
template <typename E, std::enable_if_t<std::is_enum_v<E>, int> = 0>
typename OnWire<E>::Wire wire_value(E v) {
  return static_cast<typename OnWire<E>::Wire>(static_cast<int>(v));
}
msg::Vector3 wire_value(const Eigen::Vector3d& v) {
  msg::Vector3 w;
  w.x(v.x());
  w.y(v.y());
  w.z(v.z());
  return w;
}
msg::AxisPosition wire_value(const AxisPosition& v);
msg::NamedValue wire_value(const NamedValue& v);
msg::Touch wire_value(const Touch& v);
msg::TrackerPoint wire_value(const TrackerPoint& v);
msg::Metric wire_value(const Metric& v);
msg::SoftwareCorrection wire_value(const Correction& v);
template <typename T>
auto wire_value(const std::vector<T>& v) {
  std::vector<std::decay_t<decltype(wire_value(std::declval<const T&>()))>> w;
  w.reserve(v.size());
  for (const auto& x : v) w.push_back(wire_value(x));
  return w;
}

// ---- From the wire, by type ---------------------------------------------------------------------
template <typename T, std::enable_if_t<std::is_arithmetic_v<T>, int> = 0>
void model_value(T w, T& v, const Field& /*field*/, std::string& /*error*/) {
  v = w;
}
void model_value(const std::string& w, std::string& v, const Field& /*field*/,
                 std::string& /*error*/) {
  v = w;
}
template <typename E, std::enable_if_t<std::is_enum_v<E>, int> = 0>
void model_value(typename OnWire<E>::Wire w, E& v, const Field& field, std::string& error) {
  const auto raw = static_cast<std::uint32_t>(w);
  if (raw > static_cast<std::uint32_t>(OnWire<E>::kLast)) {
    note(error, field.text() + " = " + std::to_string(raw) + " is not a known " + OnWire<E>::kWhat);
    v = OnWire<E>::kFallback;
    return;
  }
  v = static_cast<E>(raw);
}
void model_value(const msg::Vector3& w, Eigen::Vector3d& v, const Field& /*field*/,
                 std::string& /*error*/) {
  v = {w.x(), w.y(), w.z()};
}
void model_value(const msg::AxisPosition& w, AxisPosition& v, const Field& field,
                 std::string& error);
void model_value(const msg::NamedValue& w, NamedValue& v, const Field& field, std::string& error);
void model_value(const msg::Touch& w, Touch& v, const Field& field, std::string& error);
void model_value(const msg::TrackerPoint& w, TrackerPoint& v, const Field& field,
                 std::string& error);
void model_value(const msg::Metric& w, Metric& v, const Field& field, std::string& error);
void model_value(const msg::SoftwareCorrection& w, Correction& v, const Field& field,
                 std::string& error);
template <typename W, typename M>
void model_value(const std::vector<W>& w, std::vector<M>& v, const Field& field,
                 std::string& error) {
  v.resize(w.size());
  for (std::size_t i = 0; i < w.size(); ++i) model_value(w[i], v[i], field, error);
}

// ---- Structs, from their field lists ------------------------------------------------------------
// Their arguments are types and field names, which cannot be parenthesised.
// NOLINTBEGIN(bugprone-macro-parentheses)
#define NCQUAL_TO_WIRE(f) w.f(wire_value(v.f));
#define NCQUAL_FROM_WIRE(f) model_value(w.f(), v.f, Field{type, #f}, error);
#define NCQUAL_BY_HAND(f)
// The X fields of `Model`, both ways: wire_fields(model, wire) and model_fields(wire, model).
#define NCQUAL_CONVERT_FIELDS(Model, Wire, FIELDS)                                  \
  [[maybe_unused]] void wire_fields(const Model& v, Wire& w) {                      \
    FIELDS(NCQUAL_TO_WIRE, NCQUAL_BY_HAND)                                          \
  }                                                                                 \
  [[maybe_unused]] void model_fields(const Wire& w, Model& v, std::string& error) { \
    [[maybe_unused]] constexpr const char* type = #Model;                           \
    FIELDS(NCQUAL_FROM_WIRE, NCQUAL_BY_HAND)                                        \
  }
// A part of a sample (no S fields): wire_value and model_value of its own.
#define NCQUAL_CONVERT_PART(Model, Wire, FIELDS)                                          \
  NCQUAL_CONVERT_FIELDS(Model, Wire, FIELDS)                                              \
  Wire wire_value(const Model& v) {                                                       \
    Wire w;                                                                               \
    wire_fields(v, w);                                                                    \
    return w;                                                                             \
  }                                                                                       \
  void model_value(const Wire& w, Model& v, const Field& /*field*/, std::string& error) { \
    model_fields(w, v, error);                                                            \
  }

// NOLINTEND(bugprone-macro-parentheses)

NCQUAL_CONVERT_PART(AxisPosition, msg::AxisPosition, NCQUAL_FIELDS_AXIS_POSITION)
NCQUAL_CONVERT_PART(NamedValue, msg::NamedValue, NCQUAL_FIELDS_NAMED_VALUE)
NCQUAL_CONVERT_PART(Touch, msg::Touch, NCQUAL_FIELDS_TOUCH)
NCQUAL_CONVERT_PART(TrackerPoint, msg::TrackerPoint, NCQUAL_FIELDS_TRACKER_POINT)
NCQUAL_CONVERT_PART(Metric, msg::Metric, NCQUAL_FIELDS_METRIC)
NCQUAL_CONVERT_PART(Correction, msg::SoftwareCorrection, NCQUAL_FIELDS_CORRECTION)
NCQUAL_CONVERT_FIELDS(CheckRequest, msg::CheckRequest, NCQUAL_FIELDS_CHECK_REQUEST)
NCQUAL_CONVERT_FIELDS(CheckCommand, msg::CheckCommand, NCQUAL_FIELDS_CHECK_COMMAND)
NCQUAL_CONVERT_FIELDS(MeasurementSet, msg::v2::MeasurementSet, NCQUAL_FIELDS_MEASUREMENT_SET)
NCQUAL_CONVERT_FIELDS(CheckResult, msg::v2::CheckResult, NCQUAL_FIELDS_CHECK_RESULT)
// Contract 1's layouts: the same X fields, no origin.
NCQUAL_CONVERT_FIELDS(MeasurementSet, msg::MeasurementSet, NCQUAL_FIELDS_MEASUREMENT_SET)
NCQUAL_CONVERT_FIELDS(CheckResult, msg::CheckResult, NCQUAL_FIELDS_CHECK_RESULT)
NCQUAL_CONVERT_FIELDS(MachineStatus, msg::MachineStatus, NCQUAL_FIELDS_MACHINE_STATUS)
NCQUAL_CONVERT_FIELDS(Intervention, msg::Intervention, NCQUAL_FIELDS_INTERVENTION)
NCQUAL_CONVERT_FIELDS(Compensation, msg::Compensation, NCQUAL_FIELDS_COMPENSATION)
NCQUAL_CONVERT_FIELDS(Heartbeat, msg::Heartbeat, NCQUAL_FIELDS_HEARTBEAT)
NCQUAL_CONVERT_FIELDS(Acknowledgement, msg::Acknowledgement, NCQUAL_FIELDS_ACKNOWLEDGEMENT)
NCQUAL_CONVERT_FIELDS(Alarm, msg::Alarm, NCQUAL_FIELDS_ALARM)
NCQUAL_CONVERT_FIELDS(TrendWarning, msg::TrendWarning, NCQUAL_FIELDS_TREND_WARNING)

#undef NCQUAL_CONVERT_PART
#undef NCQUAL_CONVERT_FIELDS
#undef NCQUAL_BY_HAND
#undef NCQUAL_FROM_WIRE
#undef NCQUAL_TO_WIRE

// A sample with no S field, both ways.
template <typename Wire, typename Model>
Wire plain_to_wire(const Model& v) {
  Wire w;
  wire_fields(v, w);
  return w;
}
template <typename Model, typename Wire>
Model plain_from_wire(const Wire& w, std::string& error) {
  Model v;
  model_fields(w, v, error);
  return v;
}

}  // namespace

msg::CheckRequest to_wire(const CheckRequest& v) { return plain_to_wire<msg::CheckRequest>(v); }
CheckRequest from_wire(const msg::CheckRequest& w, std::string& error) {
  return plain_from_wire<CheckRequest>(w, error);
}
msg::CheckCommand to_wire(const CheckCommand& v) { return plain_to_wire<msg::CheckCommand>(v); }
CheckCommand from_wire(const msg::CheckCommand& w, std::string& error) {
  return plain_from_wire<CheckCommand>(w, error);
}
// S: origin, from contract 2 on.
msg::v2::MeasurementSet to_wire(const MeasurementSet& v) {
  msg::v2::MeasurementSet w = plain_to_wire<msg::v2::MeasurementSet>(v);
  w.origin(wire_value(v.origin));
  return w;
}
MeasurementSet from_wire(const msg::v2::MeasurementSet& w, std::string& error) {
  MeasurementSet v = plain_from_wire<MeasurementSet>(w, error);
  model_value(w.origin(), v.origin, Field{"MeasurementSet", "origin"}, error);
  return v;
}
msg::MeasurementSet to_wire_contract1(const MeasurementSet& v) {
  return plain_to_wire<msg::MeasurementSet>(v);
}
MeasurementSet from_wire(const msg::MeasurementSet& w, std::string& error) {
  return plain_from_wire<MeasurementSet>(w, error);  // origin: Unknown
}
msg::Intervention to_wire(const Intervention& v) { return plain_to_wire<msg::Intervention>(v); }
Intervention from_wire(const msg::Intervention& w, std::string& error) {
  return plain_from_wire<Intervention>(w, error);
}
msg::Compensation to_wire(const Compensation& v) { return plain_to_wire<msg::Compensation>(v); }
Compensation from_wire(const msg::Compensation& w, std::string& error) {
  return plain_from_wire<Compensation>(w, error);
}
msg::Acknowledgement to_wire(const Acknowledgement& v) {
  return plain_to_wire<msg::Acknowledgement>(v);
}
Acknowledgement from_wire(const msg::Acknowledgement& w, std::string& error) {
  return plain_from_wire<Acknowledgement>(w, error);
}
msg::Alarm to_wire(const Alarm& v) { return plain_to_wire<msg::Alarm>(v); }
Alarm from_wire(const msg::Alarm& w, std::string& error) {
  return plain_from_wire<Alarm>(w, error);
}

// S: correction travels with has_correction; origin from contract 2 on.
template <typename Wire>
Wire result_to_wire(const CheckResult& v) {
  Wire w = plain_to_wire<Wire>(v);
  w.has_correction(v.correction.has_value());
  if (v.correction) w.correction(wire_value(*v.correction));
  return w;
}
template <typename Wire>
CheckResult result_from_wire(const Wire& w, std::string& error) {
  CheckResult v = plain_from_wire<CheckResult>(w, error);
  if (w.has_correction()) {
    model_value(w.correction(), v.correction.emplace(), Field{"CheckResult", "correction"}, error);
  }
  return v;
}
msg::v2::CheckResult to_wire(const CheckResult& v) {
  msg::v2::CheckResult w = result_to_wire<msg::v2::CheckResult>(v);
  w.origin(wire_value(v.origin));
  return w;
}
CheckResult from_wire(const msg::v2::CheckResult& w, std::string& error) {
  CheckResult v = result_from_wire(w, error);
  model_value(w.origin(), v.origin, Field{"CheckResult", "origin"}, error);
  return v;
}
msg::CheckResult to_wire_contract1(const CheckResult& v) {
  return result_to_wire<msg::CheckResult>(v);
}
CheckResult from_wire(const msg::CheckResult& w, std::string& error) {
  return result_from_wire(w, error);  // origin: Unknown
}

// S: last_kind and last_verdict travel with has_last_check (the verdict INVALID when none).
msg::MachineStatus to_wire(const MachineStatus& v) {
  msg::MachineStatus w = plain_to_wire<msg::MachineStatus>(v);
  w.has_last_check(v.last_kind.has_value());
  if (v.last_kind) w.last_kind(wire_value(*v.last_kind));
  w.last_verdict(wire_value(v.last_verdict.value_or(Verdict::Invalid)));
  return w;
}
MachineStatus from_wire(const msg::MachineStatus& w, std::string& error) {
  MachineStatus v = plain_from_wire<MachineStatus>(w, error);
  if (w.has_last_check()) {
    model_value(w.last_kind(), v.last_kind.emplace(), Field{"MachineStatus", "last_kind"}, error);
    model_value(w.last_verdict(), v.last_verdict.emplace(), Field{"MachineStatus", "last_verdict"},
                error);
  }
  return v;
}

// S: outbox_depth is 32-bit on the wire, clamped.
msg::Heartbeat to_wire(const Heartbeat& v) {
  msg::Heartbeat w = plain_to_wire<msg::Heartbeat>(v);
  w.outbox_depth(static_cast<std::int32_t>(std::min<std::int64_t>(v.outbox_depth, INT32_MAX)));
  return w;
}
Heartbeat from_wire(const msg::Heartbeat& w, std::string& error) {
  Heartbeat v = plain_from_wire<Heartbeat>(w, error);
  v.outbox_depth = w.outbox_depth();
  return v;
}

// S: metric is metric_name on the wire; the crossing dates are 0 there when none.
msg::TrendWarning to_wire(const TrendWarning& v) {
  msg::TrendWarning w = plain_to_wire<msg::TrendWarning>(v);
  w.metric_name(v.metric);
  w.expected_crossing_ns(v.expected_crossing_ns.value_or(0));
  w.earliest_crossing_ns(v.earliest_crossing_ns.value_or(0));
  return w;
}
TrendWarning from_wire(const msg::TrendWarning& w, std::string& error) {
  const auto date = [](std::int64_t ns) {
    return ns == 0 ? std::nullopt : std::optional<std::int64_t>(ns);
  };
  TrendWarning v = plain_from_wire<TrendWarning>(w, error);
  v.metric = w.metric_name();
  v.expected_crossing_ns = date(w.expected_crossing_ns());
  v.earliest_crossing_ns = date(w.earliest_crossing_ns());
  return v;
}

}  // namespace ncqual::dds
