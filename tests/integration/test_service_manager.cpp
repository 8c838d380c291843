// SPDX-License-Identifier: Apache-2.0
// The services under systemd (deploy/systemd: Type=notify, WatchdogSec=): each tells the service
// manager READY=1 once its participant, readers, writers and files are made, pings the watchdog
// from its receive loop, and says STOPPING=1 on SIGTERM. The test stands in for systemd at the
// other end of NOTIFY_SOCKET, the datagram socket systemd gives a Type=notify service.
#include "harness.hpp"

#include <gtest/gtest.h>

#include <poll.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <string>
#include <vector>

namespace ncqual::testing {
namespace {

// The receiving end of NOTIFY_SOCKET: one datagram per sd_notify call.
class NotifySocket {
 public:
  explicit NotifySocket(const fs::path& path) : path_(path.string()) {
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    std::strncpy(address.sun_path, path_.c_str(), sizeof address.sun_path - 1);
    if (fd_ < 0 || ::bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
      throw std::runtime_error("cannot bind " + path_ + ": " + std::strerror(errno));
    }
  }
  ~NotifySocket() {
    ::close(fd_);
    ::unlink(path_.c_str());
  }
  const std::string& path() const { return path_; }

  // The next datagram that contains `line`, or "" when none came within `timeout`; every datagram
  // received meanwhile is appended to `seen`.
  std::string next_with(const std::string& line, std::chrono::milliseconds timeout,
                        std::vector<std::string>& seen) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (true) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return "";
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) continue;
      char buffer[4096];
      const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
      if (n <= 0) continue;
      std::string message(buffer, static_cast<std::size_t>(n));
      seen.push_back(message);
      if (("\n" + message + "\n").find("\n" + line + "\n") != std::string::npos) return message;
    }
  }

 private:
  std::string path_;
  int fd_ = -1;
};

TEST(ServiceManager, AServiceIsReadyWhenItsEndpointsAreMadePingsTheWatchdogAndSaysWhenItStops) {
  Plant plant("notify", TestDomain::ServiceManager);
  plant.add_machine("m1", machine_yaml("m1", ""));
  plant.write_plant();
  NotifySocket socket(plant.dir() / "notify.sock");
  std::vector<std::string> seen;
  // The historian, as systemd starts it: NOTIFY_SOCKET, and WATCHDOG_USEC for WatchdogSec=1 (its
  // WATCHDOG_PID unset: the variables are meant for the process that reads them).
  Process historian(Launch({NCQUAL_HISTORIAN_EXE, "--plant", plant.plant_file()})
                        .with_env("NOTIFY_SOCKET", socket.path())
                        .with_env("WATCHDOG_USEC", "1000000")
                        .log_to((plant.dir() / "historian.log").string()));
  const std::string ready = socket.next_with("READY=1", std::chrono::seconds(30), seen);
  ASSERT_FALSE(ready.empty()) << "no READY=1 within 30 s\n" << plant.log("historian");
  EXPECT_NE(ready.find("STATUS=running on domain " + std::to_string(plant.domain())),
            std::string::npos)
      << ready;
  // Ready means the database is open and its schema made.
  EXPECT_TRUE(fs::exists(plant.db_path()));
  // Pinged every half period while the loop runs: twice more within two periods.
  EXPECT_FALSE(socket.next_with("WATCHDOG=1", std::chrono::seconds(2), seen).empty());
  EXPECT_FALSE(socket.next_with("WATCHDOG=1", std::chrono::seconds(2), seen).empty());
  historian.terminate();
  EXPECT_FALSE(socket.next_with("STOPPING=1", std::chrono::seconds(30), seen).empty())
      << plant.log("historian");
  EXPECT_EQ(historian.wait(), 0) << plant.log("historian");

  // Without NOTIFY_SOCKET (not under systemd) a service runs as before and notifies nobody.
  Process plain(Launch({NCQUAL_SOLVER_EXE, "--plant", plant.plant_file()})
                    .log_to((plant.dir() / "solver.log").string()));
  const std::size_t before = seen.size();
  EXPECT_TRUE(socket.next_with("READY=1", std::chrono::seconds(3), seen).empty());
  EXPECT_EQ(seen.size(), before);
  EXPECT_TRUE(plain.running()) << plant.log("solver");
}

}  // namespace
}  // namespace ncqual::testing
