// SPDX-License-Identifier: Apache-2.0
#include "ncqual/dds/dispatcher.hpp"

#include <spdlog/spdlog.h>

#include <csignal>
#include <thread>

namespace ncqual::dds {
using namespace eprosima::fastdds::dds;

eprosima::fastrtps::Duration_t to_dds_duration(std::chrono::milliseconds ms) {
  const auto count = ms.count() < 0 ? 0 : ms.count();
  return eprosima::fastrtps::Duration_t(static_cast<std::int32_t>(count / 1000),
                                        static_cast<std::uint32_t>((count % 1000) * 1000000));
}

Dispatcher::Dispatcher() { waitset_.attach_condition(stop_); }

Dispatcher::~Dispatcher() {
  for (auto& h : handlers_) waitset_.detach_condition(*h.condition);
  waitset_.detach_condition(stop_);
}

void Dispatcher::every(std::chrono::milliseconds period, std::function<void()> work) {
  periodic_.push_back(Periodic{period, std::chrono::steady_clock::now(), std::move(work)});
}

bool Dispatcher::step(std::chrono::steady_clock::time_point deadline) {
  auto now = std::chrono::steady_clock::now();
  for (auto& p : periodic_) {
    if (p.next < deadline) deadline = p.next;
  }
  ConditionSeq active;
  const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - now);
  waitset_.wait(active, to_dds_duration(wait));
  if (stop_.get_trigger_value()) return false;
  for (auto* condition : active) {
    for (auto& h : handlers_) {
      if (h.condition != condition) continue;
      try {
        h.drain();
      } catch (const std::exception& e) {
        spdlog::error("handler failed: {}", e.what());
      }
    }
  }
  now = std::chrono::steady_clock::now();
  for (auto& p : periodic_) {
    if (p.next > now) continue;
    p.next = now + p.period;
    try {
      p.work();
    } catch (const std::exception& e) {
      spdlog::error("periodic work failed: {}", e.what());
    }
  }
  return true;
}

void Dispatcher::run() {
  while (step(std::chrono::steady_clock::now() + std::chrono::seconds(3600))) {}
}

bool Dispatcher::run_until(const std::function<bool()>& done, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!done()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    if (!step(deadline)) break;
  }
  return done();
}

bool Dispatcher::drain_until(const std::function<bool()>& done, std::chrono::milliseconds timeout) {
  stop_.set_trigger_value(false);
  const bool result = run_until(done, timeout);
  stop_.set_trigger_value(true);
  return result;
}

void Dispatcher::stop() { stop_.set_trigger_value(true); }

bool Dispatcher::stopping() const { return stop_.get_trigger_value(); }

void handle_termination_signals(const std::function<void(int)>& on_signal) {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  std::thread([set, on_signal]() {
    int sig = 0;
    if (sigwait(&set, &sig) == 0) on_signal(sig);
  }).detach();
}

}  // namespace ncqual::dds
