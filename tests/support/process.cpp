// SPDX-License-Identifier: Apache-2.0
#include "process.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace ncqual::testing {
namespace {

// An unlinked temporary file, closed on exec (the child gets it only through dup2).
int capture_file() {
  std::string pattern =
      (std::filesystem::temp_directory_path() / "ncqual-test-output-XXXXXX").string();
  const int fd = mkostemp(pattern.data(), O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("mkostemp " + pattern + ": " + std::strerror(errno));
  ::unlink(pattern.c_str());
  return fd;
}

std::string read_from_start(int fd) {
  std::string text;
  if (fd < 0 || ::lseek(fd, 0, SEEK_SET) < 0) return text;
  char buffer[65536];
  for (ssize_t n; (n = ::read(fd, buffer, sizeof buffer)) != 0;) {
    if (n < 0) {
      if (errno == EINTR) continue;
      break;
    }
    text.append(buffer, static_cast<std::size_t>(n));
  }
  return text;
}

// The test's environment with `extra` set over it, as "NAME=value" strings.
std::vector<std::string> environment_with(const std::map<std::string, std::string>& extra) {
  std::vector<std::string> env;
  for (char** entry = environ; entry && *entry; ++entry) {
    const std::string text = *entry;
    if (extra.count(text.substr(0, text.find('='))) == 0) env.push_back(text);
  }
  for (const auto& [name, value] : extra) env.push_back(name + "=" + value);
  return env;
}

std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> p;
  for (auto& s : strings) p.push_back(s.data());
  p.push_back(nullptr);
  return p;
}

// posix_spawn_file_actions_t, destroyed at the end of the scope.
struct FileActions {
  FileActions() { posix_spawn_file_actions_init(&actions); }
  ~FileActions() { posix_spawn_file_actions_destroy(&actions); }
  posix_spawn_file_actions_t actions;
};

}  // namespace

Process::Process(const Launch& launch) {
  if (launch.argv.empty()) throw std::invalid_argument("Process: an empty argv");
  FileActions files;
  posix_spawn_file_actions_addopen(&files.actions, 0, "/dev/null", O_RDONLY, 0);
  switch (launch.output) {
    case Output::Separate:
      out_fd_ = capture_file();
      err_fd_ = capture_file();
      posix_spawn_file_actions_adddup2(&files.actions, out_fd_, 1);
      posix_spawn_file_actions_adddup2(&files.actions, err_fd_, 2);
      break;
    case Output::Merged:
      out_fd_ = capture_file();
      posix_spawn_file_actions_adddup2(&files.actions, out_fd_, 1);
      posix_spawn_file_actions_adddup2(&files.actions, out_fd_, 2);
      break;
    case Output::StdoutOnly:
      out_fd_ = capture_file();
      posix_spawn_file_actions_adddup2(&files.actions, out_fd_, 1);
      posix_spawn_file_actions_addopen(&files.actions, 2, "/dev/null", O_WRONLY, 0);
      break;
    case Output::LogFile:
      if (launch.log_file.empty())
        throw std::invalid_argument("Process: Output::LogFile, no log_file");
      posix_spawn_file_actions_addopen(&files.actions, 1, launch.log_file.c_str(),
                                       O_WRONLY | O_CREAT | O_APPEND, 0644);
      posix_spawn_file_actions_adddup2(&files.actions, 1, 2);
      break;
  }
  if (!launch.working_directory.empty()) {
    posix_spawn_file_actions_addchdir_np(&files.actions, launch.working_directory.c_str());
  }
  std::vector<std::string> args = launch.argv;
  std::vector<std::string> env = environment_with(launch.environment);
  const int rc = posix_spawnp(&pid_, args[0].c_str(), &files.actions, nullptr,
                              pointers(args).data(), pointers(env).data());
  if (rc != 0) {
    pid_ = -1;
    if (out_fd_ >= 0) ::close(out_fd_);
    if (err_fd_ >= 0) ::close(err_fd_);
    throw std::runtime_error(
        "cannot start " + launch.argv[0] +
        (launch.working_directory.empty() ? "" : " in " + launch.working_directory) + ": " +
        std::strerror(rc));
  }
}

Process::~Process() {
  if (running()) {
    terminate();
    if (!wait_for(std::chrono::seconds(10))) kill();
  }
  wait();
  if (out_fd_ >= 0) ::close(out_fd_);
  if (err_fd_ >= 0) ::close(err_fd_);
}

void Process::ended(int status) {
  exited_ = true;
  if (WIFEXITED(status)) {
    exit_code_ = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    term_signal_ = WTERMSIG(status);
  }
  out_ = read_from_start(out_fd_);
  err_ = read_from_start(err_fd_);
}

bool Process::running() {
  if (pid_ <= 0 || exited_) return false;
  int status = 0;
  if (::waitpid(pid_, &status, WNOHANG) == pid_) {
    ended(status);
    return false;
  }
  return true;
}

void Process::signal(int sig) {
  if (pid_ > 0 && !exited_) ::kill(pid_, sig);
}

int Process::wait() {
  if (pid_ > 0 && !exited_) {
    int status = 0;
    pid_t got;
    while ((got = ::waitpid(pid_, &status, 0)) < 0 && errno == EINTR) {}
    if (got == pid_) ended(status);
  }
  return exit_code_;
}

bool Process::wait_for(std::chrono::milliseconds timeout) {
  // waitpid has no timeout: look every 10 ms until the deadline.
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (running()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

Outcome run(const Launch& launch) {
  Outcome r;
  try {
    Process process(launch);
    r.exit_code = process.wait();
    r.out = process.out();
    r.err = process.err();
  } catch (const std::runtime_error& error) {
    (launch.output == Output::Merged ? r.out : r.err) = error.what();
  }
  return r;
}

}  // namespace ncqual::testing
