// SPDX-License-Identifier: Apache-2.0
// The plant's calendar: shifts in the plant's time zone, the periods of the qualification process
// (which checks belong to each, in the order they run at the start of a shift), and when a
// period's checks are due or overdue. Pure functions of (config, last pass, time): the scheduler
// decides with them, and `ncqual status` shows the same answers from the historian.
//
// Times are nanoseconds since the Unix epoch (UTC); the calendar is read in the plant's IANA time
// zone (the OS tz database, e.g. "Europe/Berlin"), so shifts follow the wall clock across DST:
//   - a shift starting at a local time that does not exist (spring forward, 02:30 on a day the
//     clocks jump from 02:00 to 03:00) starts at the first instant after the gap (03:00);
//   - a local time that occurs twice (fall back) means its first occurrence;
//   - a shift whose end is not after its start (22:00-06:00) ends on the next day; `days` name the
//     day it starts.
// A period starts at local midnight of its day, of the week's first day (week_start) or of the
// month's first day; `every: n` groups n consecutive periods counted from 1970 (days from
// 1970-01-01, weeks from the first week_start day of 1970, months from January 1970).
//
// Due and overdue (a check's "last pass" is the time of its newest PASS):
//   due(t)     no pass since the start of the period containing t;
//   overdue(t) due, and a shift of that period has already started by t: the machine had its
//              chance to run the check and did not (it failed, the scheduler was down, the shift
//              was missed). Between a period's start and its first shift a check is due but not
//              overdue, so a machine stays QUALIFIED overnight.
#pragma once

#include "ncqual/common/model.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace date {
class time_zone;
}

namespace ncqual {

enum class PeriodUnit { Shift, Day, Week, Month };

std::string_view to_string(PeriodUnit unit);

struct ShiftConfig {
  std::string name;
  int start_minute = 0;        // local time of day, minutes after midnight (0..1439)
  int end_minute = 0;          // <= start_minute: the shift ends on the next day
  std::array<bool, 7> days{};  // the day it starts, [0] = Monday .. [6] = Sunday
};

struct PeriodConfig {
  std::string name;  // e.g. "monthly"
  PeriodUnit unit = PeriodUnit::Day;
  int every = 1;                  // >= 1
  std::vector<CheckKind> checks;  // run in this order
};

// Parts: after the period checks pass, the machine works parts until the end of the shift. Each
// part starts with `checks` (the set points); the next part's checks follow `cycle_min` after the
// part's checks passed (machining and unloading). cycle_min = 0: no part loop from the calendar;
// part checks come only as operator orders (`ncqual check`).
struct PartLoopConfig {
  std::vector<CheckKind> checks{CheckKind::PartSetPoints};
  double cycle_min = 0;
};

struct CalendarConfig {
  std::string time_zone = "UTC";
  int week_start = 0;  // 0 = Monday .. 6 = Sunday
  std::vector<ShiftConfig> shifts;
  std::vector<PeriodConfig> periods;  // in the order their checks run at the start of a shift
  PartLoopConfig parts;
  // A check that gets no result within this time is issued again (a new request id), at most
  // `retries` more times; then it is reported and holds the machine.
  double check_timeout_min = 120;
  int retries = 2;
};

// The process of docs/architecture.md: monthly tracker checks (master frame, grid, W, A, C, the
// three circles, the ISO 230-2 run), the weekly fixture pre-calibration, the daily monument
// checks 1 -> 4, in that order; two shifts Monday to Friday, 06:00-14:00 and 14:00-22:00, UTC.
CalendarConfig default_calendar_config();

// The plant config's `scheduler.calendar:` (read by the configuration layer,
// common/src/config/calendar_section.cpp): time_zone, week_start, shifts [{name, start "HH:MM",
// end, days: [mon, ...] or "mon-fri"}], periods [{name, every: shift|day|week|month, count,
// checks}], parts {checks, cycle_min}, check_timeout_min, retries. Omitted keys take the defaults
// above; an unknown time zone is refused with the rest.

struct ShiftSlot {
  std::string name;
  std::int64_t start_ns = 0;
  std::int64_t end_ns = 0;
};

class Calendar {
 public:
  // Throws ConfigError when the time zone is not in the tz database or a shift or period is
  // malformed (names the field and the value).
  explicit Calendar(CalendarConfig config);

  const CalendarConfig& config() const { return config_; }

  // The shift in progress at t (start <= t < end); the earliest-starting one if shifts overlap.
  std::optional<ShiftSlot> shift_at(std::int64_t t_ns) const;
  // The first shift that starts after t (strictly); none when no shift is configured.
  std::optional<ShiftSlot> next_shift_after(std::int64_t t_ns) const;
  // Start of the period (of `period`) that contains t. For PeriodUnit::Shift: the start of the
  // newest shift that started at or before t (the epoch when there is none).
  std::int64_t period_start(const PeriodConfig& period, std::int64_t t_ns) const;
  // Start of the period after the one containing t (for Shift: the next shift's start).
  std::int64_t next_period_start(const PeriodConfig& period, std::int64_t t_ns) const;

  bool due(const PeriodConfig& period, std::optional<std::int64_t> last_pass_ns,
           std::int64_t t_ns) const;
  bool overdue(const PeriodConfig& period, std::optional<std::int64_t> last_pass_ns,
               std::int64_t t_ns) const;
  // When the check falls due next: now (t) when it is due, else the next period's start.
  std::int64_t next_due(const PeriodConfig& period, std::optional<std::int64_t> last_pass_ns,
                        std::int64_t t_ns) const;

  // "2026-03-29 06:00 +02:00 CEST": t in the plant's zone with its offset from UTC, to the
  // minute, or to the second ("2026-03-29 06:00:07 +02:00 CEST") with `seconds`. Every time a
  // person reads (status, history, trend, the scheduler's log) is written this way.
  std::string local_text(std::int64_t t_ns, bool seconds = false) const;
  // The plant's time zone ("Europe/Berlin").
  const std::string& zone_name() const { return config_.time_zone; }
  // The UTC instant of a local date and time in the plant's zone (DST rules as above).
  std::int64_t utc_ns(int year, int month, int day, int hour, int minute) const;
  // A date or time a person typed (the command line's --since, --until, --before), read in the
  // plant's zone: "2027-01-15" is that day's local midnight, "2027-01-15T06:00[:SS[.fff]]" (or
  // with a space for the T) a local time (DST rules as above); a time with "Z" or an offset
  // ("2027-01-15T06:00Z", "2027-01-15T06:00+01:00") means what it says. Nothing when the text is
  // none of these.
  std::optional<std::int64_t> parse_time(std::string_view text) const;
  // The plant's wall clock at t, as ns since the epoch read as if it were UTC (a chart's local
  // days are whole days of it), and back: the instant of a wall-clock time (DST rules as above).
  std::int64_t wall_ns(std::int64_t t_ns) const;
  std::int64_t from_wall_ns(std::int64_t wall_ns) const;

 private:
  CalendarConfig config_;
  const date::time_zone* zone_ = nullptr;
};

}  // namespace ncqual
