// SPDX-License-Identifier: Apache-2.0
// Trend warnings in words and as the historian keeps them (docs/trends.md, "Warnings"): the one
// sentence each warning carries, the records an assessment's active warnings become, and the
// TrendWarning sample of a change. Pure functions.
#pragma once

#include "ncqual/common/model.hpp"
#include "ncqual/storage/trend.hpp"
#include "ncqual/trend/assess.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace ncqual::report {

// The one sentence a warning carries, with its figures in the metric's unit (values with the
// decimals its tolerance band calls for, dates in UTC).
std::string warning_text(const trend::Warning& warning, const trend::Assessment& assessment,
                         const std::string& metric, const std::string& unit,
                         const trend::Band& band);

// The warnings an assessment has active, as the storage keeps them (raised_by, raised_ns and the
// end are the storage's to fill).
std::vector<storage::TrendWarningRecord> active_records(
    const trend::Assessment& assessment, const std::string& machine_id, const std::string& metric,
    CheckKind check_kind, const std::string& unit, const trend::Band& band);

// A change as the TrendWarning sample that announces it (`at_ns`: its time).
TrendWarning to_sample(const storage::TrendWarningRecord& record, std::int64_t at_ns);

}  // namespace ncqual::report
