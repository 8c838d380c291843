// SPDX-License-Identifier: Apache-2.0
// The dashboard's HTTP server and its life (serve.hpp): cpp-httplib 0.11's listener over
// web::Dashboard, one thread taking SIGTERM and SIGINT, the systemd watchdog pinged while the
// server answers its own request, and the error budgets evaluated when the historian changes.
#include "serve.hpp"

#include "ncqual/web/dashboard.hpp"

#include "ncqual/common/service_manager.hpp"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <mutex>
#include <pthread.h>
#include <string>
#include <thread>
#include <utility>

namespace ncqual::web {

namespace {

// The request httplib parsed, as the dashboard takes it.
web::Request request_of(const httplib::Request& req) {
  web::Request r;
  r.method = req.method;
  r.path = req.path;
  for (const auto& [name, value] : req.params) r.params.emplace_back(name, value);
  return r;
}

void answer(web::Dashboard& dashboard, const httplib::Request& req, httplib::Response& res) {
  const web::Reply reply = dashboard.handle(request_of(req));
  res.status = reply.status;
  for (const auto& [name, value] : reply.headers) res.set_header(name, value);
  res.set_content(reply.body, reply.content_type);
}

}  // namespace

int serve(const PlantConfig& plant, const std::string& database) {
  // SIGTERM and SIGINT are taken by one thread (sigwait), blocked in every thread's mask before
  // httplib starts its workers; SIGUSR1 wakes that thread when listening ended by itself.
  sigset_t waited;
  sigemptyset(&waited);
  sigaddset(&waited, SIGTERM);
  sigaddset(&waited, SIGINT);
  sigaddset(&waited, SIGUSR1);
  pthread_sigmask(SIG_BLOCK, &waited, nullptr);

  web::Dashboard dashboard(plant, database);
  httplib::Server server;
  server.set_payload_max_length(std::size_t{64} *
                                1024);  // nothing is posted; a body is read no further
  server.set_read_timeout(std::chrono::seconds(10));
  server.set_write_timeout(std::chrono::seconds(10));
  server.set_keep_alive_max_count(100);
  // Every method reaches the dashboard, which answers 405 to all but GET and HEAD, before any
  // body is read.
  server.set_pre_routing_handler([&](const httplib::Request& req, httplib::Response& res) {
    if (req.method == "GET" || req.method == "HEAD")
      return httplib::Server::HandlerResponse::Unhandled;
    answer(dashboard, req, res);
    return httplib::Server::HandlerResponse::Handled;
  });
  server.Get(".*", [&](const httplib::Request& req, httplib::Response& res) {
    answer(dashboard, req, res);
  });
  server.set_exception_handler(
      [](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
        std::string what = "unknown error";
        try {
          std::rethrow_exception(std::move(ep));
        } catch (const std::exception& e) {
          what = e.what();
        } catch (...) {}
        spdlog::error("{} {}: {}", req.method, req.path.substr(0, 200), what);
        res.status = 500;
        res.set_content("{\"error\": {\"status\": 500, \"message\": \"internal error\"}}\n",
                        "application/json");
      });
  server.set_logger([](const httplib::Request& req, const httplib::Response& res) {
    spdlog::debug("{} {} -> {}", req.method, req.path.substr(0, 200), res.status);
  });

  int bound = 0;
  if (plant.web.port == 0) {
    bound = server.bind_to_any_port(plant.web.bind);
  } else {
    bound = server.bind_to_port(plant.web.bind, plant.web.port) ? plant.web.port : -1;
  }
  if (bound <= 0) {
    throw ConfigError("cannot listen on " + plant.web.bind + ":" + std::to_string(plant.web.port) +
                      " (in use, or not an address of this host)");
  }

  std::atomic<bool> stopping{false};
  std::atomic<bool> listening_done{false};
  std::mutex mutex;
  std::condition_variable done;
  std::thread signals([&] {
    int signal = 0;
    for (;;) {
      sigwait(&waited, &signal);
      if (signal != SIGUSR1) break;  // SIGTERM or SIGINT
      if (listening_done) return;    // listening ended by itself: nothing to stop
    }
    spdlog::info("{}: stopping", signal == SIGTERM ? "SIGTERM" : "SIGINT");
    stopping = true;
    service_manager::notify("STOPPING=1");
    // stop() closes the listener once listen has begun: asked again until listen returned.
    std::unique_lock lock(mutex);
    while (!listening_done) {
      server.stop();
      done.wait_for(lock, std::chrono::milliseconds(50));
    }
  });
  // Under WatchdogSec=: pinged while the dashboard still answers a request of its own.
  std::thread watchdog;
  if (const auto ping = service_manager::watchdog_ping_period()) {
    const auto period = *ping;
    const std::string host = plant.web.bind == "0.0.0.0" ? "127.0.0.1" : plant.web.bind;
    watchdog = std::thread([&, period, host] {
      httplib::Client self(host, bound);
      self.set_connection_timeout(std::chrono::seconds(2));
      self.set_read_timeout(std::chrono::seconds(5));
      std::unique_lock lock(mutex);
      while (!done.wait_for(lock, period, [&] { return listening_done.load(); })) {
        lock.unlock();
        const auto res = self.Get("/api/v1/changes");
        if (res && res->status == 200) service_manager::notify("WATCHDOG=1");
        lock.lock();
      }
    });
  }

  // The error budgets, evaluated when the historian changes rather than when a page asks (their
  // Monte Carlo would be most of a machine page's time): at start, then whenever the change
  // token moves, looked at every second.
  std::thread budgets([&] {
    std::string seen;
    std::unique_lock lock(mutex);
    do {
      lock.unlock();
      try {
        if (const std::string token = dashboard.change_token(); token != seen) {
          const std::size_t evaluated =
              dashboard.refresh_budgets([&] { return listening_done.load(); });
          if (evaluated > 0) spdlog::debug("error budgets evaluated again: {}", evaluated);
          seen = token;
        }
      } catch (const std::exception& e) {
        spdlog::warn("error budgets: {} (tried again in a second)", e.what());
      }
      lock.lock();
    } while (!done.wait_for(lock, std::chrono::seconds(1), [&] { return listening_done.load(); }));
  });

  spdlog::info("serving plant {} on http://{}:{}/ from {} (read-only)", plant.plant, plant.web.bind,
               bound, database);
  service_manager::notify("READY=1");
  const bool ok = stopping || server.listen_after_bind();
  {
    const std::lock_guard lock(mutex);
    listening_done = true;
  }
  done.notify_all();
  if (!stopping) pthread_kill(signals.native_handle(), SIGUSR1);  // listen ended: end sigwait
  signals.join();
  if (watchdog.joinable()) watchdog.join();
  budgets.join();
  spdlog::info("stopped");
  return ok || stopping ? 0 : 1;
}

}  // namespace ncqual::web
