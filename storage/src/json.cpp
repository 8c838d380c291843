// SPDX-License-Identifier: Apache-2.0
#include "ncqual/storage/json.hpp"

namespace ncqual::storage {

CheckRecordDocument document_of(const CheckRecord& record) {
  CheckRecordDocument d;
  d.machine_id = record.machine_id;
  d.request_id = record.request_id;
  d.kind = record.kind;
  if (const auto& request = record.request) {
    d.requested_by = request->requested_by;
    d.requested_at_ns = request->time_ns;
    for (const NamedValue& p : request->parameters) d.parameters[p.name] = {p.value, p.unit};
    if (!request->verifies_correction_of.empty()) {
      d.verifies_correction_of = request->verifies_correction_of;
    }
  }
  if (const auto& result = record.result) {
    d.result_at_ns = result->time_ns;
    d.verdict = result->verdict;
    d.reason = result->reason;
    d.produced_by = result->produced_by;
    d.metrics = result->metrics;
    d.likely_causes = result->likely_causes;
    d.correction = result->correction;
  }
  if (const auto& m = record.measurement) {
    d.measurement = MeasurementDocument{m->instrument, m->touches,           m->tracker_points,
                                        m->error,      m->points_thinned_ns, m->origin};
  }
  d.conflicts = record.conflicts;
  d.origin = origin_of(record);
  const auto writer = [](const std::string& guid) {
    return guid.empty() ? std::nullopt : std::optional<WriterDocument>(WriterDocument{guid});
  };
  d.writers = {writer(record.writers.request), writer(record.writers.measurement),
               writer(record.writers.result)};
  return d;
}

nlohmann::json to_json(const CheckRecord& record) { return document_of(record); }

void to_json(nlohmann::json& json, const CheckRecord& record) { json = to_json(record); }

}  // namespace ncqual::storage
