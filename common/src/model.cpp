// SPDX-License-Identifier: Apache-2.0
#include "ncqual/common/model.hpp"

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/enum_names.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace ncqual {
namespace {

constexpr std::array<std::string_view, 3> kVerdictNames = {"PASS", "FAIL", "INVALID"};
constexpr std::array<std::string_view, 6> kStateNames = {
    "UNKNOWN", "QUALIFIED", "CHECKING", "NEEDS_INTERVENTION", "OVERDUE", "OFFLINE"};
constexpr std::array<std::string_view, 5> kAckNames = {"STORED", "DUPLICATE", "CONFLICT", "REFUSED",
                                                       "ACCEPTED"};
constexpr std::array<std::string_view, 3> kOriginNames = {"unknown", "measured", "simulated"};
constexpr std::array<std::string_view, 2> kAlarmNames = {"CONFLICT", "STORAGE"};

}  // namespace

// Check kinds are named by their row of the table (ncqual/common/check_kinds.hpp).
std::string_view to_string(CheckKind kind) {
  const int k = static_cast<int>(kind);
  return k >= 0 && k < kCheckKindCount ? check_kind_info(kind).name : "unknown";
}
std::optional<CheckKind> parse_check_kind(std::string_view name) {
  for (const auto& row : check_kinds()) {
    if (row.name == name) return row.kind;
  }
  return std::nullopt;
}
std::vector<CheckKind> all_check_kinds() {
  std::vector<CheckKind> kinds;
  kinds.reserve(kCheckKindCount);
  for (int i = 0; i < kCheckKindCount; ++i) kinds.push_back(static_cast<CheckKind>(i));
  return kinds;
}

std::string_view to_string(Verdict verdict) { return name_of(kVerdictNames, verdict, "unknown"); }
std::optional<Verdict> parse_verdict(std::string_view name) {
  return enum_named<Verdict>(kVerdictNames, name);
}

std::string_view to_string(DataOrigin origin) { return name_of(kOriginNames, origin, "unknown"); }
std::optional<DataOrigin> parse_data_origin(std::string_view name) {
  return enum_named<DataOrigin>(kOriginNames, name);
}

std::string_view to_string(MachineState state) { return name_of(kStateNames, state, "unknown"); }
std::optional<MachineState> parse_machine_state(std::string_view name) {
  return enum_named<MachineState>(kStateNames, name);
}

std::string_view to_string(AckOutcome outcome) { return name_of(kAckNames, outcome, "unknown"); }
std::optional<AckOutcome> parse_ack_outcome(std::string_view name) {
  return enum_named<AckOutcome>(kAckNames, name);
}

std::string_view to_string(AlarmKind kind) { return name_of(kAlarmNames, kind, "unknown"); }
std::optional<AlarmKind> parse_alarm_kind(std::string_view name) {
  return enum_named<AlarmKind>(kAlarmNames, name);
}

std::string sample_id_of(const CheckRequest& v) { return v.request_id; }
std::string sample_id_of(const CheckCommand& v) { return v.request_id; }
std::string sample_id_of(const MeasurementSet& v) { return v.request_id; }
std::string sample_id_of(const CheckResult& v) { return v.request_id; }
std::string sample_id_of(const Compensation& v) { return v.request_id + "/" + v.correction.target; }
std::string sample_id_of(const Intervention& v) { return v.intervention_id; }
std::string sample_id_of(const MachineStatus& v) {
  return v.machine_id + "/" + std::to_string(v.time_ns) + "/" + std::string(to_string(v.state)) +
         "/" + v.request_id;
}

const Metric* find_metric(const CheckResult& result, std::string_view name) {
  for (const auto& m : result.metrics) {
    if (m.name == name) return &m;
  }
  return nullptr;
}

int metric_decimals(const Metric& metric) {
  const bool lower = std::isfinite(metric.lower);
  const bool upper = std::isfinite(metric.upper);
  const double band = lower && upper ? metric.upper - metric.lower
                      : lower        ? std::abs(metric.lower)
                      : upper        ? std::abs(metric.upper)
                                     : 0.0;
  if (!(band > 0)) return 4;
  // Rounded first, so a tenth of 0.05 (0.005000000000000001) is 3 decimals, not 4.
  const double digits = std::ceil(-std::log10(band / 10) - 1e-9);
  return static_cast<int>(std::clamp(digits, 0.0, 9.0));
}

std::string format_metric_value(const Metric& metric) {
  if (!std::isfinite(metric.value)) return "n/a";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", metric_decimals(metric), metric.value);
  std::string text = buffer;
  // -0.0002 at 3 decimals is 0.000, not "-0.000": the sign of nothing shown says nothing.
  if (text[0] == '-' && text.find_first_not_of("-0.") == std::string::npos) text.erase(0, 1);
  return text;
}

MeasurementSet measurement_set_for(const CheckRequest& request, std::int64_t time_ns) {
  MeasurementSet set;
  set.machine_id = request.machine_id;
  set.request_id = request.request_id;
  set.kind = request.kind;
  set.time_ns = time_ns;
  set.parameters = request.parameters;
  return set;
}

const NamedValue* find_value(const std::vector<NamedValue>& values, std::string_view name) {
  for (const auto& v : values) {
    if (v.name == name) return &v;
  }
  return nullptr;
}

}  // namespace ncqual
