// SPDX-License-Identifier: Apache-2.0
// Starting processes from tests: the one way the tests run an executable, whether a service that
// runs beside the test (the integration harness), the `ncqual` binary (the CLI tests) or any
// other program (bash for the completion test).
//
// An argv, never a shell: every argument reaches the program as it is, so paths with spaces or
// quotes need no quoting. argv[0] is a path, or a name looked up in PATH. Captured output goes
// to unlinked temporary files rather than pipes, so a child that writes a lot never blocks on a
// test that is not reading yet; it is read when the process has ended.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <csignal>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace ncqual::testing {

// Where a child's stdout and stderr go.
enum class Output {
  Separate,    // stdout to out(), stderr to err()
  Merged,      // both to out(), interleaved as the child wrote them (2>&1)
  StdoutOnly,  // stdout to out(), stderr discarded (e.g. for --json)
  LogFile,     // both appended to Launch::log_file (a service's log); out() and err() are empty
};

// What to start and how: Launch({"sh", "-c", "..."}).in(dir).with_env("TZ", "UTC").
struct Launch {
  explicit Launch(std::vector<std::string> argv_, Output output_ = Output::Separate)
      : argv(std::move(argv_)), output(output_) {}
  Launch& in(std::string directory) {
    working_directory = std::move(directory);
    return *this;
  }
  Launch& with_env(const std::string& name, std::string value) {
    environment[name] = std::move(value);
    return *this;
  }
  // Output::LogFile into `path`.
  Launch& log_to(std::string path) {
    output = Output::LogFile;
    log_file = std::move(path);
    return *this;
  }

  std::vector<std::string> argv;  // argv[0]: the executable, a path or a name in PATH
  Output output = Output::Separate;
  std::string working_directory;                   // empty: the test's own
  std::map<std::string, std::string> environment;  // set in the child, over the test's own
  std::string log_file;  // for Output::LogFile: created if missing, appended to
};

// A child process. The destructor stops one still running as an operator would (SIGTERM, so that
// it removes its shared-memory segments; SIGKILL if it has not ended after 10 s) and reaps it.
class Process {
 public:
  // Starts `launch.argv`; throws std::runtime_error naming the program when it cannot be started
  // (not found, not executable, no such working directory).
  explicit Process(const Launch& launch);
  ~Process();
  Process(const Process&) = delete;
  Process& operator=(const Process&) = delete;

  pid_t pid() const { return pid_; }
  // False once the process has ended (it is reaped then).
  bool running();
  void terminate() { signal(SIGTERM); }
  void kill() { signal(SIGKILL); }
  void signal(int sig);  // any signal, while it runs
  // Waits for the end; its exit code, or -1 when a signal ended it (term_signal() says which).
  int wait();
  // As wait(), but gives up after `timeout`: false when it still runs then.
  bool wait_for(std::chrono::milliseconds timeout);
  // The signal that ended it, 0 when it exited (or has not ended).
  int term_signal() const { return term_signal_; }
  // What it wrote (see Output); complete once it has ended, read by wait().
  const std::string& out() const { return out_; }
  const std::string& err() const { return err_; }

 private:
  void ended(int status);

  pid_t pid_ = -1;
  bool exited_ = false;
  int exit_code_ = -1;
  int term_signal_ = 0;
  int out_fd_ = -1;  // the unlinked temporary files that capture stdout and stderr
  int err_fd_ = -1;
  std::string out_;
  std::string err_;
};

// A finished run: exit code (-1 when a signal ended it) and what it wrote.
struct Outcome {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// Starts `launch`, waits for it to end and returns what it did. A program that cannot be started
// gives exit code -1 and the reason in `err` (in `out` for Output::Merged), so that a test's
// assertion on the code shows why.
Outcome run(const Launch& launch);

}  // namespace ncqual::testing
