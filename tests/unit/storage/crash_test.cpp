// SPDX-License-Identifier: Apache-2.0
// Crash tests in the spirit of SQLite's own: a child process stores results as fast as it can and
// reports each committed request id over a pipe, then dies by SIGKILL. After every death the file
// must be intact and hold every reported result exactly once, each one whole.
//
// Two ways to die:
// - The parent SIGKILLs the child after reading N ids. Realistic, but the kill tends to land just
//   after the child's report (writing to the pipe wakes the parent, which preempts the child), so
//   between two samples more often than inside one.
// - The child kills itself just before the k-th write or sync of the WAL (every commit) or of the
//   database file (a checkpoint), through a shim VFS: an exact sweep of points inside
//   transactions and checkpoints.
//
// No sleeps: the parent acts only on what it read from the pipe.
#include "kill_vfs.hpp"
#include "storage_test_support.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <functional>
#include <limits>
#include <set>

namespace ncqual::storage {
namespace {

using namespace testing;  // storage_test_support.hpp, kill_vfs.hpp

constexpr int kMetricsPerResult = 64;      // several pages per transaction: more places to die in
constexpr int kMaxStoresPerChild = 5'000;  // a child that is never killed still ends
constexpr std::size_t kNeverKill = std::numeric_limits<std::size_t>::max();

CheckResult big_result(const std::string& request_id, int i) {
  CheckResult result = testing::make_result(request_id, "M" + std::to_string(i % 3), i);
  result.metrics.clear();
  for (int m = 0; m < kMetricsPerResult; ++m) {
    result.metrics.push_back(
        Metric{"metric_" + std::to_string(m), 1e-3 * (m + i), "mm", -0.05, 0.05, m % 7 != 0});
  }
  return result;
}

// The child: never returns into the test framework.
[[noreturn]] void store_until_killed(const std::string& path, const std::string& prefix,
                                     int report_fd) {
  try {
    Database db = Database::open(path);
    for (int i = 0; i < kMaxStoresPerChild; ++i) {
      const std::string id = prefix + std::to_string(i);
      if (!db.store(big_result(id, i))) _exit(4);  // ids are fresh: a false is a bug
      // One write of less than PIPE_BUF bytes is atomic: the parent never reads half an id.
      const std::string line = id + "\n";
      if (write(report_fd, line.data(), line.size()) != static_cast<ssize_t>(line.size())) {
        _exit(3);
      }
    }
  } catch (...) {
    _exit(2);
  }
  _exit(0);
}

struct Death {
  std::vector<std::string> committed;  // every id the child reported, in order
  int wait_status = 0;
};

// Forks a writer (running `prepare` first in the child), reads reported ids, SIGKILLs it once
// `kill_after` were read, and drains the pipe to EOF: ids the child reported between our last
// read and its death were committed too.
Death run_writer(const std::string& path, const std::string& prefix, std::size_t kill_after,
                 const std::function<void()>& prepare) {
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    close(fds[0]);
    prepare();
    store_until_killed(path, prefix, fds[1]);
  }
  close(fds[1]);

  Death death;
  std::string pending;
  bool killed = false;
  char buffer[4096];
  for (;;) {
    const ssize_t n = read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // EOF: the child is gone
    pending.append(buffer, static_cast<std::size_t>(n));
    for (std::size_t end; (end = pending.find('\n')) != std::string::npos;) {
      death.committed.push_back(pending.substr(0, end));
      pending.erase(0, end + 1);
    }
    if (!killed && death.committed.size() >= kill_after) {
      kill(pid, SIGKILL);
      killed = true;
    }
  }
  close(fds[0]);
  waitpid(pid, &death.wait_status, 0);
  return death;
}

// Checks the file as a restarted historian finds it after the deaths so far. `committed` holds
// every id ever reported; `deaths` is how many writers died (each may have committed one result
// it could not report).
void expect_intact(const std::string& path, const std::set<std::string>& committed, int deaths,
                   const std::string& when) {
  SCOPED_TRACE(when);
  Database db = Database::open(path);  // recovery from the WAL happens here
  ASSERT_EQ(db.integrity_check(), "ok");
  RawDb raw(path);
  EXPECT_EQ(raw.text("PRAGMA foreign_key_check"), "");
  for (const auto& id : committed) {
    ASSERT_EQ(raw.count("results", "request_id = '" + id + "'"), 1) << id;
    ASSERT_EQ(raw.count("checks", "request_id = '" + id + "'"), 1) << id;
  }
  const std::int64_t stored = db.count_results();
  EXPECT_GE(stored, static_cast<std::int64_t>(committed.size()));
  EXPECT_LE(stored, static_cast<std::int64_t>(committed.size()) + deaths);
  // Whatever is there is whole: every result with all its metrics, and its check row.
  EXPECT_EQ(raw.count("metrics"), stored * kMetricsPerResult);
  EXPECT_EQ(raw.count("checks"), stored);
}

void expect_sigkilled(const Death& death) {
  ASSERT_TRUE(WIFSIGNALED(death.wait_status) && WTERMSIG(death.wait_status) == SIGKILL)
      << "the writer ended by itself (exit status "
      << (WIFEXITED(death.wait_status) ? WEXITSTATUS(death.wait_status) : -1) << ") after "
      << death.committed.size() << " stores";
}

class StorageCrash : public ::testing::Test {
 protected:
  void SetUp() override {
    // Create and migrate up front, then close: no connection may be open across fork().
    Database::open(path_);
  }

  TempDir dir_;
  std::string path_ = dir_.file("historian.db");
};

TEST_F(StorageCrash, WriterKilledFromOutsideLosesNothingItReported) {
  std::set<std::string> committed;
  const std::size_t kill_points[] = {17, 64, 5, 131, 1, 40};
  int deaths = 0;
  for (std::size_t kill_after : kill_points) {
    const std::string prefix = "outside" + std::to_string(deaths) + "-";
    const Death death = run_writer(path_, prefix, kill_after, [] {});
    ++deaths;
    expect_sigkilled(death);
    ASSERT_GE(death.committed.size(), kill_after);
    committed.insert(death.committed.begin(), death.committed.end());
    expect_intact(path_, committed, deaths, "after kill " + std::to_string(deaths));
  }
}

// Every write or sync of the WAL over the first few commits: dies inside a commit at every
// point it can, and the sample is then entirely there or entirely absent.
TEST_F(StorageCrash, WriterKilledAtEachWalWriteLosesNothingItReported) {
  std::set<std::string> committed;
  int deaths = 0;
  for (long n = 1; n <= 40; ++n) {
    const std::string prefix = "wal" + std::to_string(n) + "-";
    const Death death = run_writer(path_, prefix, kNeverKill,
                                   [n] { testing::install_kill_vfs(KillTarget::Wal, n); });
    ++deaths;
    expect_sigkilled(death);
    committed.insert(death.committed.begin(), death.committed.end());
    expect_intact(path_, committed, deaths, "killed at WAL operation " + std::to_string(n));
    if (HasFatalFailure() || HasNonfatalFailure()) return;
  }
  // The sweep reached past the first commit: deaths fell both inside and between samples.
  EXPECT_GT(committed.size(), 0u);
}

// The database file is written only by checkpoints (after ~1000 WAL pages): dying in the middle
// of copying pages back must not lose or tear anything either.
TEST_F(StorageCrash, WriterKilledDuringACheckpointLosesNothingItReported) {
  std::set<std::string> committed;
  int deaths = 0;
  for (long n : {1L, 2L, 5L, 13L}) {
    const std::string prefix = "checkpoint" + std::to_string(n) + "-";
    const Death death = run_writer(path_, prefix, kNeverKill,
                                   [n] { testing::install_kill_vfs(KillTarget::MainDatabase, n); });
    ++deaths;
    expect_sigkilled(death);
    ASSERT_GT(death.committed.size(), 0u);  // it got as far as a checkpoint
    committed.insert(death.committed.begin(), death.committed.end());
    expect_intact(path_, committed, deaths,
                  "killed at database file operation " + std::to_string(n));
  }
}

}  // namespace
}  // namespace ncqual::storage
