// SPDX-License-Identifier: Apache-2.0
// The plant calendar: shifts in a time zone across DST, periods across month and year ends,
// due and overdue, and the calendar's config section. Expected instants are worked by hand from
// the zones' offsets (Europe/Berlin: CET = UTC+1, CEST = UTC+2 from the last Sunday of March
// 01:00 UTC to the last Sunday of October 01:00 UTC; America/Chicago: CST = UTC-6, CDT = UTC-5
// from the second Sunday of March 08:00 UTC to the first Sunday of November 07:00 UTC).
#include "ncqual/common/calendar.hpp"
#include "ncqual/common/clock.hpp"
#include "ncqual/common/config.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace ncqual {
namespace {

constexpr std::int64_t kMinute = 60'000'000'000LL;
constexpr std::int64_t kHour = 60 * kMinute;

std::int64_t utc(const char* text) {
  const auto t = parse_iso8601(text);
  EXPECT_TRUE(t.has_value()) << text;
  return t.value_or(0);
}

ShiftConfig shift(const char* name, int start_h, int start_m, int end_h, int end_m,
                  std::array<bool, 7> days = {true, true, true, true, true, true, true}) {
  return ShiftConfig{name, start_h * 60 + start_m, end_h * 60 + end_m, days};
}

CalendarConfig zone_config(const char* zone, std::vector<ShiftConfig> shifts) {
  CalendarConfig c = default_calendar_config();
  c.time_zone = zone;
  c.shifts = std::move(shifts);
  return c;
}

const PeriodConfig& period(const Calendar& cal, const std::string& name) {
  for (const auto& p : cal.config().periods) {
    if (p.name == name) return p;
  }
  throw std::runtime_error("no period " + name);
}

TEST(Iso8601, ParsesWhatFormatWritesAndRefusesTheRest) {
  const std::int64_t t = utc("2026-03-29T01:30:15.250Z");
  char buffer[32];
  EXPECT_EQ(format_iso8601(t, buffer), "2026-03-29T01:30:15.250Z");
  EXPECT_EQ(utc("2026-03-29 01:30Z"), t - 15'250'000'000LL);
  EXPECT_EQ(utc("1970-01-01T00:00:00Z"), 0);
  EXPECT_EQ(utc("2261-12-31T23:59:59Z"), 9'214'646'399'000'000'000LL);
  for (const char* bad : {"2026-02-30T00:00Z", "2026-03-29T24:00Z", "2026-03-29T01:30", "yesterday",
                          "2026-03-29T01:30:61Z", "2026-3-29T01:30Z", "2026-03-29T01:30Zx",
                          "2262-06-01T00:00Z", "1600-01-01T00:00Z"}) {
    EXPECT_FALSE(parse_iso8601(bad).has_value()) << bad;
  }
}

TEST(Calendar, NightShiftIsAnHourShorterWhenTheClocksSpringForward) {
  const Calendar cal(zone_config("Europe/Berlin", {shift("night", 22, 0, 6, 0)}));
  // Saturday 28 March 2026 22:00 CET = 21:00Z; Sunday 06:00 CEST = 04:00Z: 7 h.
  const auto s = cal.shift_at(utc("2026-03-29T00:30:00Z"));
  ASSERT_TRUE(s);
  EXPECT_EQ(s->start_ns, utc("2026-03-28T21:00:00Z"));
  EXPECT_EQ(s->end_ns, utc("2026-03-29T04:00:00Z"));
  EXPECT_EQ(s->end_ns - s->start_ns, 7 * kHour);
  // The week before: 8 h; the night of 24 October (fall back): 9 h.
  const auto before = cal.shift_at(utc("2026-03-22T00:30:00Z"));
  ASSERT_TRUE(before);
  EXPECT_EQ(before->end_ns - before->start_ns, 8 * kHour);
  const auto fall = cal.shift_at(utc("2026-10-25T01:30:00Z"));
  ASSERT_TRUE(fall);
  EXPECT_EQ(fall->start_ns, utc("2026-10-24T20:00:00Z"));
  EXPECT_EQ(fall->end_ns, utc("2026-10-25T05:00:00Z"));
  EXPECT_EQ(fall->end_ns - fall->start_ns, 9 * kHour);
  EXPECT_EQ(cal.local_text(fall->end_ns), "2026-10-25 06:00 +01:00 CET");
  EXPECT_EQ(cal.local_text(s->end_ns), "2026-03-29 06:00 +02:00 CEST");
  EXPECT_EQ(cal.local_text(s->end_ns + 7'400'000'000, true), "2026-03-29 06:00:07 +02:00 CEST");
}

TEST(Calendar, LocalTimesInTheGapStartAfterItAndRepeatedOnesTakeTheFirst) {
  const Calendar cal(zone_config("Europe/Berlin", {shift("odd", 2, 30, 10, 0)}));
  // 02:30 does not exist on 29 March: the shift starts at 03:00 CEST = 01:00Z.
  const auto spring = cal.next_shift_after(utc("2026-03-28T12:00:00Z"));
  ASSERT_TRUE(spring);
  EXPECT_EQ(spring->start_ns, utc("2026-03-29T01:00:00Z"));
  EXPECT_EQ(spring->end_ns, utc("2026-03-29T08:00:00Z"));
  // 02:30 happens twice on 25 October: the first (CEST) is 00:30Z.
  const auto fall = cal.next_shift_after(utc("2026-10-24T12:00:00Z"));
  ASSERT_TRUE(fall);
  EXPECT_EQ(fall->start_ns, utc("2026-10-25T00:30:00Z"));
  EXPECT_EQ(fall->end_ns, utc("2026-10-25T09:00:00Z"));
  EXPECT_EQ(cal.utc_ns(2026, 3, 29, 2, 30), utc("2026-03-29T01:00:00Z"));
  EXPECT_EQ(cal.utc_ns(2026, 10, 25, 2, 30), utc("2026-10-25T00:30:00Z"));
  EXPECT_THROW((void)cal.utc_ns(2026, 2, 29, 0, 0), std::invalid_argument);
}

TEST(Calendar, ReadsTypedDatesAndTimesInThePlantsZone) {
  // Hand-worked: Berlin is UTC+1 in January (CET), UTC+2 in July (CEST); on 2026-03-29 02:00 CET
  // the clocks jump to 03:00 CEST, on 2026-10-25 03:00 CEST they fall back to 02:00 CET.
  const Calendar berlin(zone_config("Europe/Berlin", {}));
  EXPECT_EQ(berlin.parse_time("2027-01-15"), utc("2027-01-14T23:00:00Z"));  // local midnight
  EXPECT_EQ(berlin.parse_time("2027-07-15"), utc("2027-07-14T22:00:00Z"));
  EXPECT_EQ(berlin.parse_time("2027-01-15T00:30"), utc("2027-01-14T23:30:00Z"));
  EXPECT_EQ(berlin.parse_time("2027-01-15 09:00:01.5"), utc("2027-01-15T08:00:01.5Z"));
  EXPECT_EQ(berlin.parse_time("2026-03-29T02:30"), utc("2026-03-29T01:00:00Z"));  // the gap's end
  EXPECT_EQ(berlin.parse_time("2026-10-25T02:30"), utc("2026-10-25T00:30:00Z"));  // the first
  // A time with Z or an offset means what it says, whatever the plant's zone.
  EXPECT_EQ(berlin.parse_time("2027-01-15T06:00Z"), utc("2027-01-15T06:00:00Z"));
  EXPECT_EQ(berlin.parse_time("2027-01-15T06:00+05:30"), utc("2027-01-15T00:30:00Z"));
  EXPECT_EQ(berlin.parse_time("2027-01-15T06:00:10-03:00"), utc("2027-01-15T09:00:10Z"));
  // Without a plant config the CLI reads UTC: a date is UTC midnight.
  const Calendar utc_plant(zone_config("UTC", {}));
  EXPECT_EQ(utc_plant.parse_time("2027-01-15"), utc("2027-01-15T00:00:00Z"));
  // The wall clock as if UTC (a chart's local days) and back.
  EXPECT_EQ(berlin.wall_ns(utc("2027-01-14T23:30:00Z")), utc("2027-01-15T00:30:00Z"));
  EXPECT_EQ(berlin.wall_ns(utc("2027-07-14T22:00:00.25Z")), utc("2027-07-15T00:00:00.25Z"));
  EXPECT_EQ(berlin.from_wall_ns(utc("2027-01-15T00:30:00Z")), utc("2027-01-14T23:30:00Z"));
  EXPECT_EQ(berlin.from_wall_ns(utc("2026-03-29T00:00:00Z")), utc("2026-03-28T23:00:00Z"));
  EXPECT_EQ(berlin.from_wall_ns(utc("2026-03-30T00:00:00Z")), utc("2026-03-29T22:00:00Z"));
  for (const char* bad :
       {"", "2027-1-15", "2027-02-30", "15.01.2027", "2027-01-15T25:00", "2027-01-15T06:00+24:00",
        "2027-01-15T06:00+1:00", "2027-01-15Z", "2027-01-15T06:00 CET", "yesterday"}) {
    EXPECT_FALSE(berlin.parse_time(bad).has_value()) << bad;
  }
}

TEST(Calendar, WeekdayShiftsSkipTheWeekend) {
  const Calendar cal(zone_config("America/Chicago", default_calendar_config().shifts));
  // Friday 6 March 2026 22:00 CST is the end of the late shift; the next shift is Monday
  // 9 March 06:00 CDT = 11:00Z (the clocks sprang forward on Sunday 8 March).
  const std::int64_t friday_night = utc("2026-03-07T04:00:00Z");
  EXPECT_FALSE(cal.shift_at(friday_night));
  const auto next = cal.next_shift_after(friday_night);
  ASSERT_TRUE(next);
  EXPECT_EQ(next->name, "early");
  EXPECT_EQ(next->start_ns, utc("2026-03-09T11:00:00Z"));
  // Late shift on the Friday before: 14:00 CST = 20:00Z.
  const auto late = cal.shift_at(utc("2026-03-06T21:00:00Z"));
  ASSERT_TRUE(late);
  EXPECT_EQ(late->name, "late");
  EXPECT_EQ(late->start_ns, utc("2026-03-06T20:00:00Z"));
  EXPECT_EQ(late->end_ns, utc("2026-03-07T04:00:00Z"));
}

TEST(Calendar, MonthlyCheckFallsDueAtLocalMidnightAndIsOverdueAtTheFirstShiftOfTheMonth) {
  const Calendar cal(zone_config("America/Chicago", default_calendar_config().shifts));
  const PeriodConfig& monthly = period(cal, "monthly");
  const std::int64_t passed = utc("2026-01-02T13:00:00Z");
  // 31 January 23:59 CST: still January.
  EXPECT_FALSE(cal.due(monthly, passed, utc("2026-02-01T05:59:00Z")));
  // 1 February 00:00 CST = 06:00Z: due. 1 February 2026 is a Sunday: no shift, not overdue.
  EXPECT_EQ(cal.period_start(monthly, utc("2026-02-10T00:00:00Z")), utc("2026-02-01T06:00:00Z"));
  EXPECT_TRUE(cal.due(monthly, passed, utc("2026-02-01T06:00:00Z")));
  EXPECT_FALSE(cal.overdue(monthly, passed, utc("2026-02-02T11:59:00Z")));
  // Monday 2 February 06:00 CST = 12:00Z: the first shift of February has started.
  EXPECT_TRUE(cal.overdue(monthly, passed, utc("2026-02-02T12:00:00Z")));
  EXPECT_EQ(cal.next_due(monthly, passed, utc("2026-01-20T00:00:00Z")),
            utc("2026-02-01T06:00:00Z"));
  // December to January crosses the year; February of a leap year has 29 days.
  EXPECT_EQ(cal.next_period_start(monthly, utc("2026-12-15T00:00:00Z")),
            utc("2027-01-01T06:00:00Z"));
  EXPECT_EQ(cal.next_period_start(monthly, utc("2028-02-29T12:00:00Z")),
            utc("2028-03-01T06:00:00Z"));
  // A month that starts in CDT: 1 April 00:00 CDT = 05:00Z.
  EXPECT_EQ(cal.period_start(monthly, utc("2026-04-15T00:00:00Z")), utc("2026-04-01T05:00:00Z"));
}

TEST(Calendar, DailyPeriodFollowsLocalMidnightAcrossDst) {
  const Calendar cal(zone_config("Europe/Berlin", default_calendar_config().shifts));
  const PeriodConfig& daily = period(cal, "daily");
  // 29 March 2026 starts at 00:00 CET = 28 March 23:00Z and lasts 23 h.
  EXPECT_EQ(cal.period_start(daily, utc("2026-03-29T12:00:00Z")), utc("2026-03-28T23:00:00Z"));
  EXPECT_EQ(cal.next_period_start(daily, utc("2026-03-29T12:00:00Z")), utc("2026-03-29T22:00:00Z"));
  // A pass at 05:30 CEST on 30 March counts for that day, not for the 29th.
  const std::int64_t pass = utc("2026-03-30T03:30:00Z");
  EXPECT_FALSE(cal.due(daily, pass, utc("2026-03-30T21:59:00Z")));
  EXPECT_TRUE(cal.due(daily, pass, utc("2026-03-30T22:00:00Z")));
  EXPECT_TRUE(cal.due(daily, std::nullopt, utc("2026-03-30T12:00:00Z")));
}

TEST(Calendar, MissedShiftsMakeEveryStalePeriodOverdueButNotTwiceDue) {
  const Calendar cal(zone_config("UTC", default_calendar_config().shifts));
  const PeriodConfig& daily = period(cal, "daily");
  const PeriodConfig& weekly = period(cal, "weekly");
  // Last passes on Monday 5 January 2026; the machine is back on Thursday 15 January 10:00.
  const std::int64_t last = utc("2026-01-05T06:30:00Z");
  const std::int64_t back = utc("2026-01-15T10:00:00Z");
  EXPECT_TRUE(cal.overdue(daily, last, back));
  EXPECT_TRUE(cal.overdue(weekly, last, back));
  // One pass now satisfies the period, whatever was missed before.
  EXPECT_FALSE(cal.due(daily, back + kMinute, back + 2 * kMinute));
  EXPECT_FALSE(cal.due(weekly, back + kMinute, utc("2026-01-18T23:59:00Z")));
  EXPECT_TRUE(cal.due(weekly, back + kMinute, utc("2026-01-19T00:00:00Z")));
  // Never passed: due, and overdue once a shift has started.
  EXPECT_TRUE(cal.overdue(daily, std::nullopt, back));
  EXPECT_FALSE(cal.overdue(daily, std::nullopt, utc("2026-01-17T12:00:00Z")));  // a Saturday
}

TEST(Calendar, WeeksStartOnTheConfiguredDayAndCountGroupsThem) {
  CalendarConfig c = zone_config("UTC", default_calendar_config().shifts);
  c.week_start = 6;  // Sunday
  c.periods = {{"fortnightly", PeriodUnit::Week, 2, {CheckKind::FixturePreCalibration}}};
  const Calendar cal(c);
  const PeriodConfig& p = cal.config().periods.front();
  // Sunday-weeks counted from Sunday 4 January 1970 (day 3); fortnights from there.
  const std::int64_t start = cal.period_start(p, utc("2026-01-14T12:00:00Z"));
  const std::int64_t next = cal.next_period_start(p, utc("2026-01-14T12:00:00Z"));
  EXPECT_EQ(next - start, 14 * 24 * kHour);
  const std::int64_t start_day = start / (24 * kHour);
  EXPECT_EQ((start_day - 3) % 14, 0);
  EXPECT_EQ((start_day + 4) % 7, 0);  // a Sunday: day 3 is one
  EXPECT_LE(start, utc("2026-01-14T12:00:00Z"));
  EXPECT_GT(next, utc("2026-01-14T12:00:00Z"));
}

TEST(Calendar, PerShiftPeriodIsDueAtEveryShift) {
  CalendarConfig c = zone_config("UTC", default_calendar_config().shifts);
  c.periods = {{"every shift", PeriodUnit::Shift, 1, {CheckKind::MonumentPositioning}}};
  const Calendar cal(c);
  const PeriodConfig& p = cal.config().periods.front();
  const std::int64_t early_pass = utc("2026-01-06T06:10:00Z");
  EXPECT_FALSE(cal.due(p, early_pass, utc("2026-01-06T13:59:00Z")));
  EXPECT_TRUE(cal.due(p, early_pass, utc("2026-01-06T14:00:00Z")));
  EXPECT_EQ(cal.next_due(p, early_pass, utc("2026-01-06T10:00:00Z")), utc("2026-01-06T14:00:00Z"));
}

// The section as YAML text (parse_calendar_config reads it as the loader would).
const std::string& yaml(const std::string& text) { return text; }

TEST(CalendarConfig, ReadsShiftsPeriodsAndParts) {
  const CalendarConfig c = parse_calendar_config(yaml(R"(
time_zone: Europe/Berlin
week_start: sun
shifts:
  - {name: night, start: "22:00", end: "06:00", days: sun-thu}
  - {name: day, start: "06:00", end: "14:00", days: [mon, wed]}
periods:
  - {name: daily, every: day, checks: [monument_c_alignment, monument_positioning]}
  - {name: biweekly, every: week, count: 2, checks: [fixture_precal]}
parts: {cycle_min: 90}
check_timeout_min: 45
retries: 1
)"),
                                                 "plant.yaml");
  EXPECT_EQ(c.time_zone, "Europe/Berlin");
  EXPECT_EQ(c.week_start, 6);
  ASSERT_EQ(c.shifts.size(), 2u);
  EXPECT_EQ(c.shifts[0].start_minute, 22 * 60);
  EXPECT_EQ(c.shifts[0].days, (std::array<bool, 7>{true, true, true, true, false, false, true}));
  EXPECT_EQ(c.shifts[1].days, (std::array<bool, 7>{true, false, true, false, false, false, false}));
  ASSERT_EQ(c.periods.size(), 2u);
  EXPECT_EQ(c.periods[1].every, 2);
  EXPECT_EQ(c.periods[1].unit, PeriodUnit::Week);
  EXPECT_EQ(c.parts.cycle_min, 90);
  EXPECT_EQ(c.parts.checks, std::vector<CheckKind>{CheckKind::PartSetPoints});
  EXPECT_EQ(c.check_timeout_min, 45);
  EXPECT_EQ(c.retries, 1);
  // Omitted: the defaults of docs/architecture.md.
  const CalendarConfig d = parse_calendar_config(yaml("{}"), "plant.yaml");
  ASSERT_EQ(d.periods.size(), 3u);
  EXPECT_EQ(d.periods[0].name, "monthly");
  EXPECT_EQ(d.periods[2].checks.front(), CheckKind::MonumentCAlignment);
}

void expect_refused(const std::string& text, const std::string& key, const std::string& value) {
  try {
    (void)parse_calendar_config(yaml(text), "plant.yaml");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("plant.yaml"), std::string::npos) << what;
    EXPECT_NE(what.find(key), std::string::npos) << what;
    EXPECT_NE(what.find(value), std::string::npos) << what;
  }
}

TEST(CalendarConfig, RefusesBadValuesNamingKeyAndValue) {
  expect_refused("time_zone: Mars/Olympus", "time_zone", "Mars/Olympus");
  expect_refused("shifts: [{name: a, start: '25:00', end: '06:00'}]", "shifts[0].start", "25:00");
  expect_refused("shifts: [{name: a, start: '06:00'}]", "shifts[0].end", "missing");
  expect_refused("shifts: [{name: a, start: '06:00', end: '14:00', days: [mon, funday]}]",
                 "shifts[0].days[1]", "funday");
  expect_refused("shifts: [{name: a, start: '06:00', end: '14:00', dayz: mon}]", "dayz",
                 "unknown key");
  expect_refused("periods: [{name: p, every: fortnight, checks: [monument_positioning]}]",
                 "periods[0].every", "fortnight");
  expect_refused("periods: [{name: p, every: day, checks: [part_setpoints]}]",
                 "periods[0].checks[0]", "per part");
  expect_refused(
      "periods: [{every: day, checks: [monument_positioning]}, {every: week, checks: "
      "[monument_positioning]}]",
      "periods[1].checks[0]", "another period");
  expect_refused("periods: [{every: day, count: 0, checks: [monument_positioning]}]", "count", "0");
  expect_refused("retries: -1", "retries", "-1");
  expect_refused("check_timeout_min: 0", "check_timeout_min", "0");
  expect_refused("week_start: someday", "week_start", "someday");
}

TEST(CalendarConfig, PlantConfigCarriesCalendarStateFileAndSimulatedClock) {
  const std::string dir = ::testing::TempDir() + "ncqual-calendar-plant";
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/plant.yaml";
  {
    std::ofstream(path) << "plant: p\nhistorian: {database: var/h.db}\n"
                           "scheduler:\n  calendar: {time_zone: UTC}\n"
                           "clock: {mode: simulated, start: '2026-01-05T00:00:00Z'}\n";
  }
  const PlantConfig p = load_plant_config(path);
  ASSERT_TRUE(p.calendar);
  EXPECT_TRUE(p.simulated_clock);
  EXPECT_EQ(p.simulated_start_ns, utc("2026-01-05T00:00:00Z"));
  EXPECT_EQ(std::filesystem::path(p.scheduler_state_database).filename(), "scheduler.db");
  EXPECT_EQ(std::filesystem::path(p.scheduler_state_database).parent_path().filename(), "var");
  { std::ofstream(path) << "plant: p\nclock: {mode: simulated, start: 'monday'}\n"; }
  try {
    (void)load_plant_config(path);
    ADD_FAILURE() << "a bad clock.start was accepted";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("clock.start"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ncqual
