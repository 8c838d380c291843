// SPDX-License-Identifier: Apache-2.0
// Checks a sample before anything of it is written. Throws StorageError whose message names the
// field and the value ("CheckResult.request_id is empty", "Metric.value of 'center_dx_mm' is
// NaN (CheckResult 'r-17')").
#pragma once

#include "ncqual/common/model.hpp"

namespace ncqual::storage::validate {

void check(const CheckRequest& request);
void check(const MeasurementSet& measurement_set);
void check(const CheckResult& result);
void check(const MachineStatus& status);
void check(const Intervention& intervention);
void check(const Compensation& compensation);
void check(const Heartbeat& heartbeat);

bool is_check_kind(CheckKind value);

}  // namespace ncqual::storage::validate
