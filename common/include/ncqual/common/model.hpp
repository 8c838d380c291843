// SPDX-License-Identifier: Apache-2.0
// The domain model shared by every part of ncqual: plain C++ values, no DDS.
//
// The wire types in idl/ mirror these one to one; dds/ converts between them, so
// that the solver, the storage and the simulator never see a generated type.
// Units: millimetres, radians and nanoseconds since the Unix epoch (UTC).
#pragma once

#include <Eigen/Core>

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ncqual {

// Every check of the qualification process. The numeric values are those of the IDL enum
// and of the `kind` columns in the historian: never renumber, only append.
enum class CheckKind : int {
  MonumentCAlignment = 0,      // daily 1: probe alignment with the C axis
  MonumentToolLength = 1,      // daily 2: composite tool length
  MonumentPositioning = 2,     // daily 3: repeatable X, Y, Z positioning
  MonumentCRotation = 3,       // daily 4: C-axis rotational accuracy
  FixturePreCalibration = 4,   // weekly
  FixturePostCalibration = 5,  // weekly, after a zero-offset correction
  PartSetPoints = 6,           // per part
  GlobalMasterFrame = 7,       // monthly, laser tracker
  GlobalGrid = 8,
  RotaryW = 9,
  RotaryA = 10,
  RotaryC = 11,
  CircleXY = 12,
  CircleYZ = 13,
  CircleXZ = 14,
  LinearAxisRun = 15,
};
inline constexpr int kCheckKindCount = 16;

// Stable names used in config, the command line, logs and JSON output.
std::string_view to_string(CheckKind kind);
// Parses a stable name; std::nullopt when the name is not a check kind.
std::optional<CheckKind> parse_check_kind(std::string_view name);
std::vector<CheckKind> all_check_kinds();

enum class Verdict : int { Pass = 0, Fail = 1, Invalid = 2 };
std::string_view to_string(Verdict verdict);
std::optional<Verdict> parse_verdict(std::string_view name);

// Where a set's numbers (and so its result's) come from; its numbering is the IDL's DataOrigin.
// Unknown: a sample of wire contract 1 or a row stored before schema 11; never assumed measured.
enum class DataOrigin : int { Unknown = 0, Measured = 1, Simulated = 2 };
std::string_view to_string(DataOrigin origin);  // "unknown", "measured", "simulated"
std::optional<DataOrigin> parse_data_origin(std::string_view name);

enum class MachineState : int {
  Unknown = 0,
  Qualified = 1,
  Checking = 2,
  NeedsIntervention = 3,
  Overdue = 4,
  Offline = 5,
};
std::string_view to_string(MachineState state);
std::optional<MachineState> parse_machine_state(std::string_view name);

// The fields of each struct below are listed once, in the NCQUAL_FIELDS_<STRUCT>(X, S) macro that
// follows it: the wire conversion (dds/src/convert.cpp) and the JSON (ncqual/common/json.hpp) are
// generated from these lists, so a new field touches the IDL, the struct and its list. X(f): a
// field the wire carries under the same name, converted by its type; S(f): one the wire carries
// differently (the comment above the list says how), converted by hand in convert.cpp and plain in
// JSON. The storage (storage/src) binds its columns by hand: a stored field also needs a migration.
// Readouts of the machine's six axes: X, Y, Z position of the wrist pivot (intersection of the
// A and C axes) in the machine frame, W spindle travel along the tool axis, A and C wrist angles.
struct AxisPosition {
  double x_mm = 0, y_mm = 0, z_mm = 0, w_mm = 0, a_rad = 0, c_rad = 0;
};
// clang-format off
#define NCQUAL_FIELDS_AXIS_POSITION(X, S) X(x_mm) X(y_mm) X(z_mm) X(w_mm) X(a_rad) X(c_rad)
// clang-format on

// A named number with its unit: request parameters, correction offsets.
struct NamedValue {
  std::string name;
  double value = 0;
  std::string unit;
};
// clang-format off
#define NCQUAL_FIELDS_NAMED_VALUE(X, S) X(name) X(value) X(unit)
// clang-format on

// Looks up a named value; nullptr when absent.
const NamedValue* find_value(const std::vector<NamedValue>& values, std::string_view name);

// One touch of a touch-trigger probe: the axis readouts latched when the probe triggered, and
// the direction the stylus was moving in (unit vector, machine frame). `feature` names what was
// touched, e.g. "hole_edge", "face".
struct Touch {
  std::string feature;
  AxisPosition axes;
  Eigen::Vector3d approach = Eigen::Vector3d::Zero();
};
// clang-format off
#define NCQUAL_FIELDS_TOUCH(X, S) X(feature) X(axes) X(approach)
// clang-format on

// One point measured by a laser tracker (or other 3-D instrument): the commanded axes and the
// target position in the instrument's frame (mm).
struct TrackerPoint {
  std::string label;
  AxisPosition commanded;
  Eigen::Vector3d measured_mm = Eigen::Vector3d::Zero();
};
// clang-format off
#define NCQUAL_FIELDS_TRACKER_POINT(X, S) X(label) X(commanded) X(measured_mm)
// clang-format on

// MeasurementSet::instrument of a set published by `ncqual import` from an instrument's file:
// no CheckRequest precedes it.
inline constexpr std::string_view kImportedInstrument = "import";

// Raw measurements answering one CheckRequest. Never the answer: judging is the solver's.
struct MeasurementSet {
  std::string machine_id;
  std::string request_id;
  CheckKind kind = CheckKind::MonumentPositioning;
  std::string instrument;  // "touch_probe", "laser_tracker", kImportedInstrument
  std::string frame;       // frame of the coordinates: "machine", "tracker"
  std::int64_t time_ns = 0;
  std::vector<Touch> touches;
  std::vector<TrackerPoint> tracker_points;
  // The request's parameters, echoed by the instrument so the solver knows what was asked
  // (e.g. "fixture_configuration" of a weekly fixture check).
  std::vector<NamedValue> parameters;
  std::string error;  // non-empty when the instrument could not perform the request
  DataOrigin origin = DataOrigin::Unknown;  // measured by an instrument, or simulated
};
// S: origin exists on the wire from contract 2 on (v2::MeasurementSet), not in contract 1's type.
// clang-format off
#define NCQUAL_FIELDS_MEASUREMENT_SET(X, S) \
  X(machine_id) X(request_id) X(kind) X(instrument) X(frame) X(time_ns) X(touches) \
  X(tracker_points) X(parameters) X(error) S(origin)
// clang-format on

struct Metric {
  std::string name;  // public interface, e.g. "center_dx_mm"
  double value = 0;
  std::string unit;  // "mm", "rad", "arcsec", ...
  double lower = 0;  // tolerance band: pass when lower <= value <= upper
  double upper = 0;
  bool pass = false;
};
// clang-format off
#define NCQUAL_FIELDS_METRIC(X, S) X(name) X(value) X(unit) X(lower) X(upper) X(pass)
// clang-format on

// A software correction: offsets to apply to `target` (e.g. "fixture:F1", "machine:work_offset").
struct Correction {
  std::string target;
  std::vector<NamedValue> offsets;
};
// clang-format off
#define NCQUAL_FIELDS_CORRECTION(X, S) X(target) X(offsets)
// clang-format on

struct CheckRequest {
  std::string machine_id;
  std::string request_id;
  CheckKind kind = CheckKind::MonumentPositioning;
  std::string requested_by;  // "scheduler", "operator:<name>", ...
  std::int64_t time_ns = 0;
  std::int32_t attempt = 1;
  // What the check should do beyond its kind, e.g. "fixture_configuration" = 3 (0-based index
  // of the weekly rotation). Empty for most checks.
  std::vector<NamedValue> parameters;
  // A fixture post-calibration verifies the zero offsets a pre-calibration issued: the request
  // id of that pre-calibration, whose Compensation the instrument must have applied before it
  // measures. Empty otherwise.
  std::string verifies_correction_of;
};
// clang-format off
#define NCQUAL_FIELDS_CHECK_REQUEST(X, S) \
  X(machine_id) X(request_id) X(kind) X(requested_by) X(time_ns) X(attempt) X(parameters) \
  X(verifies_correction_of)
// clang-format on

struct CheckResult {
  std::string machine_id;
  std::string request_id;
  CheckKind kind = CheckKind::MonumentPositioning;
  Verdict verdict = Verdict::Invalid;
  std::vector<Metric> metrics;
  std::vector<std::string> likely_causes;  // in the order to investigate them
  std::string reason;                      // why INVALID or FAIL, in words
  std::optional<Correction> correction;
  std::int64_t time_ns = 0;
  // The software that judged it ("ncqual-solver 0.1.0 (git 1a2b3c4)"), so that a stored verdict
  // names the version that made it; empty for results stored before it was recorded.
  std::string produced_by;
  // The origin of the set it judged: a verdict on simulated numbers says nothing of a machine.
  DataOrigin origin = DataOrigin::Unknown;
};
// S: correction travels with has_correction on the wire; origin from contract 2 on.
// clang-format off
#define NCQUAL_FIELDS_CHECK_RESULT(X, S) \
  X(machine_id) X(request_id) X(kind) X(verdict) X(metrics) X(likely_causes) X(reason) \
  S(correction) X(time_ns) X(produced_by) S(origin)
// clang-format on

struct MachineStatus {
  std::string machine_id;
  std::string request_id;  // the request that caused this status, may be empty
  MachineState state = MachineState::Unknown;
  std::optional<CheckKind> last_kind;
  std::optional<Verdict> last_verdict;
  std::string detail;
  std::int64_t time_ns = 0;
};
// S: last_kind and last_verdict travel with has_last_check on the wire (INVALID when none).
// clang-format off
#define NCQUAL_FIELDS_MACHINE_STATUS(X, S) \
  X(machine_id) X(request_id) X(state) S(last_kind) S(last_verdict) X(detail) X(time_ns)
// clang-format on

struct Intervention {
  std::string machine_id;
  std::string intervention_id;
  CheckKind kind = CheckKind::MonumentPositioning;  // the check it re-arms
  std::string note;
  std::string operator_name;
  std::int64_t time_ns = 0;
};
// clang-format off
#define NCQUAL_FIELDS_INTERVENTION(X, S) \
  X(machine_id) X(intervention_id) X(kind) X(note) X(operator_name) X(time_ns)
// clang-format on

struct Compensation {
  std::string machine_id;
  std::string request_id;
  Correction correction;
  std::int64_t time_ns = 0;
};
// clang-format off
#define NCQUAL_FIELDS_COMPENSATION(X, S) X(machine_id) X(request_id) X(correction) X(time_ns)
// clang-format on

// An operator's order to the scheduler (`ncqual check`). The scheduler turns it into a
// CheckRequest with the same request id.
struct CheckCommand {
  std::string machine_id;
  std::string request_id;
  CheckKind kind = CheckKind::MonumentPositioning;
  std::string requested_by;
  std::int64_t time_ns = 0;
  std::vector<NamedValue> parameters;  // passed on to the CheckRequest
};
// clang-format off
#define NCQUAL_FIELDS_CHECK_COMMAND(X, S) \
  X(machine_id) X(request_id) X(kind) X(requested_by) X(time_ns) X(parameters)
// clang-format on

// How often every service publishes its Heartbeat; the plant's status calls a service silent after
// a few periods without one. Here, not in the DDS library, so that what reads the historian
// (status, ncqual-web) needs no DDS.
inline constexpr std::chrono::milliseconds kHeartbeatPeriod{2000};

struct Heartbeat {
  std::string service;     // "scheduler", "acquisition", "solver", "historian"
  std::string instance;    // host:pid
  std::string machine_id;  // the machine an acquisition serves; empty for plant-wide services
  std::string state;       // "starting", "running", "stopping"
  std::int64_t time_ns = 0;
  std::string health = "ok";      // "ok", "degraded", "failed": the service's storage and outbox
  std::string health_detail;      // why, when not ok
  std::int64_t outbox_depth = 0;  // samples sent and not yet acknowledged by all they await
  std::int64_t oldest_unacknowledged_ns = 0;  // queued time of the oldest of them; 0: none
};
// S: outbox_depth is 32-bit on the wire (clamped).
// clang-format off
#define NCQUAL_FIELDS_HEARTBEAT(X, S) \
  X(service) X(instance) X(machine_id) X(state) X(time_ns) X(health) X(health_detail) \
  S(outbox_depth) X(oldest_unacknowledged_ns)
// clang-format on

// What a service says about a sample it received (docs/architecture.md, "Acknowledged storage").
enum class AckOutcome : std::int32_t {
  Stored = 0,     // historian: committed
  Duplicate = 1,  // historian: the same sample was already stored
  Conflict = 2,   // historian: another sample with this id and other content is stored; this one
                  // is stored beside it, flagged
  Refused = 3,    // can never be used (detail says why): not to be sent again
  Accepted = 4,   // taken into the service's durable state
};
std::string_view to_string(AckOutcome outcome);
std::optional<AckOutcome> parse_ack_outcome(std::string_view name);

// The roles that acknowledge samples, as Acknowledgement::by names them.
namespace roles {
inline constexpr const char* kHistorian = "historian";
inline constexpr const char* kScheduler = "scheduler";
inline constexpr const char* kAcquisition = "acquisition";
inline constexpr const char* kSolver = "solver";
}  // namespace roles

struct Acknowledgement {
  std::string machine_id;
  std::string topic;         // "ncqual/CheckResult"
  std::string sample_id;     // sample_id_of() the sample
  std::string content_hash;  // SHA-256 of its CDR serialization, hex
  AckOutcome outcome = AckOutcome::Stored;
  std::string by;        // roles::
  std::string instance;  // host:pid
  std::string detail;
  std::int64_t time_ns = 0;
};
// clang-format off
#define NCQUAL_FIELDS_ACKNOWLEDGEMENT(X, S) \
  X(machine_id) X(topic) X(sample_id) X(content_hash) X(outcome) X(by) X(instance) X(detail) \
  X(time_ns)
// clang-format on

// What people must look at now (docs/architecture.md, "Acknowledged storage").
enum class AlarmKind : std::int32_t {
  Conflict = 0,  // a sample whose id is stored with other content: kept beside it, flagged
  Storage = 1,   // the historian cannot store
};
std::string_view to_string(AlarmKind kind);
std::optional<AlarmKind> parse_alarm_kind(std::string_view name);

struct Alarm {
  std::string machine_id;  // "" for the plant
  std::string alarm_id;    // conflict/<topic>/<sample id>/<content hash>; storage/<instance>
  AlarmKind kind = AlarmKind::Conflict;
  bool active = true;  // false: cleared
  std::string source;  // roles::
  std::string instance;
  std::string text;
  std::int64_t time_ns = 0;
};
// clang-format off
#define NCQUAL_FIELDS_ALARM(X, S) \
  X(machine_id) X(alarm_id) X(kind) X(active) X(source) X(instance) X(text) X(time_ns)
// clang-format on

// A trend warning's change (idl/ncqual.idl; docs/trends.md, "Warnings"): raised, updated or
// ended by the historian.
struct TrendWarning {
  std::string machine_id;
  std::string metric;
  CheckKind check_kind = CheckKind::MonumentPositioning;
  std::string kind;  // trend::to_string(WarningKind)
  std::string side;  // "above", "below"
  bool active = true;
  std::int64_t started_ns = 0;
  std::string raised_by;
  std::string ended_by;                              // "" while active
  std::optional<std::int64_t> expected_crossing_ns;  // 0 on the wire
  std::optional<std::int64_t> earliest_crossing_ns;  // 0 on the wire
  std::string text;
  std::int64_t time_ns = 0;
};
// S: metric is metric_name on the wire; the crossing dates are 0 there when none.
// clang-format off
#define NCQUAL_FIELDS_TREND_WARNING(X, S) \
  X(machine_id) S(metric) X(check_kind) X(kind) X(side) X(active) X(started_ns) X(raised_by) \
  X(ended_by) S(expected_crossing_ns) S(earliest_crossing_ns) X(text) X(time_ns)
// clang-format on

// The id a sample is acknowledged and stored under: its request id; an intervention's id; a
// status change's machine, time, state and request (the historian's identity of a status).
std::string sample_id_of(const CheckRequest& v);
std::string sample_id_of(const CheckCommand& v);
std::string sample_id_of(const MeasurementSet& v);
std::string sample_id_of(const CheckResult& v);
std::string sample_id_of(const Compensation& v);
std::string sample_id_of(const Intervention& v);
std::string sample_id_of(const MachineStatus& v);

// Looks up a metric by name; nullptr when absent.
const Metric* find_metric(const CheckResult& result, std::string_view name);

// The decimals a metric is shown with: enough that one step of the last digit is at most a tenth
// of its tolerance band (upper - lower; the finite bound's size for a one-sided band), so no
// display rounds a value across a tolerance (350.0601 mm against +-0.025 mm: 350.060, never 350.1);
// 4 when the band gives no scale (no finite bound, or zero), at most 9.
int metric_decimals(const Metric& metric);
// The value with metric_decimals(), without its unit; "n/a" for a value that could not be
// evaluated (NaN, infinite). Every text display of a metric goes through it.
std::string format_metric_value(const Metric& metric);

// The MeasurementSet that answers `request`, taken at `time_ns`, with nothing measured yet: its
// machine, request id, kind and parameters.
MeasurementSet measurement_set_for(const CheckRequest& request, std::int64_t time_ns);

}  // namespace ncqual
