// SPDX-License-Identifier: Apache-2.0
// What the historian holds for a machine's error budget (`ncqual budget`, the report's budget
// section): the values of every metric a budget source names, newest first, in the metric's
// configured unit. The math is solver::evaluate_error_budget's.
#pragma once

#include "ncqual/common/calendar.hpp"
#include "ncqual/solver/error_budget.hpp"
#include "ncqual/storage/database.hpp"
#include "ncqual/storage/trend.hpp"

#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>

namespace ncqual::report {

struct BudgetHistory {
  solver::MetricHistories values;  // newest first, the budget metric's unit
  std::map<std::string, std::int64_t> newest_time_ns;
  // Each metric's newest stored value as its check judged it (value, band, pass; stored unit).
  std::map<std::string, storage::MetricValue> newest;
  int unconvertible = 0;  // values stored in a unit that cannot be turned into the metric's
};

// Every judged (PASS or FAIL) result of the machine, newest first, up to `until_ns` (result
// time; default: all).
BudgetHistory gather_budget_history(
    storage::Database& db, const std::string& machine_id, const solver::ErrorBudgetConfig& budget,
    std::int64_t until_ns = std::numeric_limits<std::int64_t>::max());

// The machine's standing for the budget's verdict (solver::judge_budget) as of `until_ns`: held
// when its newest status up to then is NEEDS_INTERVENTION; each budget metric whose newest value
// in `history` failed its check's tolerance.
// Its times are in `calendar`'s zone with the offset (UTC without one).
solver::BudgetMachineStanding budget_machine_standing(
    storage::Database& db, const std::string& machine_id, const BudgetHistory& history,
    std::int64_t until_ns = std::numeric_limits<std::int64_t>::max(),
    const Calendar* calendar = nullptr);

// Sets standing.held and held_why from the machine's newest status up to `until_ns` (the part of
// the standing that can change without a new result: an intervention).
void read_machine_hold(storage::Database& db, const std::string& machine_id, std::int64_t until_ns,
                       solver::BudgetMachineStanding& standing, const Calendar* calendar = nullptr);

// Factor turning a value in unit `from` into `to` when both are units of one dimension (length
// or angle); none otherwise. An empty `from` is taken as `to`.
std::optional<double> unit_factor(const std::string& from, const std::string& to);

}  // namespace ncqual::report
