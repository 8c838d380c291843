// Running the built `ncqual` binary from a test: its exit code and what it printed, and a private
// temporary directory for the files a test writes. Shared by the CLI tests (budget, analyze,
// uncertainty, import); the binary is NCQUAL_CLI_EXE, defined by each test target's CMake.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>

#ifndef NCQUAL_CLI_EXE
#error "NCQUAL_CLI_EXE (the path of the built ncqual binary) must be defined by the test target"
#endif

namespace ncqual::testing_cli {

namespace fs = std::filesystem;

struct CliRun {
  int exit_code = -1;  // -1 when it could not be started or did not exit normally
  std::string out;     // stdout (with stderr after it for Capture::Merged)
  std::string err;     // stderr, for Capture::Separate only
};

enum class Capture {
  Merged,      // stdout and stderr together in `out` (2>&1)
  StdoutOnly,  // stdout in `out`, stderr discarded (e.g. for --json)
  Separate,    // stdout in `out`, stderr in `err`
};

namespace detail {

inline std::string read_all(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A file name of its own under the temporary directory (mkstemp), removed by the destructor.
class ScratchFile {
 public:
  ScratchFile() {
    std::string pattern = (fs::temp_directory_path() / "ncqual-cli-stderr-XXXXXX").string();
    const int fd = mkstemp(pattern.data());
    if (fd < 0) throw std::runtime_error("mkstemp " + pattern + " failed");
    close(fd);
    path_ = pattern;
  }
  ~ScratchFile() {
    std::error_code ec;
    fs::remove(path_, ec);
  }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

}  // namespace detail

// Runs `command` through the shell and waits for it. It must already be shell-safe (the
// tests' paths have no spaces or quotes).
inline CliRun run_command(std::string command, Capture capture = Capture::Merged) {
  CliRun r;
  std::unique_ptr<detail::ScratchFile> err_file;
  switch (capture) {
    case Capture::Merged:
      command += " 2>&1";
      break;
    case Capture::StdoutOnly:
      command += " 2>/dev/null";
      break;
    case Capture::Separate:
      err_file = std::make_unique<detail::ScratchFile>();
      command += " 2>" + err_file->path().string();
      break;
  }
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) r.out.append(buffer, n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (err_file) r.err = detail::read_all(err_file->path());
  return r;
}

// Runs `ncqual <args>` through the shell and waits for it (see run_command).
inline CliRun run_cli(const std::string& args, Capture capture = Capture::Merged) {
  return run_command(std::string(NCQUAL_CLI_EXE) + " " + args, capture);
}

// stdout alone (stderr discarded).
inline CliRun run_cli_stdout(const std::string& args) {
  return run_cli(args, Capture::StdoutOnly);
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
