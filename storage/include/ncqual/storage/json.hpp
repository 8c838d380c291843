// SPDX-License-Identifier: Apache-2.0
// The JSON of one check, for `ncqual history --json`, `ncqual check --json` and reports. The
// names are a public interface: append, never rename. Declared with nlohmann's macros over
// ncqual/common/json.hpp (enumerations by name, an absent part as null, a non-finite tolerance
// bound, i.e. a one-sided band, as null).
#pragma once

#include "ncqual/common/json.hpp"
#include "ncqual/storage/database.hpp"

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace ncqual::storage {

struct ParameterDocument {
  double value = 0;
  std::string unit;
};

struct MeasurementDocument {
  std::string instrument;
  std::int64_t touches = 0;         // measured, also once thinned
  std::int64_t tracker_points = 0;  // measured, also once thinned
  std::string error;                // empty unless the instrument could not perform the request
  // When retention deleted the set's points (ns since the epoch, UTC); null while stored.
  std::optional<std::int64_t> points_thinned_ns;
  // "measured", "simulated", or "unknown" (stored before schema 11, or a sample that did not say).
  DataOrigin origin = DataOrigin::Unknown;
};

// Who wrote a part of a check: the DataWriter's GUID; `ncqual history` adds the identity and
// subject on a secured plant (ncqual/dds/identity.hpp).
struct WriterDocument {
  std::string guid;
};

struct WritersDocument {
  std::optional<WriterDocument> request, measurement, result;  // null: not arrived or not known
};

struct CheckRecordDocument {
  std::string machine_id;
  std::string request_id;
  CheckKind kind = CheckKind::MonumentPositioning;
  // From the request; null (parameters: empty) until the request has arrived.
  std::optional<std::string> requested_by;
  std::optional<std::int64_t> requested_at_ns;
  std::map<std::string, ParameterDocument> parameters;
  std::optional<std::string> verifies_correction_of;  // null also when it verifies nothing
  // From the result; null (lists: empty) until the result has arrived.
  std::optional<std::int64_t> result_at_ns;
  std::optional<Verdict> verdict;
  std::optional<std::string> reason;
  std::optional<std::string> produced_by;
  std::vector<Metric> metrics;             // in the check's order
  std::vector<std::string> likely_causes;  // in the order to investigate them
  std::optional<Correction> correction;
  std::optional<MeasurementDocument> measurement;  // null until the measurement has arrived
  // Samples of this request kept beside these for conflicting content (0: none).
  std::int64_t conflicts = 0;
  WritersDocument writers;
  // Whether the check's numbers were measured or simulated (storage::origin_of): "measured",
  // "simulated", or "unknown" when neither its result nor its set says.
  DataOrigin origin = DataOrigin::Unknown;
};

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ParameterDocument, value, unit)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(MeasurementDocument, instrument, touches, tracker_points, error,
                                   points_thinned_ns, origin)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(WriterDocument, guid)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(WritersDocument, request, measurement, result)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CheckRecordDocument, machine_id, request_id, kind, requested_by,
                                   requested_at_ns, parameters, verifies_correction_of,
                                   result_at_ns, verdict, reason, produced_by, metrics,
                                   likely_causes, correction, measurement, conflicts, writers,
                                   origin)

CheckRecordDocument document_of(const CheckRecord& record);

nlohmann::json to_json(const CheckRecord& record);

// For nlohmann's implicit conversions: `nlohmann::json j = records;`.
void to_json(nlohmann::json& json, const CheckRecord& record);

}  // namespace ncqual::storage
