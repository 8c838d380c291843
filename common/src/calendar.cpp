#include "ncqual/calendar.hpp"

#include "ncqual/config.hpp"

#include <date/tz.h>

#include <algorithm>
#include <limits>
#include <set>
#include <stdexcept>

namespace ncqual {

namespace {

using std::chrono::minutes;
using std::chrono::nanoseconds;
using std::chrono::seconds;
using LocalSeconds = date::local_time<seconds>;

constexpr int kSearchDays = 400;  // how far shift searches look: over a year of holidays

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  const std::int64_t q = a / b;
  return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}

const char* const kDayNames[7] = {"mon", "tue", "wed", "thu", "fri", "sat", "sun"};

int monday_index(date::local_days d) {
  return static_cast<int>((date::weekday(d).c_encoding() + 6) % 7);
}

}  // namespace

std::string_view to_string(PeriodUnit unit) {
  switch (unit) {
    case PeriodUnit::Shift: return "shift";
    case PeriodUnit::Day: return "day";
    case PeriodUnit::Week: return "week";
    case PeriodUnit::Month: return "month";
  }
  return "?";
}

CalendarConfig default_calendar_config() {
  CalendarConfig c;
  ShiftConfig early{"early", 6 * 60, 14 * 60, {true, true, true, true, true, false, false}};
  ShiftConfig late{"late", 14 * 60, 22 * 60, {true, true, true, true, true, false, false}};
  c.shifts = {early, late};
  c.periods = {
      {"monthly", PeriodUnit::Month, 1,
       {CheckKind::GlobalMasterFrame, CheckKind::GlobalGrid, CheckKind::RotaryW, CheckKind::RotaryA,
        CheckKind::RotaryC, CheckKind::CircleXY, CheckKind::CircleYZ, CheckKind::CircleXZ,
        CheckKind::LinearAxisRun}},
      {"weekly", PeriodUnit::Week, 1, {CheckKind::FixturePreCalibration}},
      {"daily", PeriodUnit::Day, 1,
       {CheckKind::MonumentCAlignment, CheckKind::MonumentToolLength,
        CheckKind::MonumentPositioning, CheckKind::MonumentCRotation}},
  };
  return c;
}

namespace {

using yaml::fail;

int parse_time_of_day(const YAML::Node& node, const std::string& key, const std::string& where) {
  if (!node.IsScalar()) fail(where, key, node, "expected a local time \"HH:MM\"");
  const std::string s = node.Scalar();
  int h = -1, m = -1;
  char colon = 0;
  if (s.size() == 5 && std::sscanf(s.c_str(), "%2d%c%2d", &h, &colon, &m) == 3 && colon == ':' &&
      h >= 0 && h <= 23 && m >= 0 && m <= 59) {
    return h * 60 + m;
  }
  fail(where, key, node, "expected a local time \"HH:MM\" from 00:00 to 23:59");
}

int parse_day(const std::string& name, const YAML::Node& node, const std::string& key,
              const std::string& where) {
  for (int d = 0; d < 7; ++d) {
    if (name == kDayNames[d]) return d;
  }
  fail(where, key, node, "'" + name + "' is not a day (mon, tue, wed, thu, fri, sat, sun)");
}

std::array<bool, 7> parse_days(const YAML::Node& node, const std::string& key,
                               const std::string& where) {
  std::array<bool, 7> days{};
  if (node.IsScalar()) {
    const std::string s = node.Scalar();
    if (s == "daily" || s == "all") {
      days.fill(true);
      return days;
    }
    const auto dash = s.find('-');
    if (dash == std::string::npos) {
      days[static_cast<std::size_t>(parse_day(s, node, key, where))] = true;
      return days;
    }
    const int from = parse_day(s.substr(0, dash), node, key, where);
    const int to = parse_day(s.substr(dash + 1), node, key, where);
    for (int d = from;; d = (d + 1) % 7) {
      days[static_cast<std::size_t>(d)] = true;
      if (d == to) break;
    }
    return days;
  }
  if (!node.IsSequence() || node.size() == 0) {
    fail(where, key, node, "expected days: a list such as [mon, tue] or a range \"mon-fri\"");
  }
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string k = key + "[" + std::to_string(i) + "]";
    if (!node[i].IsScalar()) fail(where, k, node[i], "expected a day name");
    days[static_cast<std::size_t>(parse_day(node[i].Scalar(), node[i], k, where))] = true;
  }
  return days;
}

std::vector<CheckKind> parse_kinds(const YAML::Node& node, const std::string& key,
                                   const std::string& where) {
  if (!node.IsSequence()) fail(where, key, node, "expected a list of check kinds");
  std::vector<CheckKind> kinds;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const auto kind = node[i].IsScalar() ? parse_check_kind(node[i].Scalar()) : std::nullopt;
    if (!kind) {
      fail(where, key + "[" + std::to_string(i) + "]", node[i],
           "not a check kind (e.g. monument_positioning)");
    }
    if (std::find(kinds.begin(), kinds.end(), *kind) != kinds.end()) {
      fail(where, key + "[" + std::to_string(i) + "]", node[i], "listed twice");
    }
    kinds.push_back(*kind);
  }
  return kinds;
}

PeriodUnit parse_unit(const YAML::Node& node, const std::string& key, const std::string& where) {
  if (node.IsScalar()) {
    for (PeriodUnit u : {PeriodUnit::Shift, PeriodUnit::Day, PeriodUnit::Week, PeriodUnit::Month}) {
      if (node.Scalar() == to_string(u)) return u;
    }
  }
  fail(where, key, node, "expected shift, day, week or month");
}

}  // namespace

CalendarConfig parse_calendar_config(const YAML::Node& node, const std::string& where) {
  const std::string p = "scheduler.calendar.";
  if (!node.IsMap()) fail(where, "scheduler.calendar", node, "expected a mapping");
  yaml::refuse_unknown_keys(node,
                            {"time_zone", "week_start", "shifts", "periods", "parts",
                             "check_timeout_min", "retries"},
                            p, where);
  CalendarConfig c = default_calendar_config();
  c.time_zone = yaml::string_or(node, "time_zone", c.time_zone, where);
  if (const YAML::Node w = node["week_start"]) {
    if (!w.IsScalar()) fail(where, p + "week_start", w, "expected a day name");
    c.week_start = parse_day(w.Scalar(), w, p + "week_start", where);
  }
  if (const YAML::Node shifts = node["shifts"]) {
    if (!shifts.IsSequence()) fail(where, p + "shifts", shifts, "expected a list of shifts");
    c.shifts.clear();
    std::set<std::string> names;
    for (std::size_t i = 0; i < shifts.size(); ++i) {
      const std::string k = p + "shifts[" + std::to_string(i) + "]";
      const YAML::Node s = shifts[i];
      if (!s.IsMap()) fail(where, k, s, "expected {name, start, end, days}");
      yaml::refuse_unknown_keys(s, {"name", "start", "end", "days"}, k + ".", where);
      ShiftConfig shift;
      shift.name = yaml::string_or(s, "name", "shift" + std::to_string(i + 1), where);
      if (!names.insert(shift.name).second) fail(where, k + ".name", s["name"], "used twice");
      if (!s["start"]) fail(where, k + ".start", s, "missing: the local start time \"HH:MM\"");
      if (!s["end"]) fail(where, k + ".end", s, "missing: the local end time \"HH:MM\"");
      shift.start_minute = parse_time_of_day(s["start"], k + ".start", where);
      shift.end_minute = parse_time_of_day(s["end"], k + ".end", where);
      shift.days = s["days"] ? parse_days(s["days"], k + ".days", where)
                             : std::array<bool, 7>{true, true, true, true, true, false, false};
      c.shifts.push_back(std::move(shift));
    }
  }
  if (const YAML::Node periods = node["periods"]) {
    if (!periods.IsSequence()) fail(where, p + "periods", periods, "expected a list of periods");
    c.periods.clear();
    std::set<CheckKind> seen;
    for (std::size_t i = 0; i < periods.size(); ++i) {
      const std::string k = p + "periods[" + std::to_string(i) + "]";
      const YAML::Node n = periods[i];
      if (!n.IsMap()) fail(where, k, n, "expected {name, every, checks}");
      yaml::refuse_unknown_keys(n, {"name", "every", "count", "checks"}, k + ".", where);
      PeriodConfig period;
      if (!n["every"]) fail(where, k + ".every", n, "missing: shift, day, week or month");
      if (!n["checks"]) fail(where, k + ".checks", n, "missing: the list of check kinds");
      period.unit = parse_unit(n["every"], k + ".every", where);
      period.name = yaml::string_or(n, "name", std::string(to_string(period.unit)), where);
      const double count = yaml::number_or(n, "count", 1, where);
      if (count < 1 || count > 1000 || count != static_cast<int>(count)) {
        fail(where, k + ".count", n["count"], "must be an integer from 1 to 1000");
      }
      period.every = static_cast<int>(count);
      if (period.unit == PeriodUnit::Shift && period.every != 1) {
        fail(where, k + ".count", n["count"], "a per-shift period cannot span several shifts");
      }
      period.checks = parse_kinds(n["checks"], k + ".checks", where);
      for (std::size_t j = 0; j < period.checks.size(); ++j) {
        const CheckKind kind = period.checks[j];
        if (kind == CheckKind::FixturePostCalibration || kind == CheckKind::PartSetPoints) {
          fail(where, k + ".checks[" + std::to_string(j) + "]", n["checks"][j],
               kind == CheckKind::PartSetPoints
                   ? "part checks run per part (scheduler.calendar.parts), not per period"
                   : "the post-calibration follows a failed pre-calibration; it is not scheduled");
        }
        if (!seen.insert(kind).second) {
          fail(where, k + ".checks[" + std::to_string(j) + "]", n["checks"][j],
               "already belongs to another period");
        }
      }
      c.periods.push_back(std::move(period));
    }
  }
  if (const YAML::Node parts = node["parts"]) {
    if (!parts.IsMap()) fail(where, p + "parts", parts, "expected {checks, cycle_min}");
    yaml::refuse_unknown_keys(parts, {"checks", "cycle_min"}, p + "parts.", where);
    if (parts["checks"]) c.parts.checks = parse_kinds(parts["checks"], p + "parts.checks", where);
    c.parts.cycle_min = yaml::number_or(parts, "cycle_min", c.parts.cycle_min, where);
    if (!(c.parts.cycle_min >= 0) || c.parts.cycle_min > 24 * 60) {
      fail(where, p + "parts.cycle_min", parts["cycle_min"], "must be from 0 to 1440 minutes");
    }
  }
  c.check_timeout_min = yaml::number_or(node, "check_timeout_min", c.check_timeout_min, where);
  if (!(c.check_timeout_min > 0) || c.check_timeout_min > 7 * 24 * 60) {
    fail(where, p + "check_timeout_min", node["check_timeout_min"], "must be > 0 and at most a week");
  }
  const double retries = yaml::number_or(node, "retries", c.retries, where);
  if (retries < 0 || retries > 10 || retries != static_cast<int>(retries)) {
    fail(where, p + "retries", node["retries"], "must be an integer from 0 to 10");
  }
  c.retries = static_cast<int>(retries);
  // The zone and the shifts are checked once more by Calendar, with the same message shape.
  try {
    (void)Calendar(c);
  } catch (const ConfigError& e) {
    throw ConfigError(where + ": " + e.what());
  }
  return c;
}

// ------------------------------------------------------------------------------------------------

Calendar::Calendar(CalendarConfig config) : config_(std::move(config)) {
  try {
    zone_ = date::locate_zone(config_.time_zone);
  } catch (const std::exception&) {
    throw ConfigError("scheduler.calendar.time_zone = '" + config_.time_zone +
                      "': not a time zone of the tz database (e.g. Europe/Berlin, "
                      "America/Chicago, UTC)");
  }
  if (config_.week_start < 0 || config_.week_start > 6) {
    throw ConfigError("scheduler.calendar.week_start = " + std::to_string(config_.week_start) +
                      ": must be 0 (Monday) to 6 (Sunday)");
  }
  for (std::size_t i = 0; i < config_.shifts.size(); ++i) {
    const ShiftConfig& s = config_.shifts[i];
    const std::string k = "scheduler.calendar.shifts[" + std::to_string(i) + "]";
    if (s.start_minute < 0 || s.start_minute >= 1440 || s.end_minute < 0 || s.end_minute >= 1440) {
      throw ConfigError(k + ": start/end minute out of 0..1439");
    }
    if (std::none_of(s.days.begin(), s.days.end(), [](bool b) { return b; })) {
      throw ConfigError(k + ".days: no day selected");
    }
  }
  for (std::size_t i = 0; i < config_.periods.size(); ++i) {
    if (config_.periods[i].every < 1) {
      throw ConfigError("scheduler.calendar.periods[" + std::to_string(i) +
                        "].count = " + std::to_string(config_.periods[i].every) + ": must be >= 1");
    }
  }
}

namespace {

// The UTC instant of a local time: the first occurrence when it is ambiguous, the end of the gap
// when it does not exist.
std::int64_t to_utc(const date::time_zone* zone, LocalSeconds local) {
  const date::local_info info = zone->get_info(local);
  date::sys_seconds sys;
  if (info.result == date::local_info::nonexistent) {
    sys = info.first.end;
  } else {
    sys = date::sys_seconds{local.time_since_epoch() - info.first.offset};
  }
  return std::chrono::duration_cast<nanoseconds>(sys.time_since_epoch()).count();
}

date::local_days local_day(const date::time_zone* zone, std::int64_t t_ns) {
  const date::sys_time<nanoseconds> sys{nanoseconds(t_ns)};
  return date::floor<date::days>(zone->to_local(sys));
}

std::optional<ShiftSlot> slot_on(const date::time_zone* zone, const ShiftConfig& s,
                                 date::local_days day) {
  if (!s.days[static_cast<std::size_t>(monday_index(day))]) return std::nullopt;
  const date::local_days end_day = s.end_minute <= s.start_minute ? day + date::days(1) : day;
  ShiftSlot slot{s.name, to_utc(zone, day + minutes(s.start_minute)),
                 to_utc(zone, end_day + minutes(s.end_minute))};
  if (slot.end_ns <= slot.start_ns) return std::nullopt;  // swallowed by a DST gap
  return slot;
}

}  // namespace

std::optional<ShiftSlot> Calendar::shift_at(std::int64_t t_ns) const {
  const date::local_days today = local_day(zone_, t_ns);
  std::optional<ShiftSlot> best;
  for (date::local_days d = today - date::days(1); d <= today; d += date::days(1)) {
    for (const auto& s : config_.shifts) {
      const auto slot = slot_on(zone_, s, d);
      if (slot && slot->start_ns <= t_ns && t_ns < slot->end_ns &&
          (!best || slot->start_ns < best->start_ns)) {
        best = slot;
      }
    }
  }
  return best;
}

std::optional<ShiftSlot> Calendar::next_shift_after(std::int64_t t_ns) const {
  const date::local_days today = local_day(zone_, t_ns);
  std::optional<ShiftSlot> best;
  for (int i = -1; i <= kSearchDays; ++i) {
    const date::local_days d = today + date::days(i);
    for (const auto& s : config_.shifts) {
      const auto slot = slot_on(zone_, s, d);
      if (slot && slot->start_ns > t_ns && (!best || slot->start_ns < best->start_ns)) best = slot;
    }
    // Starts grow with the day (by at least a day minus a DST hour): one more day settles it.
    if (best && local_day(zone_, best->start_ns) < d) break;
  }
  return best;
}

namespace {

// Start day of period number `index` (counted from 1970 in units of the period's unit).
date::local_days period_day(PeriodUnit unit, int week_start, std::int64_t index) {
  switch (unit) {
    case PeriodUnit::Day: return date::local_days{date::days(index)};
    case PeriodUnit::Week: {
      const std::int64_t anchor = (week_start - 3 + 7) % 7;  // 1970-01-01 was a Thursday
      return date::local_days{date::days(anchor + 7 * index)};
    }
    case PeriodUnit::Month: {
      const std::int64_t y = 1970 + floor_div(index, 12);
      const auto m = static_cast<unsigned>(index - floor_div(index, 12) * 12 + 1);
      return date::local_days{date::year(static_cast<int>(y)) / date::month(m) / 1};
    }
    case PeriodUnit::Shift: break;
  }
  throw std::logic_error("period_day: shift periods have no day");
}

std::int64_t period_index(PeriodUnit unit, int week_start, date::local_days day) {
  const std::int64_t n = day.time_since_epoch().count();
  switch (unit) {
    case PeriodUnit::Day: return n;
    case PeriodUnit::Week: return floor_div(n - (week_start - 3 + 7) % 7, 7);
    case PeriodUnit::Month: {
      const date::year_month_day ymd{day};
      return (static_cast<int>(ymd.year()) - 1970) * 12 +
             static_cast<int>(static_cast<unsigned>(ymd.month())) - 1;
    }
    case PeriodUnit::Shift: break;
  }
  throw std::logic_error("period_index: shift periods have no index");
}

}  // namespace

std::int64_t Calendar::period_start(const PeriodConfig& period, std::int64_t t_ns) const {
  if (period.unit == PeriodUnit::Shift) {
    if (const auto now = shift_at(t_ns)) return now->start_ns;
    // The newest shift that started before t: search back day by day.
    const date::local_days today = local_day(zone_, t_ns);
    std::optional<std::int64_t> best;
    for (int i = 0; i <= kSearchDays && !best; ++i) {
      for (const auto& s : config_.shifts) {
        const auto slot = slot_on(zone_, s, today - date::days(i));
        if (slot && slot->start_ns <= t_ns && (!best || slot->start_ns > *best)) best = slot->start_ns;
      }
    }
    return best.value_or(std::numeric_limits<std::int64_t>::min());
  }
  const std::int64_t index = period_index(period.unit, config_.week_start, local_day(zone_, t_ns));
  const std::int64_t aligned = floor_div(index, period.every) * period.every;
  return to_utc(zone_, LocalSeconds{period_day(period.unit, config_.week_start, aligned)});
}

std::int64_t Calendar::next_period_start(const PeriodConfig& period, std::int64_t t_ns) const {
  if (period.unit == PeriodUnit::Shift) {
    const auto next = next_shift_after(t_ns);
    return next ? next->start_ns : std::numeric_limits<std::int64_t>::max();
  }
  const std::int64_t index = period_index(period.unit, config_.week_start, local_day(zone_, t_ns));
  const std::int64_t aligned = floor_div(index, period.every) * period.every + period.every;
  return to_utc(zone_, LocalSeconds{period_day(period.unit, config_.week_start, aligned)});
}

bool Calendar::due(const PeriodConfig& period, std::optional<std::int64_t> last_pass_ns,
                   std::int64_t t_ns) const {
  return !last_pass_ns || *last_pass_ns < period_start(period, t_ns);
}

bool Calendar::overdue(const PeriodConfig& period, std::optional<std::int64_t> last_pass_ns,
                       std::int64_t t_ns) const {
  if (!due(period, last_pass_ns, t_ns)) return false;
  const std::int64_t start = period_start(period, t_ns);
  if (start == std::numeric_limits<std::int64_t>::min()) return false;
  const auto first = next_shift_after(start - 1);
  return first && first->start_ns <= t_ns;
}

std::int64_t Calendar::next_due(const PeriodConfig& period, std::optional<std::int64_t> last_pass_ns,
                                std::int64_t t_ns) const {
  return due(period, last_pass_ns, t_ns) ? t_ns : next_period_start(period, t_ns);
}

std::string Calendar::local_text(std::int64_t t_ns) const {
  const date::sys_time<std::chrono::minutes> sys =
      date::floor<std::chrono::minutes>(date::sys_time<nanoseconds>{nanoseconds(t_ns)});
  return date::format("%F %R %Z", date::make_zoned(zone_, sys));
}

std::int64_t Calendar::utc_ns(int year, int month, int day, int hour, int minute) const {
  const date::year_month_day ymd{date::year(year), date::month(static_cast<unsigned>(month)),
                                 date::day(static_cast<unsigned>(day))};
  if (!ymd.ok()) {
    throw std::invalid_argument("date " + std::to_string(year) + "-" + std::to_string(month) + "-" +
                                std::to_string(day) + " does not exist");
  }
  return to_utc(zone_, date::local_days{ymd} + std::chrono::hours(hour) + minutes(minute));
}

}  // namespace ncqual
