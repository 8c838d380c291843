// SPDX-License-Identifier: Apache-2.0
// tests/support/process.hpp, with small programs every Debian machine has (sh, printf, pwd,
// printenv, sleep, head).
#include "process.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace ncqual::testing {
namespace {

namespace fs = std::filesystem;

TEST(Process, ExitCodeAndStdoutAndStderrApart) {
  const Outcome r = run(Launch({"sh", "-c", "echo to-out; echo to-err >&2; exit 3"}));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(r.out, "to-out\n");
  EXPECT_EQ(r.err, "to-err\n");
  EXPECT_EQ(run(Launch({"true"})).exit_code, 0);
}

TEST(Process, MergedKeepsTheOrderAndStdoutOnlyDropsStderr) {
  const std::string script = "echo 1; echo 2 >&2; echo 3";
  const Outcome merged = run(Launch({"sh", "-c", script}, Output::Merged));
  EXPECT_EQ(merged.out, "1\n2\n3\n");
  EXPECT_EQ(merged.err, "");
  const Outcome stdout_only = run(Launch({"sh", "-c", script}, Output::StdoutOnly));
  EXPECT_EQ(stdout_only.out, "1\n3\n");
  EXPECT_EQ(stdout_only.err, "");
}

TEST(Process, ArgumentsArriveAsTheyAreWithNoShell) {
  const Outcome r =
      run(Launch({"printf", "[%s]\\n", "two words", "it's \"quoted\"", "$HOME", "*", ""}));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "[two words]\n[it's \"quoted\"]\n[$HOME]\n[*]\n[]\n");
}

TEST(Process, WorkingDirectoryAndEnvironment) {
  const fs::path dir = fs::canonical(fs::temp_directory_path());
  const Outcome pwd = run(Launch({"pwd"}).in(dir.string()));
  EXPECT_EQ(pwd.out, dir.string() + "\n");
  const Outcome env = run(Launch({"printenv", "NCQUAL_PROCESS_TEST", "PATH"})
                              .with_env("NCQUAL_PROCESS_TEST", "a value"));
  EXPECT_EQ(env.out, std::string("a value\n") + std::getenv("PATH") + "\n");
}

TEST(Process, MuchOutputDoesNotBlockTheChild) {
  const Outcome r = run(Launch({"head", "-c", "3000000", "/dev/zero"}));
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out.size(), 3000000u);
}

TEST(Process, LogFileIsAppendedTo) {
  const fs::path log =
      fs::temp_directory_path() / ("ncqual-process-test-" + std::to_string(::getpid()) + ".log");
  std::ofstream(log) << "before\n";
  for (const char* word : {"one", "two"}) {
    const Outcome r =
        run(Launch({"sh", "-c", std::string("echo ") + word + "; echo " + word + "-err >&2"})
                .log_to(log.string()));
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_EQ(r.out, "");
  }
  std::stringstream text;
  text << std::ifstream(log).rdbuf();
  EXPECT_EQ(text.str(), "before\none\none-err\ntwo\ntwo-err\n");
  fs::remove(log);
}

TEST(Process, KilledAndTerminatedProcessesSayBySignal) {
  Process killed(Launch({"sleep", "600"}));
  EXPECT_TRUE(killed.running());
  EXPECT_FALSE(killed.wait_for(std::chrono::milliseconds(50)));
  killed.kill();
  EXPECT_EQ(killed.wait(), -1);
  EXPECT_EQ(killed.term_signal(), SIGKILL);
  EXPECT_FALSE(killed.running());

  Process terminated(Launch({"sleep", "600"}));
  terminated.terminate();
  EXPECT_TRUE(terminated.wait_for(std::chrono::seconds(10)));
  EXPECT_EQ(terminated.wait(), -1);
  EXPECT_EQ(terminated.term_signal(), SIGTERM);
}

TEST(Process, TheDestructorStopsARunningProcess) {
  pid_t pid = 0;
  {
    Process p(Launch({"sleep", "600"}));
    pid = p.pid();
    ASSERT_GT(pid, 0);
  }
  // Reaped: the pid names no process of ours any more.
  EXPECT_NE(::kill(pid, 0), 0);
}

TEST(Process, AProgramThatCannotStartIsNamed) {
  EXPECT_THROW(Process(Launch({"/nonexistent/ncqual-nothing"})), std::runtime_error);
  const Outcome r = run(Launch({"/nonexistent/ncqual-nothing"}));
  EXPECT_EQ(r.exit_code, -1);
  EXPECT_NE(r.err.find("cannot start /nonexistent/ncqual-nothing"), std::string::npos) << r.err;
  const Outcome merged = run(Launch({"true"}, Output::Merged).in("/nonexistent-dir"));
  EXPECT_EQ(merged.exit_code, -1);
  EXPECT_NE(merged.out.find("in /nonexistent-dir"), std::string::npos) << merged.out;
}

}  // namespace
}  // namespace ncqual::testing
