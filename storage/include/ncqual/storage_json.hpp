// SPDX-License-Identifier: Apache-2.0
// JSON for `ncqual history --json` and reports. The names are a public interface: append, never
// rename.
//
//   {"machine_id", "request_id", "kind": stable name (to_string), "requested_by" (null without a
//    request), "requested_at_ns" (null without a request), "result_at_ns" (null without a result),
//    "verdict": "PASS" | "FAIL" | "INVALID" | null without a result, "reason" (null without a
//    result), "metrics": [{"name", "value", "unit", "lower", "upper", "pass"}],
//    "likely_causes": [strings, in the order to investigate them],
//    "correction": {"target", "offsets": [{"name", "value", "unit"}]} | null,
//    "measurement": {"instrument", "touches", "tracker_points", "error"} | null}
//
// An infinite tolerance bound (a one-sided band) comes out as null: JSON has no infinity.
#pragma once

#include "ncqual/storage.hpp"

#include <nlohmann/json.hpp>

namespace ncqual::storage {

nlohmann::json to_json(const CheckRecord& record);

// For nlohmann's implicit conversions: `nlohmann::json j = records;`.
void to_json(nlohmann::json& json, const CheckRecord& record);

}  // namespace ncqual::storage
