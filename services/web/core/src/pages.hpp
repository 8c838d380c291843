// SPDX-License-Identifier: Apache-2.0
// The dashboard's HTML (pages.cpp): server-rendered pages, readable without script; a small inline
// script polls /api/v1/changes and re-fetches the page's <main> when the token moved. Private to
// ncqual_web.
#pragma once

#include "ncqual/web/dashboard.hpp"

#include "ncqual/status/plant_status.hpp"
#include "ncqual/storage/changes.hpp"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace ncqual::web {

inline constexpr const char* kHtmlType = "text/html; charset=utf-8";

using Failures = std::vector<std::pair<std::string, storage::FailureRecord>>;  // machine, check

struct PlantView {
  std::string token;
  plant_status::StatusDocument status;
  Failures failures;  // newest first, across machines, bounded
};

struct MachineView {
  std::string token;
  std::int64_t now_ns = 0;       // the machine's "now" (the simulated clock's on such plants)
  std::int64_t wall_now_ns = 0;  // the wall clock's
  plant_status::MachineDocument machine;
  Failures failures;
  std::vector<storage::CheckRecord> checks;  // newest first, bounded
  std::string report_sections;               // the report's HTML fragment
  std::string report_problem;                // why there are none, when there are none
  int days = 0;                              // the report's period: the last `days` days
};

std::string plant_html(const PlantConfig& plant, const Calendar& calendar, const PlantView& view,
                       const Limits& limits);
std::string machine_html(const PlantConfig& plant, const Calendar& calendar,
                         const MachineView& view, const Limits& limits);
std::string check_html(const PlantConfig& plant, const Calendar& calendar,
                       const storage::CheckRecord& check, const std::string& token,
                       const Limits& limits);
std::string error_page(const PlantConfig& plant, int status, const std::string& message);

// The machine report's sections (ncqual/report/machine_report.hpp) of `machine`'s checks since
// `since_ns`, as of `now_ns`, its times in the plant's zone (`calendar`, as the pages' own).
// std::invalid_argument when the historian has nothing of it.
std::string report_sections(storage::Database& db, const MachineConfig& machine,
                            const Calendar& calendar, std::int64_t since_ns, std::int64_t now_ns,
                            report::BudgetMemo* budgets = nullptr);

}  // namespace ncqual::web
