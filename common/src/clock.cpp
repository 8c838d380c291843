// SPDX-License-Identifier: Apache-2.0
#include "ncqual/common/clock.hpp"

#include <chrono>
#include <cstdio>
#include <ctime>
#include <date/date.h>
#include <cctype>
#include <string>
#include <string_view>

namespace ncqual {

std::int64_t WallClock::now_ns() const {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string_view format_iso8601(std::int64_t time_ns, char (&buffer)[32]) {
  std::int64_t secs = time_ns / 1000000000;
  std::int64_t rem = time_ns % 1000000000;
  if (rem < 0) {
    rem += 1000000000;
    secs -= 1;
  }
  const std::time_t t = static_cast<std::time_t>(secs);
  std::tm tm{};
  gmtime_r(&t, &tm);
  const int n = std::snprintf(buffer, sizeof buffer, "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ",
                              tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday, tm.tm_hour, tm.tm_min,
                              tm.tm_sec, static_cast<int>(rem / 1000000));
  return std::string_view(buffer, n > 0 ? static_cast<std::size_t>(n) : 0);
}

std::optional<std::int64_t> parse_iso8601(std::string_view text) {
  // YYYY-MM-DD(T| )HH:MM[:SS[.fff...]]Z, read field by field: no locale, no partial matches.
  const std::string s(text);
  int y = 0, mo = 0, d = 0, h = 0, mi = 0, consumed = 0;
  char sep = 0;
  if (std::sscanf(s.c_str(), "%4d-%2d-%2d%c%2d:%2d%n", &y, &mo, &d, &sep, &h, &mi, &consumed) !=
          6 ||
      consumed != 16 || (sep != 'T' && sep != ' ')) {
    return std::nullopt;
  }
  std::size_t i = 16;
  std::int64_t ns = 0;
  if (i < s.size() && s[i] == ':') {
    if (i + 3 > s.size() || !std::isdigit(static_cast<unsigned char>(s[i + 1])) ||
        !std::isdigit(static_cast<unsigned char>(s[i + 2]))) {
      return std::nullopt;
    }
    const int sec = (s[i + 1] - '0') * 10 + (s[i + 2] - '0');
    if (sec > 59) return std::nullopt;
    ns = sec * 1000000000LL;
    i += 3;
    if (i < s.size() && s[i] == '.') {
      std::int64_t scale = 100000000;
      for (++i; i < s.size() && std::isdigit(static_cast<unsigned char>(s[i])); ++i, scale /= 10) {
        ns += (s[i] - '0') * scale;
      }
    }
  }
  if (i + 1 != s.size() || s[i] != 'Z' || h > 23 || mi > 59) return std::nullopt;
  // Nanoseconds in int64 reach from September 1677 to April 2262: refuse what would overflow.
  if (y < 1678 || y > 2261) return std::nullopt;
  const date::year_month_day ymd{date::year(y), date::month(static_cast<unsigned>(mo)),
                                 date::day(static_cast<unsigned>(d))};
  if (!ymd.ok()) return std::nullopt;
  const std::int64_t days = date::sys_days(ymd).time_since_epoch().count();
  return ((days * 24 + h) * 60 + mi) * 60 * 1000000000LL + ns;
}

}  // namespace ncqual
