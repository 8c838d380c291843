// SPDX-License-Identifier: Apache-2.0
// The service manager (systemd, Type=notify units in deploy/systemd) as every long-running
// executable speaks to it: readiness, stopping, status and the watchdog. Without a NOTIFY_SOCKET
// (run by hand, in tests) nothing is sent. Link ncqual_command_line.
#pragma once

#include <chrono>
#include <optional>
#include <string>

namespace ncqual::service_manager {

// Tells the service manager `state` ("READY=1", "STOPPING=1", "WATCHDOG=1", "STATUS=..."); a
// failure to send is logged as a warning, never thrown.
void notify(const std::string& state);

// Under a unit with WatchdogSec=: how often to ping ("WATCHDOG=1"), half the watchdog's period as
// sd_watchdog_enabled(3) advises; nothing without a watchdog.
std::optional<std::chrono::microseconds> watchdog_ping_period();

}  // namespace ncqual::service_manager
