// SPDX-License-Identifier: Apache-2.0
#include "ncqual/storage_json.hpp"

namespace ncqual::storage {

nlohmann::json to_json(const CheckRecord& record) {
  using nlohmann::json;
  json out = json::object();
  out["machine_id"] = record.machine_id;
  out["request_id"] = record.request_id;
  out["kind"] = std::string(to_string(record.kind));

  const auto& request = record.request;
  out["requested_by"] = request ? json(request->requested_by) : json(nullptr);
  out["requested_at_ns"] = request ? json(request->time_ns) : json(nullptr);
  json parameters = json::object();
  if (request) {
    for (const NamedValue& p : request->parameters) {
      parameters[p.name] = {{"value", p.value}, {"unit", p.unit}};
    }
  }
  out["parameters"] = std::move(parameters);
  out["verifies_correction_of"] = request && !request->verifies_correction_of.empty()
                                      ? json(request->verifies_correction_of)
                                      : json(nullptr);

  const auto& result = record.result;
  out["result_at_ns"] = result ? json(result->time_ns) : json(nullptr);
  out["verdict"] = result ? json(std::string(to_string(result->verdict))) : json(nullptr);
  out["reason"] = result ? json(result->reason) : json(nullptr);
  out["produced_by"] = result ? json(result->produced_by) : json(nullptr);

  json metrics = json::array();
  json causes = json::array();
  json correction = nullptr;
  if (result) {
    for (const Metric& m : result->metrics) {
      // nlohmann writes a non-finite number as null: an infinite bound is a one-sided band.
      metrics.push_back({{"name", m.name},
                         {"value", m.value},
                         {"unit", m.unit},
                         {"lower", m.lower},
                         {"upper", m.upper},
                         {"pass", m.pass}});
    }
    for (const auto& cause : result->likely_causes) causes.push_back(cause);
    if (result->correction) {
      json offsets = json::array();
      for (const NamedValue& offset : result->correction->offsets) {
        offsets.push_back({{"name", offset.name}, {"value", offset.value}, {"unit", offset.unit}});
      }
      correction = {{"target", result->correction->target}, {"offsets", std::move(offsets)}};
    }
  }
  out["metrics"] = std::move(metrics);
  out["likely_causes"] = std::move(causes);
  out["correction"] = std::move(correction);

  if (record.measurement) {
    const MeasurementSummary& m = *record.measurement;
    out["measurement"] = {{"instrument", m.instrument},
                          {"touches", m.touches},
                          {"tracker_points", m.tracker_points},
                          {"error", m.error}};
  } else {
    out["measurement"] = nullptr;
  }
  return out;
}

void to_json(nlohmann::json& json, const CheckRecord& record) { json = to_json(record); }

}  // namespace ncqual::storage
