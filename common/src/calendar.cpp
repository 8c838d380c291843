// SPDX-License-Identifier: Apache-2.0
#include "ncqual/common/calendar.hpp"

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/clock.hpp"
#include "ncqual/common/config.hpp"

#include <date/tz.h>

#include <algorithm>
#include <cctype>
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
  // Each period takes the kinds of its cadence from the table, in the table's order.
  c.periods = {{"monthly", PeriodUnit::Month, 1, {}},
               {"weekly", PeriodUnit::Week, 1, {}},
               {"daily", PeriodUnit::Day, 1, {}}};
  for (const auto& row : check_kinds()) {
    const int period = row.cadence == Cadence::Monthly  ? 0
                       : row.cadence == Cadence::Weekly ? 1
                       : row.cadence == Cadence::Daily  ? 2
                                                        : -1;
    if (period >= 0) c.periods[static_cast<std::size_t>(period)].checks.push_back(row.kind);
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
        if (slot && slot->start_ns <= t_ns && (!best || slot->start_ns > *best))
          best = slot->start_ns;
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

std::int64_t Calendar::next_due(const PeriodConfig& period,
                                std::optional<std::int64_t> last_pass_ns, std::int64_t t_ns) const {
  return due(period, last_pass_ns, t_ns) ? t_ns : next_period_start(period, t_ns);
}

std::string Calendar::local_text(std::int64_t t_ns, bool seconds) const {
  const date::sys_time<nanoseconds> t{nanoseconds(t_ns)};
  if (seconds) {
    return date::format("%F %T %Ez %Z",
                        date::make_zoned(zone_, date::floor<std::chrono::seconds>(t)));
  }
  return date::format("%F %R %Ez %Z",
                      date::make_zoned(zone_, date::floor<std::chrono::minutes>(t)));
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

std::optional<std::int64_t> Calendar::parse_time(std::string_view text) const {
  std::string s(text);
  if (s.size() == 10 && s[4] == '-' && s[7] == '-') s += "T00:00";  // a date: its local midnight
  if (!s.empty() && s.back() == 'Z') return parse_iso8601(s);
  constexpr std::int64_t kMinuteNs = 60LL * 1000000000LL;
  // An explicit offset, +HH:MM or -HH:MM after the time (the date's own '-' come before it).
  if (s.size() >= 16 + 6 && (s[s.size() - 6] == '+' || s[s.size() - 6] == '-') &&
      s[s.size() - 3] == ':') {
    const auto digit = [&](std::size_t i) {
      return std::isdigit(static_cast<unsigned char>(s[i])) ? s[i] - '0' : -100;
    };
    const std::size_t k = s.size() - 5;
    const int hours = digit(k) * 10 + digit(k + 1);
    const int mins = digit(k + 3) * 10 + digit(k + 4);
    if (hours < 0 || hours > 23 || mins < 0 || mins > 59) return std::nullopt;
    const auto wall = parse_iso8601(s.substr(0, s.size() - 6) + "Z");
    if (!wall) return std::nullopt;
    const std::int64_t offset_ns = (hours * 60 + mins) * kMinuteNs;
    return s[s.size() - 6] == '+' ? *wall - offset_ns : *wall + offset_ns;
  }
  // A wall-clock time of the plant: read as if UTC, then placed in the zone.
  const auto wall = parse_iso8601(s + "Z");
  if (!wall) return std::nullopt;
  return from_wall_ns(*wall);
}

std::int64_t Calendar::wall_ns(std::int64_t t_ns) const {
  const date::sys_time<nanoseconds> sys{nanoseconds(t_ns)};
  return zone_->to_local(sys).time_since_epoch().count();
}

std::int64_t Calendar::from_wall_ns(std::int64_t wall_ns) const {
  // To the minute through the zone's rules (offsets are whole minutes), the rest added back.
  constexpr std::int64_t kMinuteNs = 60LL * 1000000000LL;
  const std::int64_t minute = floor_div(wall_ns, kMinuteNs);
  const LocalSeconds local{std::chrono::duration_cast<seconds>(minutes(minute))};
  return to_utc(zone_, local) + (wall_ns - minute * kMinuteNs);
}

}  // namespace ncqual
