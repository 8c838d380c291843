// SPDX-License-Identifier: Apache-2.0
// JSON of the model's types, declared once with nlohmann-json's macros. Every JSON document of
// ncqual (the CLI's --json outputs, the services' state documents) is a struct declared with
// NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE beside the code that fills it, built from these:
// - an enumeration is written by its name (to_string) and read back by name; an unknown name is
//   refused with the enumeration and the name;
// - an empty std::optional is null, and null reads back as empty;
// - a map keyed by check kind is an object keyed by the kind's name;
// - an Eigen vector (Vector2d, Vector3d) is an array of its components;
// - a non-finite double is written as null (nlohmann's rule; JSON has no infinity), so a
//   one-sided tolerance band has a null bound.
// Object keys come out sorted (nlohmann::json keeps them in a std::map).
#pragma once

#include "ncqual/common/model.hpp"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <map>
#include <optional>
#include <stdexcept>
#include <string>

namespace nlohmann {

template <typename T>
struct adl_serializer<std::optional<T>> {
  static void to_json(json& j, const std::optional<T>& v) {
    if (v) {
      j = *v;
    } else {
      j = nullptr;
    }
  }
  static void from_json(const json& j, std::optional<T>& v) {
    if (j.is_null()) {
      v.reset();
    } else {
      v = j.get<T>();
    }
  }
};

template <typename V>
struct adl_serializer<std::map<ncqual::CheckKind, V>> {
  static void to_json(json& j, const std::map<ncqual::CheckKind, V>& m) {
    j = json::object();
    for (const auto& [kind, value] : m) j[std::string(ncqual::to_string(kind))] = value;
  }
  static void from_json(const json& j, std::map<ncqual::CheckKind, V>& m) {
    m.clear();
    for (const auto& [name, value] : j.items()) m[json(name).get<ncqual::CheckKind>()] = value;
  }
};

template <int N>
struct adl_serializer<Eigen::Matrix<double, N, 1>> {
  static void to_json(json& j, const Eigen::Matrix<double, N, 1>& v) {
    j = json::array();
    for (int i = 0; i < N; ++i) j.push_back(v[i]);
  }
  static void from_json(const json& j, Eigen::Matrix<double, N, 1>& v) {
    if (!j.is_array() || j.size() != static_cast<std::size_t>(N)) {
      throw std::invalid_argument("expected an array of " + std::to_string(N) + " numbers, got " +
                                  j.dump());
    }
    for (int i = 0; i < N; ++i) v[i] = j[static_cast<std::size_t>(i)].get<double>();
  }
};

}  // namespace nlohmann

namespace ncqual {

namespace detail {
// Reads an enumeration by the name its to_string gives, through its parse function.
template <typename Enum, typename Parse>
void enum_from_json(const nlohmann::json& j, Enum& v, Parse parse, const char* enum_name) {
  const auto parsed = parse(j.get<std::string>());
  if (!parsed) {
    throw std::invalid_argument(std::string(enum_name) + " '" + j.get<std::string>() +
                                "' is not known");
  }
  v = *parsed;
}
}  // namespace detail

inline void to_json(nlohmann::json& j, CheckKind v) { j = std::string(to_string(v)); }
inline void from_json(const nlohmann::json& j, CheckKind& v) {
  detail::enum_from_json(j, v, parse_check_kind, "CheckKind");
}
inline void to_json(nlohmann::json& j, Verdict v) { j = std::string(to_string(v)); }
inline void from_json(const nlohmann::json& j, Verdict& v) {
  detail::enum_from_json(j, v, parse_verdict, "Verdict");
}
inline void to_json(nlohmann::json& j, MachineState v) { j = std::string(to_string(v)); }
inline void from_json(const nlohmann::json& j, MachineState& v) {
  detail::enum_from_json(j, v, parse_machine_state, "MachineState");
}

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(NamedValue, name, value, unit)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Metric, name, value, unit, lower, upper, pass)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Correction, target, offsets)
// Missing fields read as their defaults: documents written before a field existed still load.
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(CheckRequest, machine_id, request_id, kind,
                                                requested_by, time_ns, attempt, parameters,
                                                verifies_correction_of)

// The other samples, as the historian keeps a conflicting one (storage: conflicts.document).
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(AxisPosition, x_mm, y_mm, z_mm, w_mm, a_rad, c_rad)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Touch, feature, axes, approach)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TrackerPoint, label, commanded, measured_mm)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(MeasurementSet, machine_id, request_id, kind, instrument, frame,
                                   time_ns, touches, tracker_points, parameters, error)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CheckResult, machine_id, request_id, kind, verdict, metrics,
                                   likely_causes, reason, correction, time_ns, produced_by)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(MachineStatus, machine_id, request_id, state, last_kind,
                                   last_verdict, detail, time_ns)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Intervention, machine_id, intervention_id, kind, note,
                                   operator_name, time_ns)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Compensation, machine_id, request_id, correction, time_ns)

}  // namespace ncqual
