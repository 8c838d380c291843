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
inline void to_json(nlohmann::json& j, DataOrigin v) { j = std::string(to_string(v)); }
inline void from_json(const nlohmann::json& j, DataOrigin& v) {
  detail::enum_from_json(j, v, parse_data_origin, "DataOrigin");
}
inline void to_json(nlohmann::json& j, Verdict v) { j = std::string(to_string(v)); }
inline void from_json(const nlohmann::json& j, Verdict& v) {
  detail::enum_from_json(j, v, parse_verdict, "Verdict");
}
inline void to_json(nlohmann::json& j, MachineState v) { j = std::string(to_string(v)); }
inline void from_json(const nlohmann::json& j, MachineState& v) {
  detail::enum_from_json(j, v, parse_machine_state, "MachineState");
}

// The model's structs from their field lists (ncqual/common/model.hpp): every field under its name.
// A document missing a field is refused, naming the field (nlohmann's json::at), except a
// CheckRequest's and an S field (an optional, a field added with a wire contract, such as a set's
// origin): those read as their defaults when missing, so documents written before a field
// existed (state files, the historian's conflict documents) still load.
// Their arguments are a type and field names, which cannot be parenthesised.
// NOLINTBEGIN(bugprone-macro-parentheses)
#define NCQUAL_JSON_PUT(f) j[#f] = v.f;
#define NCQUAL_JSON_GET(f) j.at(#f).get_to(v.f);
#define NCQUAL_JSON_GET_OR_DEFAULT(f) \
  if (const auto it = j.find(#f); it != j.end()) it->get_to(v.f);
#define NCQUAL_JSON(Type, FIELDS, GET)                      \
  inline void to_json(nlohmann::json& j, const Type& v) {   \
    j = nlohmann::json::object();                           \
    FIELDS(NCQUAL_JSON_PUT, NCQUAL_JSON_PUT)                \
  }                                                         \
  inline void from_json(const nlohmann::json& j, Type& v) { \
    FIELDS(GET, NCQUAL_JSON_GET_OR_DEFAULT)                 \
  }
// NOLINTEND(bugprone-macro-parentheses)

NCQUAL_JSON(NamedValue, NCQUAL_FIELDS_NAMED_VALUE, NCQUAL_JSON_GET)
NCQUAL_JSON(Metric, NCQUAL_FIELDS_METRIC, NCQUAL_JSON_GET)
NCQUAL_JSON(Correction, NCQUAL_FIELDS_CORRECTION, NCQUAL_JSON_GET)
NCQUAL_JSON(CheckRequest, NCQUAL_FIELDS_CHECK_REQUEST, NCQUAL_JSON_GET_OR_DEFAULT)
// The other samples, as the historian keeps a conflicting one (storage: conflicts.document).
NCQUAL_JSON(AxisPosition, NCQUAL_FIELDS_AXIS_POSITION, NCQUAL_JSON_GET)
NCQUAL_JSON(Touch, NCQUAL_FIELDS_TOUCH, NCQUAL_JSON_GET)
NCQUAL_JSON(TrackerPoint, NCQUAL_FIELDS_TRACKER_POINT, NCQUAL_JSON_GET)
NCQUAL_JSON(MeasurementSet, NCQUAL_FIELDS_MEASUREMENT_SET, NCQUAL_JSON_GET)
NCQUAL_JSON(CheckResult, NCQUAL_FIELDS_CHECK_RESULT, NCQUAL_JSON_GET)
NCQUAL_JSON(MachineStatus, NCQUAL_FIELDS_MACHINE_STATUS, NCQUAL_JSON_GET)
NCQUAL_JSON(Intervention, NCQUAL_FIELDS_INTERVENTION, NCQUAL_JSON_GET)
NCQUAL_JSON(Compensation, NCQUAL_FIELDS_COMPENSATION, NCQUAL_JSON_GET)

#undef NCQUAL_JSON
#undef NCQUAL_JSON_GET_OR_DEFAULT
#undef NCQUAL_JSON_GET
#undef NCQUAL_JSON_PUT

}  // namespace ncqual
