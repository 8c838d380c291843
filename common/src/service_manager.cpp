// SPDX-License-Identifier: Apache-2.0
// sd_notify and the watchdog's period (service_manager.hpp), on Debian's libsystemd.
#include "ncqual/common/service_manager.hpp"

#include <spdlog/spdlog.h>
#include <systemd/sd-daemon.h>

#include <cstdint>
#include <cstring>

namespace ncqual::service_manager {

void notify(const std::string& state) {
  if (const int r = sd_notify(0, state.c_str()); r < 0) {
    spdlog::warn("could not notify the service manager ({}): {}", state, std::strerror(-r));
  }
}

std::optional<std::chrono::microseconds> watchdog_ping_period() {
  std::uint64_t watchdog_usec = 0;
  if (sd_watchdog_enabled(0, &watchdog_usec) <= 0 || watchdog_usec == 0) return std::nullopt;
  return std::chrono::microseconds(std::max<std::uint64_t>(watchdog_usec / 2, 1000));
}

}  // namespace ncqual::service_manager
