// SPDX-License-Identifier: Apache-2.0
// The receive loop of a service: one WaitSet over the readers' DATA_AVAILABLE conditions, a
// GuardCondition to stop it from any thread, and optional periodic work (heartbeats, timeouts).
#pragma once

#include "ncqual/dds/endpoint.hpp"

#include <fastdds/dds/core/condition/GuardCondition.hpp>
#include <fastdds/dds/core/condition/WaitSet.hpp>

#include <chrono>
#include <functional>
#include <vector>

namespace ncqual::dds {

class Dispatcher {
 public:
  Dispatcher();
  ~Dispatcher();

  // Calls `handler` for every sample `reader` receives, on the dispatcher's thread.
  template <typename Topic, typename Handler>
  void on(Reader<Topic>& reader, Handler handler) {
    handlers_.push_back(Entry{&reader.condition(), [&reader, handler]() {
                                for (auto& r : reader.take()) handler(std::move(r));
                              }});
    waitset_.attach_condition(reader.condition());
  }

  // Calls `handler` for every sample any of `readers` receives.
  template <typename Topic, typename Handler>
  void on(MachineReaders<Topic>& readers, Handler handler) {
    for (const auto& r : readers.readers()) on(*r, handler);
  }

  // Calls `drain` whenever `condition` triggers (a reader's status condition with data
  // available): for readers that are not typed (raw.hpp).
  void on(eprosima::fastdds::dds::Condition& condition, std::function<void()> drain) {
    handlers_.push_back(Entry{&condition, std::move(drain)});
    waitset_.attach_condition(condition);
  }

  // Calls `work` about every `period` (steady clock), on the dispatcher's thread.
  void every(std::chrono::milliseconds period, std::function<void()> work);

  // Runs until stop() is called. Exceptions from handlers are logged and the loop goes on: one
  // bad sample must not take a service down.
  void run();
  // Runs until `done()` is true (checked after each wake-up) or the timeout; returns done().
  bool run_until(const std::function<bool()>& done, std::chrono::milliseconds timeout);
  // After a stop: runs again until `done()`, the timeout or another stop (a second signal), then
  // is stopped again. For the last work of a stopping service (an outbox's drain).
  bool drain_until(const std::function<bool()>& done, std::chrono::milliseconds timeout);
  // Thread-safe; wakes run() and makes it return.
  void stop();
  // True once stop() was called (a signal, or the service's own decision).
  bool stopping() const;

 private:
  struct Entry {
    eprosima::fastdds::dds::Condition* condition;
    std::function<void()> drain;
  };
  struct Periodic {
    std::chrono::milliseconds period;
    std::chrono::steady_clock::time_point next;
    std::function<void()> work;
  };
  // One wait and the work it makes due; returns false when stopped.
  bool step(std::chrono::steady_clock::time_point deadline);

  eprosima::fastdds::dds::WaitSet waitset_;
  eprosima::fastdds::dds::GuardCondition stop_;
  std::vector<Entry> handlers_;
  std::vector<Periodic> periodic_;
};

// Blocks SIGINT and SIGTERM in the calling thread (call first thing in main, before any thread
// is started, so every thread inherits the mask) and starts a thread that waits for them and
// calls `on_signal` once. Returns immediately.
void handle_termination_signals(const std::function<void(int)>& on_signal);

}  // namespace ncqual::dds
