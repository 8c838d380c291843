// SPDX-License-Identifier: Apache-2.0
// The command lines of `ncqual` and the services, with no service running: --help of every
// command and subcommand, --version of every executable, bad usage (exit 2 naming the flag),
// --flag=value, exit code 6, and the bash completion the build writes.
#include "cli_runner.hpp"

#include "ncqual/storage/database.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include <algorithm>
#include <chrono>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#if !defined(NCQUAL_SOURCE_DIR) || !defined(NCQUAL_VERSION) || !defined(NCQUAL_COMPLETION_FILE)
#error "NCQUAL_SOURCE_DIR, NCQUAL_VERSION and NCQUAL_COMPLETION_FILE must be defined by the target"
#endif

namespace ncqual {
namespace {

using testing_cli::Capture;
using testing_cli::CliRun;
using testing_cli::run_cli;
using testing_cli::run_command;
using testing_cli::words;

// `ncqual <args>`, stdout and stderr apart.
CliRun run(const std::vector<std::string>& args) { return run_cli(args, Capture::Separate); }

// Every command path with flags its help must mention.
const std::vector<std::pair<std::string, std::vector<std::string>>> kCommands{
    {"history", {"--plant", "--db", "--machine", "--kind", "--limit", "--since-ns", "--json"}},
    {"check",
     {"--machine", "--kind", "--plant", "--domain", "--secure", "--identity", "--wait", "--json"}},
    {"wait",
     {"--plant", "--db", "--request", "--count", "--settled", "--machine", "--since-ns",
      "--timeout"}},
    {"count", {"--plant", "--db", "--machine"}},
    {"budget", {"--machine", "--plant", "--db", "--last", "--json"}},
    {"analyze", {"iso230-2", "circle", "grid", "touches", "points"}},
    {"analyze iso230-2", {"FILE", "--json"}},
    {"analyze circle", {"FILE", "--plane", "--nominal-radius-mm", "--centre-mm", "--json"}},
    {"analyze grid", {"--x-run", "--y-run", "--grid", "--json"}},
    {"analyze touches", {"LOG", "--program", "--machine", "--plant", "--json"}},
    {"analyze points", {"EXPORT", "--nominals", "--machine", "--plant", "--json"}},
    {"import", {"iso230-2", "circle", "grid", "touches", "points"}},
    {"import iso230-2", {"FILE", "--machine", "--axis", "--plant", "--domain"}},
    {"import circle", {"FILE", "--machine", "--plane", "--nominal-radius-mm", "--centre-mm"}},
    {"import grid", {"--x-run", "--y-run", "--grid", "--machine"}},
    {"import touches",
     {"FILE", "--program", "--machine", "--plant", "--domain", "--secure", "--identity"}},
    {"import points",
     {"FILE", "--nominals", "--machine", "--plant", "--domain", "--secure", "--identity"}},
    {"program", {"--machine", "--check", "--dialect", "--parameters", "--out", "--plant"}},
    {"status", {"--plant", "--db", "--machine", "--json"}},
    {"intervene",
     {"--machine", "--check", "--note", "--operator", "--plant", "--domain", "--secure",
      "--identity"}},
    {"trend",
     {"--machine", "--kind", "--every", "--metrics", "--metric", "--since", "--until", "--last",
      "--csv", "--json", "--plant", "--db"}},
    {"uncertainty",
     {"--machine", "--plant", "--trials", "--seed", "--threads", "--search", "--json"}},
    {"config", {"check"}},
    {"config check", {"--plant", "--print", "--json"}},
    {"db", {"check", "recover", "thin"}},
    {"db check", {"--plant", "--db"}},
    {"db recover", {"FROM", "TO"}},
    {"db thin", {"--before", "--dry-run", "--plant", "--db"}},
    {"export", {"--since", "--until", "--machine", "--csv", "--overwrite", "--plant", "--db"}},
    {"backup", {"--out", "--overwrite", "--quick", "--step-pages", "--plant", "--db"}},
    {"record",
     {"--out", "--topics", "--machine", "--compression", "--max-size-mib", "--split-every",
      "--stop-after", "--duration", "--overwrite", "--plant", "--domain", "--secure",
      "--identity"}},
    {"recording", {"info", "recover"}},
    {"recording info", {"FILE", "--json"}},
    {"recording recover", {"IN", "OUT", "--overwrite"}},
    {"replay",
     {"FILE", "--rate", "--fast", "--topics", "--machine", "--from", "--to", "--readers",
      "--resolve", "--json", "--metric-tolerance", "--plant", "--domain", "--secure",
      "--identity"}},
};

TEST(CliUsage, HelpOfEveryCommandAndSubcommandNamesItsFlags) {
  for (const auto& [path, flags] : kCommands) {
    for (const char* help : {" --help", " -h"}) {
      const CliRun r = run(words(path + help));
      EXPECT_EQ(r.exit_code, 0) << path << help << "\n" << r.err;
      EXPECT_NE(r.out.find("usage: ncqual " + path), std::string::npos) << path << "\n" << r.out;
      for (const auto& flag : flags) {
        EXPECT_NE(r.out.find(flag), std::string::npos) << path << ": " << flag << "\n" << r.out;
      }
    }
  }
  // The top level: every command with its synopsis, and the exit codes.
  const CliRun top = run({"--help"});
  EXPECT_EQ(top.exit_code, 0) << top.err;
  EXPECT_EQ(run({"help"}).out, top.out);
  for (const auto& [path, flags] : kCommands) {
    EXPECT_NE(top.out.find("\n  " + path + " "), std::string::npos) << path << "\n" << top.out;
  }
  EXPECT_NE(top.out.find("Exit codes: 0 ok/PASS, 1 error, 2 usage (an unknown flag, a bad "
                         "value, a machine the plant does not configure), 3 FAIL, 4 INVALID"),
            std::string::npos)
      << top.out;
  EXPECT_EQ(top.out.find("completion"), std::string::npos) << "the completion command is hidden";
}

TEST(CliUsage, VersionOfTheCliAndOfEveryService) {
  // "<program> 0.1.0 (git 8c8baf2-dirty)", or "(git unknown)" without git.
  const std::string version =
      std::regex_replace(NCQUAL_VERSION, std::regex(R"(\.)"), R"(\.)") + R"( \(git [^)]+\)\n)";
  const CliRun cli = run({"--version"});
  EXPECT_EQ(cli.exit_code, 0) << cli.err;
  EXPECT_TRUE(std::regex_match(cli.out, std::regex("ncqual " + version))) << cli.out;
  for (const auto& [name, exe] : std::vector<std::pair<std::string, std::string>>{
           {"ncqual-historian", NCQUAL_HISTORIAN_EXE},
           {"ncqual-solver", NCQUAL_SOLVER_EXE},
           {"ncqual-acquisition", NCQUAL_ACQUISITION_EXE},
           {"ncqual-scheduler", NCQUAL_SCHEDULER_EXE},
           {"ncqual-recorder", NCQUAL_RECORDER_EXE}}) {
    const CliRun v = run_command({exe, "--version"}, Capture::Separate);
    EXPECT_EQ(v.exit_code, 0) << name << "\n" << v.err;
    EXPECT_TRUE(std::regex_match(v.out, std::regex(name + " " + version))) << v.out;
    // The same build: the CLI's text after its name.
    EXPECT_EQ(v.out.substr(name.size()), cli.out.substr(std::string("ncqual").size())) << name;

    const CliRun help = run_command({exe, "--help"}, Capture::Separate);
    EXPECT_EQ(help.exit_code, 0) << name;
    for (const char* flag :
         {"--plant", "--domain", "--log-level", "--secure", "--identity", "--version"}) {
      EXPECT_NE(help.out.find(flag), std::string::npos) << name << ": " << flag;
    }
    const CliRun bogus = run_command({exe, "--bogus"}, Capture::Separate);
    EXPECT_EQ(bogus.exit_code, 2) << name;
    EXPECT_NE(bogus.err.find("--bogus"), std::string::npos) << bogus.err;
    const CliRun missing = run_command({exe, "--domain"}, Capture::Separate);
    EXPECT_EQ(missing.exit_code, 2) << name;
    EXPECT_NE(missing.err.find("--domain"), std::string::npos) << missing.err;
  }
}

TEST(CliUsage, BadUsageExitsTwoNamingTheFlagWithTheCommandsUsage) {
  for (const auto& [args, named] : std::vector<std::pair<std::string, std::string>>{
           {"history --bogus", "--bogus"},
           {"history --limit five", "--limit"},
           {"history --kind nothing", "--kind"},
           {"budget --plant p.yaml --machine", "--machine"},
           {"budget --plant p.yaml", "--machine"},
           {"check --machine pm1 --kind=nothing", "--kind"},
           {"trend --machine pm1 --metrics 21", "--metrics"},
           {"intervene --machine pm1 --check monument_positioning", "--note"},
           {"status -x", "-x"},
           {"record --plant p.yaml", "--out"},
           {"record --out r.mcap --compression bzip2", "--compression"},
           {"replay r.mcap --fast --rate 2", "--rate"},
           {"wait --timeout", "--timeout"},
           {"export --csv out", "--since"},
           {"export --since 2027-01-01", "--csv"},
           {"backup --db h.db", "--out"},
           {"db thin --before", "--before"},
           {"nothing", "nothing"}}) {
    const CliRun r = run(words(args));
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(named), std::string::npos) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("usage: ncqual"), std::string::npos) << args << "\n" << r.err;
  }
}

// Issue 37: an unknown machine gave exit 0 with an empty table (history), 1 (budget), 2 (status,
// trend, report). One mistake, one code: a machine the plant does not configure is bad usage,
// exit 2, naming it, what the plant configures and the nearest name; no command opens a
// historian, a control's files or the network first.
TEST(CliUsage, AMachineThePlantDoesNotConfigureIsBadUsageInEveryCommand) {
  const testing_cli::TempDir tmp("ncqual-cli-machine");
  const std::string plant = NCQUAL_SOURCE_DIR "/deploy/plant.yaml";
  const std::string out = (tmp.path() / "out").string();
  for (const std::string& args : std::vector<std::string>{
           "history --machine pm11",
           "count --machine pm11",
           "status --machine pm11",
           "trend --machine pm11",
           "report --machine pm11 --out " + out + ".html",
           "budget --machine pm11",
           "uncertainty --machine pm11",
           "check --machine pm11 --kind monument_positioning",
           "intervene --machine pm11 --check monument_positioning --note n",
           "program --machine pm11 --check monument_positioning --out " + out + ".ngc",
           "export --machine pm11 --since 2027-01-01 --csv " + out,
           "wait --machine pm11 --count 1 --timeout 1",
           "analyze touches none.log --program none.ngc --machine pm11",
           "import touches none.log --program none.ngc --machine pm11",
       }) {
    std::vector<std::string> argv = words(args);
    argv.insert(argv.end(), {"--plant", plant});
    const CliRun r = run(argv);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find("--machine 'pm11' is not configured in " + plant +
                         " (it configures pm1); did you mean 'pm1'?"),
              std::string::npos)
        << args << "\n"
        << r.err;
  }
  EXPECT_FALSE(std::filesystem::exists(out)) << "export made its folder";
}

// Without a plant config the historian says which machines there are.
TEST(CliUsage, AMachineTheHistorianDoesNotHoldIsBadUsageWithoutAPlant) {
  const testing_cli::TempDir tmp("ncqual-cli-held");
  const std::string db = (tmp.path() / "h.db").string();
  {
    storage::Database d = storage::Database::open(db);
    MachineStatus s;
    s.machine_id = "cell-7";
    s.state = MachineState::Qualified;
    s.time_ns = 1;
    d.store(s);
  }
  for (const char* command : {"history", "count", "report"}) {
    std::vector<std::string> argv{command, "--db", db, "--machine", "cell-1"};
    if (std::string(command) == "report")
      argv.insert(argv.end(), {"--out", (tmp.path() / "r.html").string()});
    const CliRun r = run(argv);
    EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.err;
    EXPECT_NE(r.err.find("--machine 'cell-1': the historian " + db +
                         " holds no such machine (it holds cell-7); did you mean 'cell-7'?"),
              std::string::npos)
        << command << "\n"
        << r.err;
  }
  const CliRun held = run({"count", "--db", db, "--machine", "cell-7"});
  EXPECT_EQ(held.exit_code, 0) << held.err;
  EXPECT_EQ(held.out, "0\n");
}

// Issue 37: a heartbeat older than three periods on the reader's wall clock is stale, whatever
// its state said; a service whose last word was "stopped" is stopped, however old.
TEST(CliStatus, AServiceNotHeardForThreePeriodsIsStaleAndOneThatSaidStoppedIsStopped) {
  const testing_cli::TempDir tmp("ncqual-cli-stale");
  const std::string db = (tmp.path() / "h.db").string();
  const auto now_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                          std::chrono::system_clock::now().time_since_epoch())
                          .count();
  {
    storage::Database d = storage::Database::open(db);
    const auto beat = [&](const std::string& service, const std::string& state, double age_s) {
      Heartbeat b;
      b.service = service;
      b.instance = "host:" + service;
      b.state = state;
      b.time_ns = now_ns - static_cast<std::int64_t>(age_s * 1e9);
      d.store(b);
    };
    beat("solver", "running", 6.5);      // 3 periods of 2 s and a half second: stale
    beat("scheduler", "stopped", 3600);  // an hour ago, but it said it stopped
    beat("historian", "running", 0);     // just now
  }
  const CliRun json =
      run({"status", "--plant", NCQUAL_SOURCE_DIR "/deploy/plant.yaml", "--db", db, "--json"});
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto doc = nlohmann::json::parse(json.out);
  std::map<std::string, std::string> liveness;
  for (const auto& s : doc.at("services")) liveness[s.at("service")] = s.at("liveness");
  EXPECT_EQ(liveness["solver"], "stale");
  EXPECT_EQ(liveness["scheduler"], "stopped");
  EXPECT_EQ(liveness["historian"], "live");
  EXPECT_EQ(doc.at("machines").at(0).at("scheduler"), "stopped");

  const CliRun text =
      run({"status", "--plant", NCQUAL_SOURCE_DIR "/deploy/plant.yaml", "--db", db});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_NE(text.out.find("STALE"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("stale since"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("no scheduler is running for it (it stopped)"), std::string::npos)
      << text.out;
}

// A mistyped flag is named with the flag the command has nearest to it, as `config check` does for
// a key; a flag nowhere near any is named alone.
TEST(CliUsage, AMistypedFlagIsNamedWithTheNearestFlag) {
  for (const auto& [args, said] : std::vector<std::pair<std::string, std::string>>{
           {"history --machin pm1",
            "'--machin' is not an option of ncqual history; did you mean '--machine'?"},
           {"analyze circle c.csv --nominal-radius 150",
            "'--nominal-radius' is not an option of ncqual analyze circle; did you mean "
            "'--nominal-radius-mm'?"},
           {"status --jsno", "'--jsno' is not an option of ncqual status; did you mean '--json'?"},
           {"status --frobnicate", "'--frobnicate' is not an option of ncqual status\n"},
       }) {
    const CliRun r = run(words(args));
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(said), std::string::npos) << args << "\n" << r.err;
  }
  const CliRun service = run_command({NCQUAL_SOLVER_EXE, "--plnat", "p.yaml"}, Capture::Separate);
  EXPECT_EQ(service.exit_code, 2);
  EXPECT_NE(service.err.find("'--plnat' is not an option of ncqual-solver; did you mean "
                             "'--plant'?"),
            std::string::npos)
      << service.err;
}

TEST(CliUsage, FlagEqualsValueMeansTheSameAsTwoWords) {
  const std::string file = std::string(NCQUAL_SOURCE_DIR) + "/tests/data/instrument/circle_xy.csv";
  const CliRun spaced = run({"analyze", "circle", file, "--nominal-radius-mm", "150", "--json"});
  const CliRun joined = run({"analyze", "circle", file, "--nominal-radius-mm=150", "--json"});
  EXPECT_EQ(spaced.exit_code, 0) << spaced.err;
  EXPECT_EQ(joined.out, spaced.out);
}

TEST(CliUsage, NoHistorianDatabaseIsNotFound) {
  const testing_cli::TempDir tmp("ncqual-cli-usage");
  const CliRun r = run({"history", "--db", (tmp.path() / "none.db").string()});
  EXPECT_EQ(r.exit_code, 6) << r.err;
  EXPECT_NE(r.err.find("none.db"), std::string::npos) << r.err;
}

// Completes `words` (the last one being completed) with the script the build wrote.
std::vector<std::string> complete(const std::string& words) {
  const CliRun r =
      run_command({"bash", "-c",
                   "source " NCQUAL_COMPLETION_FILE " && COMP_WORDS=(" + words +
                       ") && COMP_CWORD=$((${#COMP_WORDS[@]} - 1)) && _ncqual && printf \"%s\\n\" "
                       "\"${COMPREPLY[@]}\""},
                  Capture::Separate);
  EXPECT_EQ(r.exit_code, 0) << words << "\n" << r.err;
  std::vector<std::string> out;
  std::size_t start = 0;
  for (std::size_t end; (end = r.out.find('\n', start)) != std::string::npos; start = end + 1) {
    out.push_back(r.out.substr(start, end - start));
  }
  return out;
}

bool has(const std::vector<std::string>& v, const std::string& s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

TEST(CliUsage, BashCompletionOfCommandsFlagsAndKinds) {
  const auto commands = complete("ncqual \"\"");
  for (const char* c : {"history", "check", "wait", "count", "budget", "analyze", "import",
                        "program", "status", "intervene", "trend", "uncertainty", "record",
                        "recording", "replay", "db", "export", "backup"}) {
    EXPECT_TRUE(has(commands, c)) << c;
  }
  EXPECT_FALSE(has(commands, "completion"));
  EXPECT_EQ(complete("ncqual bu"), std::vector<std::string>{"budget"});
  const auto budget = complete("ncqual budget --m");
  EXPECT_TRUE(has(budget, "--machine"));
  EXPECT_EQ(complete("ncqual budget --machine pm1 --pl"), std::vector<std::string>{"--plant"});
  EXPECT_EQ(complete("ncqual analyze ci"), std::vector<std::string>{"circle"});
  EXPECT_EQ(complete("ncqual analyze cm"), std::vector<std::string>{"cmm"});
  EXPECT_TRUE(has(complete("ncqual analyze circle --"), "--nominal-radius-mm"));
  EXPECT_TRUE(has(complete("ncqual check --kind monument_p"), "monument_positioning"));
  EXPECT_EQ(complete("ncqual recording re"), std::vector<std::string>{"recover"});
  EXPECT_TRUE(has(complete("ncqual replay --re"), "--resolve"));
  EXPECT_EQ(complete("ncqual db th"), std::vector<std::string>{"thin"});
  EXPECT_EQ(complete("ncqual export --cs"), std::vector<std::string>{"--csv"});
  EXPECT_EQ(complete("ncqual backup --ou"), std::vector<std::string>{"--out"});
}

// `config check`: every problem of the plant at once, with file, key and value, exit 4; the
// example plant loads, exit 0, and --print shows resolved values with their units.
TEST(CliUsage, ConfigCheckPrintsEveryProblemOrTheResolvedPlant) {
  testing_cli::TempDir tmp("ncqual-config-check");
  const std::string pm1 = std::string(NCQUAL_SOURCE_DIR) + "/deploy/machines/pm1.yaml";
  const std::string machine =
      tmp.write("m.yaml", "extends: " + pm1 + "\nmachine_id: m\ntolerances: {centre_dx_mm: 1}\n");
  const std::string plant = tmp.write(
      "plant.yaml",
      "plant: p\nsimulated: true\ndomian_id: 3\nqos_profile: q.xml\nmachines: [" + machine + "]\n");
  const CliRun bad = run({"config", "check", "--plant", plant});
  EXPECT_EQ(bad.exit_code, 4) << bad.out << bad.err;
  EXPECT_NE(bad.out.find(plant + ": domian_id = '3': unknown key"), std::string::npos) << bad.out;
  EXPECT_NE(bad.out.find(plant + ": qos_profile = 'q.xml': unknown key"), std::string::npos)
      << bad.out;
  EXPECT_NE(bad.out.find(machine + ": tolerances.centre_dx_mm = '1': no check reads this "
                                   "tolerance; did you mean 'center_dx_mm'?"),
            std::string::npos)
      << bad.out;
  EXPECT_NE(bad.out.find("3 problems"), std::string::npos) << bad.out;

  const CliRun ok =
      run({"config", "check", "--print", "--plant", NCQUAL_SOURCE_DIR "/deploy/plant.yaml"});
  EXPECT_EQ(ok.exit_code, 0) << ok.out << ok.err;
  EXPECT_NE(
      ok.out.find("OK, plant 'demo-plant' on domain 42, 1 machine: pm1\n"
                  "  simulated: true (a demo or test bench): measured by the simulator: pm1\n"),
      std::string::npos)
      << ok.out;
  EXPECT_NE(ok.out.find("  simulated = true\n"), std::string::npos) << ok.out;
  EXPECT_NE(ok.out.find("  budget.allowable_total = 0.762 mm (written 0.03 in)"), std::string::npos)
      << ok.out;
  EXPECT_NE(ok.out.find("  monument.face_offset_mm = 35 mm  (default)"), std::string::npos)
      << ok.out;
  // A plant file cut after its comments: one problem naming it, exit 4 (it died of SIGSEGV).
  const std::string empty = tmp.write("empty.yaml", "# SPDX-License-Identifier: Apache-2.0\n");
  const CliRun cut = run({"config", "check", "--plant", empty});
  EXPECT_EQ(cut.exit_code, 4) << cut.out << cut.err;
  EXPECT_NE(cut.out.find(empty + ": no settings in it (empty, or only comments)"),
            std::string::npos)
      << cut.out;
}

// Issue 37 point 5: the plant the package installs in /etc/ncqual (deploy/systemd/plant.yaml and
// deploy/machines/pm1.yaml, laid out as CMakeLists.txt's install rules put them) does not simulate
// unnoticed: it is refused, naming the machine and the way out, until pm1 has an instrument. A
// plant that loads says whether it is a simulation and which machines the simulator measures.
TEST(CliUsage, ConfigCheckSaysWhetherThePlantIsASimulation) {
  testing_cli::TempDir tmp("ncqual-config-simulated");
  const std::string source = NCQUAL_SOURCE_DIR;
  std::filesystem::create_directories(tmp.path() / "etc" / "machines");
  std::filesystem::copy_file(source + "/deploy/systemd/plant.yaml", tmp.path() / "etc/plant.yaml");
  std::filesystem::copy_file(source + "/deploy/machines/pm1.yaml",
                             tmp.path() / "etc/machines/pm1.yaml");
  const std::string installed = (tmp.path() / "etc/plant.yaml").string();
  const CliRun refused = run({"config", "check", "--plant", installed});
  EXPECT_EQ(refused.exit_code, 4) << refused.out << refused.err;
  EXPECT_NE(refused.out.find(installed + ": machines[0] = 'machines/pm1.yaml': machine 'pm1' (" +
                             (tmp.path() / "etc/machines/pm1.yaml").string() +
                             ") has no instrument: section"),
            std::string::npos)
      << refused.out;
  EXPECT_NE(refused.out.find("give it an instrument: section (docs/connecting-a-machine.md) or, "
                             "for a demo or test bench, say `simulated: true` in the plant"),
            std::string::npos)
      << refused.out;
  EXPECT_NE(refused.out.find("1 problem;"), std::string::npos) << refused.out;

  const std::string pm1 = source + "/deploy/machines/pm1.yaml";
  const std::string ctl = tmp.write("ctl.yaml", "extends: " + pm1 +
                                                    "\nmachine_id: ctl\ninstrument: {driver: "
                                                    "control-files, outbox: o, inbox: i}\n");
  const CliRun measured =
      run({"config", "check", "--plant", tmp.write("measured.yaml", "machines: [" + ctl + "]\n")});
  EXPECT_EQ(measured.exit_code, 0) << measured.out << measured.err;
  EXPECT_NE(measured.out.find("\n  simulated: false: every machine is measured by its "
                              "instrument: ctl\n"),
            std::string::npos)
      << measured.out;

  const std::string bench =
      tmp.write("bench.yaml", "simulated: true\nmachines: [" + pm1 + ", " + ctl + "]\n");
  const CliRun mixed = run({"config", "check", "--plant", bench});
  EXPECT_EQ(mixed.exit_code, 0) << mixed.out << mixed.err;
  EXPECT_NE(mixed.out.find("\n  simulated: true (a demo or test bench): measured by the "
                           "simulator: pm1; by their instruments: ctl\n"),
            std::string::npos)
      << mixed.out;
  const CliRun json = run({"config", "check", "--plant", bench, "--json"});
  ASSERT_EQ(json.exit_code, 0) << json.out << json.err;
  const auto doc = nlohmann::json::parse(json.out);
  EXPECT_EQ(doc.at("simulated"), true);
  ASSERT_EQ(doc.at("machines").size(), 2u);
  EXPECT_EQ(doc.at("machines")[0].at("machine_id"), "pm1");
  EXPECT_EQ(doc.at("machines")[0].at("simulated"), true);
  EXPECT_EQ(doc.at("machines")[1].at("machine_id"), "ctl");
  EXPECT_EQ(doc.at("machines")[1].at("simulated"), false);
}

}  // namespace
}  // namespace ncqual
