// SPDX-License-Identifier: Apache-2.0
// Clocks. Everything that decides by time takes a Clock, so tests and the demo can run on
// simulated time while services run on the wall clock.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string_view>

namespace ncqual {

class Clock {
 public:
  virtual ~Clock() = default;
  // Nanoseconds since the Unix epoch, UTC.
  virtual std::int64_t now_ns() const = 0;
};

class WallClock final : public Clock {
 public:
  std::int64_t now_ns() const override;
};

// A clock that moves only when told to.
class SimulatedClock final : public Clock {
 public:
  explicit SimulatedClock(std::int64_t start_ns = 0) : now_(start_ns) {}
  std::int64_t now_ns() const override { return now_.load(); }
  void set_ns(std::int64_t t) { now_.store(t); }
  void advance_ns(std::int64_t dt) { now_.fetch_add(dt); }

 private:
  std::atomic<std::int64_t> now_;
};

// ISO 8601 UTC text of a time, e.g. "2026-11-22T18:16:22.123Z".
std::string_view format_iso8601(std::int64_t time_ns, char (&buffer)[32]);

// The time of an ISO 8601 UTC text "YYYY-MM-DDTHH:MM[:SS[.fff]]Z" (also with a space for the T);
// nothing when the text is not such a time, or lies outside the years 1678-2261 (int64 ns).
std::optional<std::int64_t> parse_iso8601(std::string_view text);

}  // namespace ncqual
