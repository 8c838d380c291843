// SPDX-License-Identifier: Apache-2.0
// Running the built `ncqual` binary from a test: its exit code and what it printed, and a private
// temporary directory for the files a test writes. Shared by the CLI tests (budget, analyze,
// uncertainty, import, usage, golden outputs); the binary is NCQUAL_CLI_EXE, defined by each test
// target's CMake. Processes start through tests/support/process.hpp: an argv, no shell.
#pragma once

#include "process.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#ifndef NCQUAL_CLI_EXE
#error "NCQUAL_CLI_EXE (the path of the built ncqual binary) must be defined by the test target"
#endif

namespace ncqual::testing_cli {

namespace fs = std::filesystem;

// exit_code (-1 when it could not be started or did not exit normally), out, err.
using CliRun = testing::Outcome;

// Merged: stdout and stderr together in `out` (2>&1); StdoutOnly: stderr discarded (e.g. for
// --json); Separate: stdout in `out`, stderr in `err`.
using Capture = testing::Output;

// Runs `argv` (argv[0] a path or a name in PATH) and waits for it.
inline CliRun run_command(std::vector<std::string> argv, Capture capture = Capture::Merged) {
  return testing::run(testing::Launch(std::move(argv), capture));
}

// Runs `ncqual <args>` and waits for it: each element is one argument, as it is.
inline CliRun run_cli(std::vector<std::string> args, Capture capture = Capture::Merged) {
  args.insert(args.begin(), NCQUAL_CLI_EXE);
  return run_command(std::move(args), capture);
}

// stdout alone (stderr discarded).
inline CliRun run_cli_stdout(std::vector<std::string> args) {
  return run_cli(std::move(args), Capture::StdoutOnly);
}

// Fixed words of a command line, split at single spaces: words("history --limit five"). For
// literal text only; a path or any value that is not a fixed word goes as an argument of its own.
inline std::vector<std::string> words(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find(' ', start);
    if (end == std::string::npos) end = text.size();
    if (end > start) out.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return out;
}

// The arguments with spaces between, for a test's failure messages.
inline std::string joined(const std::vector<std::string>& args) {
  std::string text;
  for (const auto& arg : args) text += (text.empty() ? "" : " ") + arg;
  return text;
}

// A new directory under the system's temporary directory, "<stem>-<pid>-<random>", removed with
// everything in it when the object goes, unless NCQUAL_KEEP_TEST_DIRS is set (to look at the
// files of a failed test).
class TempDir {
 public:
  explicit TempDir(const std::string& stem) {
    std::random_device rd;
    for (int attempt = 0; attempt < 100; ++attempt) {
      const fs::path candidate =
          fs::temp_directory_path() /
          (stem + "-" + std::to_string(getpid()) + "-" + std::to_string(rd() % 1000000));
      if (fs::create_directories(candidate)) {
        path_ = candidate;
        return;
      }
    }
    throw std::runtime_error("could not create a temporary directory " + stem + "-*");
  }
  ~TempDir() {
    std::error_code ec;
    if (!std::getenv("NCQUAL_KEEP_TEST_DIRS")) fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const fs::path& path() const { return path_; }

  // Writes `text` to `name` in the directory; returns the file's path.
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path file = path_ / name;
    std::ofstream(file) << text;
    return file.string();
  }

 private:
  fs::path path_;
};

}  // namespace ncqual::testing_cli
