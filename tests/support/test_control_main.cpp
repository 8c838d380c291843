// SPDX-License-Identifier: Apache-2.0
// ncqual-test-control --machine-config FILE: stands in for that machine's NC control in
// multi-process tests of the control-files driver. It watches the machine's instrument outbox and
// answers each probing program with the touch log its control would write (control_emulator.hpp),
// until SIGTERM. Prints "answered <request id>" per program.
#include "control_emulator.hpp"

#include "ncqual/common/clock.hpp"

#include <csignal>
#include <cstdio>
#include <exception>
#include <thread>

namespace {
volatile std::sig_atomic_t stop = 0;
void on_signal(int) { stop = 1; }
}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 || std::string(argv[1]) != "--machine-config") {
    std::fprintf(stderr, "usage: ncqual-test-control --machine-config FILE\n");
    return 2;
  }
  std::signal(SIGTERM, on_signal);
  std::signal(SIGINT, on_signal);
  try {
    const ncqual::MachineConfig machine = ncqual::load_machine_config(argv[2]);
    const ncqual::WallClock clock;
    while (!stop) {
      for (const auto& id : ncqual::testing::answer_programs(machine, clock.now_ns())) {
        std::printf("answered %s\n", id.c_str());
        std::fflush(stdout);
      }
      // A control's operator or DNC watcher looks at the folder now and then.
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ncqual-test-control: %s\n", e.what());
    return 1;
  }
  return 0;
}
