// SPDX-License-Identifier: Apache-2.0
// The `scheduler.calendar:` section of a plant config (ncqual/common/calendar.hpp).
#include "node.hpp"

#include <algorithm>
#include <cstdio>
#include <set>

namespace ncqual::config {
namespace {

const char* const kDayNames[7] = {"mon", "tue", "wed", "thu", "fri", "sat", "sun"};

std::optional<int> time_of_day(const Node& node) {
  const std::string s = node.scalar();
  int h = -1, m = -1;
  char colon = 0;
  if (s.size() == 5 && std::sscanf(s.c_str(), "%2d%c%2d", &h, &colon, &m) == 3 && colon == ':' &&
      h >= 0 && h <= 23 && m >= 0 && m <= 59) {
    return h * 60 + m;
  }
  node.problem("expected a local time \"HH:MM\" from 00:00 to 23:59");
  return std::nullopt;
}

std::optional<int> day(const std::string& name, const Node& node) {
  for (int d = 0; d < 7; ++d) {
    if (name == kDayNames[d]) return d;
  }
  node.problem("'" + name + "' is not a day (mon, tue, wed, thu, fri, sat, sun)");
  return std::nullopt;
}

std::array<bool, 7> days(const Node& node) {
  std::array<bool, 7> days{};
  if (node.is_scalar()) {
    const std::string s = node.scalar();
    if (s == "daily" || s == "all") {
      days.fill(true);
      return days;
    }
    const auto dash = s.find('-');
    if (dash == std::string::npos) {
      if (const auto d = day(s, node)) days[static_cast<std::size_t>(*d)] = true;
      return days;
    }
    const auto from = day(s.substr(0, dash), node), to = day(s.substr(dash + 1), node);
    if (!from || !to) return days;
    for (int d = *from;; d = (d + 1) % 7) {
      days[static_cast<std::size_t>(d)] = true;
      if (d == *to) break;
    }
    return days;
  }
  if (!node.is_list() || node.size() == 0) {
    node.problem("expected days: a list such as [mon, tue] or a range \"mon-fri\"");
    return days;
  }
  for (const Node& item : node.items()) {
    if (!item.is_scalar()) {
      item.problem("expected a day name");
    } else if (const auto d = day(item.scalar(), item)) {
      days[static_cast<std::size_t>(*d)] = true;
    }
  }
  return days;
}

std::vector<CheckKind> kinds(const Node& node) {
  std::vector<CheckKind> out;
  if (!node.is_list()) {
    node.problem("expected a list of check kinds");
    return out;
  }
  for (const Node& item : node.items()) {
    const auto kind = item.is_scalar() ? parse_check_kind(item.scalar()) : std::nullopt;
    if (!kind) {
      item.problem("not a check kind (e.g. monument_positioning)");
    } else if (std::find(out.begin(), out.end(), *kind) != out.end()) {
      item.problem("listed twice");
    } else {
      out.push_back(*kind);
    }
  }
  return out;
}

std::optional<PeriodUnit> unit(const Node& node) {
  for (PeriodUnit u : {PeriodUnit::Shift, PeriodUnit::Day, PeriodUnit::Week, PeriodUnit::Month}) {
    if (node.scalar() == to_string(u)) return u;
  }
  node.problem("expected shift, day, week or month");
  return std::nullopt;
}

}  // namespace

CalendarConfig read_calendar(const Node& node) {
  CalendarConfig c = default_calendar_config();
  const std::size_t problems_before = node.diagnostics().count();
  if (!node.map_of({"time_zone", "week_start", "shifts", "periods", "parts", "check_timeout_min",
                    "retries"})) {
    return c;
  }
  c.time_zone = node["time_zone"].text(c.time_zone);
  if (const Node w = node["week_start"]; w.present()) {
    if (!w.is_scalar()) {
      w.problem("expected a day name");
    } else {
      c.week_start = day(w.scalar(), w).value_or(c.week_start);
    }
  }
  if (const Node shifts = node["shifts"]; shifts.present()) {
    if (!shifts.is_list()) shifts.problem("expected a list of shifts");
    c.shifts.clear();
    std::set<std::string> names;
    for (std::size_t i = 0; i < shifts.size(); ++i) {
      const Node s = shifts[i];
      if (!s.is_map()) {
        s.problem("expected {name, start, end, days}");
        continue;
      }
      s.map_of({"name", "start", "end", "days"});
      ShiftConfig shift;
      shift.name = s["name"].text("shift" + std::to_string(i + 1));
      if (!names.insert(shift.name).second) s["name"].problem("used twice");
      if (!s["start"].present()) s["start"].problem("missing: the local start time \"HH:MM\"");
      if (!s["end"].present()) s["end"].problem("missing: the local end time \"HH:MM\"");
      shift.start_minute = s["start"].present() ? time_of_day(s["start"]).value_or(0) : 0;
      shift.end_minute = s["end"].present() ? time_of_day(s["end"]).value_or(0) : 0;
      shift.days = s["days"].present()
                       ? days(s["days"])
                       : std::array<bool, 7>{true, true, true, true, true, false, false};
      c.shifts.push_back(std::move(shift));
    }
  }
  if (const Node periods = node["periods"]; periods.present()) {
    if (!periods.is_list()) periods.problem("expected a list of periods");
    c.periods.clear();
    std::set<CheckKind> seen;
    for (const Node& n : periods.items()) {
      if (!n.is_map()) {
        n.problem("expected {name, every, checks}");
        continue;
      }
      n.map_of({"name", "every", "count", "checks"});
      PeriodConfig period;
      if (!n["every"].present()) n["every"].problem("missing: shift, day, week or month");
      if (!n["checks"].present()) n["checks"].problem("missing: the list of check kinds");
      if (n["every"].present()) period.unit = unit(n["every"]).value_or(period.unit);
      period.name = n["name"].text(std::string(to_string(period.unit)));
      period.every = n["count"].integer(1, 1000, 1);
      if (period.unit == PeriodUnit::Shift && period.every != 1) {
        n["count"].problem("a per-shift period cannot span several shifts");
      }
      if (n["checks"].present()) period.checks = kinds(n["checks"]);
      for (std::size_t j = 0; j < period.checks.size(); ++j) {
        const CheckKind kind = period.checks[j];
        const Node item = n["checks"][j];
        if (kind == CheckKind::FixturePostCalibration || kind == CheckKind::PartSetPoints) {
          item.problem(kind == CheckKind::PartSetPoints
                           ? "part checks run per part (scheduler.calendar.parts), not per period"
                           : "the post-calibration follows a failed pre-calibration; it is not "
                             "scheduled");
        }
        if (!seen.insert(kind).second) item.problem("already belongs to another period");
      }
      c.periods.push_back(std::move(period));
    }
  }
  if (const Node parts = node["parts"]; parts.present()) {
    if (!parts.is_map()) {
      parts.problem("expected {checks, cycle_min}");
    } else {
      parts.map_of({"checks", "cycle_min"});
      if (parts["checks"].present()) c.parts.checks = kinds(parts["checks"]);
      c.parts.cycle_min = parts["cycle_min"].number(c.parts.cycle_min);
      if (!(c.parts.cycle_min >= 0) || c.parts.cycle_min > 24 * 60) {
        parts["cycle_min"].problem("must be from 0 to 1440 minutes");
      }
    }
  }
  c.check_timeout_min = node["check_timeout_min"].number(c.check_timeout_min);
  if (!(c.check_timeout_min > 0) || c.check_timeout_min > 7 * 24 * 60) {
    node["check_timeout_min"].problem("must be > 0 and at most a week");
  }
  c.retries = node["retries"].integer(0, 10, c.retries);
  // The zone and the shifts are checked once more by Calendar, with the same message shape.
  if (node.diagnostics().count() == problems_before) {
    try {
      (void)Calendar(c);
    } catch (const ConfigError& e) {
      node.diagnostics().file_problem(node.file(), e.what());
    }
  }
  return c;
}

}  // namespace ncqual::config
