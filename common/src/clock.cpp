#include "ncqual/clock.hpp"

#include <chrono>
#include <cstdio>
#include <ctime>
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

}  // namespace ncqual
