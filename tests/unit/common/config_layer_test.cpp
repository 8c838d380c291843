// SPDX-License-Identifier: Apache-2.0
// The configuration layer as a whole: every problem of a plant at once, unknown keys refused at
// every level, the resolved values with their units; and the table of check kinds against the
// wire contract.
#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/config.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

namespace ncqual {
namespace {

namespace fs = std::filesystem;

const std::string kPm1 = NCQUAL_SOURCE_DIR "/deploy/machines/pm1.yaml";

class ConfigLayer : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("ncqual-config-layer-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return (dir_ / name).string();
  }
  fs::path dir_;
};

bool names(const std::vector<std::string>& problems, const std::string& part) {
  return std::any_of(problems.begin(), problems.end(),
                     [&](const std::string& p) { return p.find(part) != std::string::npos; });
}

// The misspellings the issue names, each in its own place, all reported by one load.
TEST_F(ConfigLayer, EveryProblemOfAPlantIsReportedAtOnceWithFileKeyAndValue) {
  const std::string machine = write("m1.yaml", "extends: " + kPm1 + R"(
machine_id: m1
tolerence: {center_dx_mm: 0.02}
tolerances:
  centre_dx_mm: 0.02
budget:
  allowable_totl: "0.03 in"
simulator:
  errors: {machine_shift: [0, 0, 0]}
)");
  const std::string plant = write("plant.yaml",
                                  "plant: p\nsimulated: true\ndomian_id: 7\nqos_profile: qos.xml\n"
                                  "historian: {database: h.db}\nmachines: [" +
                                      machine + "]\n");
  try {
    load_plant_config(plant);
    FAIL() << "loaded a plant full of misspellings";
  } catch (const ConfigError& e) {
    const auto& p = e.problems();
    EXPECT_EQ(p.size(), 6u) << e.what();
    // An unknown key names the known one a few edits away, as a tolerance does.
    EXPECT_TRUE(names(p, plant + ": domian_id = '7': unknown key; did you mean 'domain_id'? "
                                 "expected one of: allow_default_qos, clock, domain_id,"))
        << e.what();
    EXPECT_TRUE(names(p, plant + ": qos_profile = 'qos.xml': unknown key; did you mean "
                                 "'qos_profiles'?"))
        << e.what();
    EXPECT_TRUE(names(p, machine + ": tolerence = (not a single value): unknown key; did you mean "
                                   "'tolerances'?"))
        << e.what();
    EXPECT_TRUE(names(p, machine + ": tolerances.centre_dx_mm = '0.02': no check reads this "
                                   "tolerance; did you mean 'center_dx_mm'?"))
        << e.what();
    EXPECT_TRUE(names(p, machine + ": budget.allowable_totl = '0.03 in': unknown key")) << e.what();
    EXPECT_TRUE(names(p, machine + ": simulator.errors.machine_shift = (not a single value): "
                                   "unknown key"))
        << e.what();
    // what() has them all, one per line.
    const std::string what = e.what();
    EXPECT_EQ(std::count(what.begin(), what.end(), '\n'), 5);
  }
}

TEST_F(ConfigLayer, CheckReportsProblemsWithoutThrowingAndResolvedValuesWithUnits) {
  const std::string plant =
      write("plant.yaml", "plant: p\nsimulated: true\nmachines: [" + kPm1 + "]\n");
  const ConfigReport ok = check_plant_config(plant);
  ASSERT_TRUE(ok.problems.empty()) << ok.problems.front();
  ASSERT_TRUE(ok.plant);
  auto value_of = [&](const std::string& key) -> const ResolvedValue* {
    for (const auto& v : ok.values) {
      if (v.key == key) return &v;
    }
    return nullptr;
  };
  // pm1 writes the allowable total in inches: resolved to mm, as written beside it.
  const ResolvedValue* total = value_of("budget.allowable_total");
  ASSERT_NE(total, nullptr);
  EXPECT_EQ(total->value, "0.762 mm (written 0.03 in)");
  EXPECT_FALSE(total->defaulted);
  const ResolvedValue* tool = value_of("probe.tool_length_mm");
  ASSERT_NE(tool, nullptr);
  EXPECT_EQ(tool->value, "350 mm");
  // Absent keys show the default taken.
  const ResolvedValue* domain = value_of("domain_id");
  ASSERT_NE(domain, nullptr);
  EXPECT_TRUE(domain->defaulted);
  EXPECT_EQ(domain->value, "0");

  const std::string bad = write("bad.yaml", "plant: p\ndomain_id: 300\nmachines: [nowhere.yaml]\n");
  const ConfigReport report = check_plant_config(bad);
  EXPECT_FALSE(report.plant);
  ASSERT_EQ(report.problems.size(), 2u);
  EXPECT_EQ(report.problems[0], bad + ": domain_id = '300': must be an integer from 0 to 232");
  EXPECT_EQ(report.problems[1], (dir_ / "nowhere.yaml").string() + ": file not found");
}

// A plant or machine file cut after its comments (an empty YAML document) is a problem naming the
// file, not a plant made of nothing (`config check` died of SIGSEGV on one).
TEST_F(ConfigLayer, AFileWithOnlyCommentsIsAProblemNamingIt) {
  const std::string empty = write("empty.yaml", "# SPDX-License-Identifier: Apache-2.0\n# cut\n");
  const ConfigReport report = check_plant_config(empty);
  EXPECT_FALSE(report.plant);
  ASSERT_EQ(report.problems.size(), 1u);
  EXPECT_EQ(report.problems[0], empty + ": no settings in it (empty, or only comments)");
  const std::string machine = write("m.yaml", "");
  const std::string plant = write("p.yaml", "plant: p\nmachines: [" + machine + "]\n");
  const ConfigReport with_empty_machine = check_plant_config(plant);
  EXPECT_FALSE(with_empty_machine.plant);
  EXPECT_TRUE(names(with_empty_machine.problems, machine + ": no settings in it"));
}

// A bad value is reported once, not again by every check that uses it.
TEST_F(ConfigLayer, ABadValueIsOneProblemNotACascade) {
  const std::string machine = write("m.yaml", "extends: " + kPm1 + R"(
monument: {hole_diameter_mm: wide}
)");
  try {
    load_machine_config(machine);
    FAIL();
  } catch (const ConfigError& e) {
    ASSERT_EQ(e.problems().size(), 1u) << e.what();
    EXPECT_NE(e.problems()[0].find("monument.hole_diameter_mm = 'wide'"), std::string::npos);
  }
}

// ---- The table of check kinds
// --------------------------------------------------------------------

// The IDL's enum CheckKind, in order, as the table's names (MONUMENT_C_ALIGNMENT ->
// monument_c_alignment).
std::vector<std::string> idl_check_kinds() {
  std::ifstream in(NCQUAL_SOURCE_DIR "/idl/ncqual.idl");
  std::stringstream s;
  s << in.rdbuf();
  const std::string idl = s.str();
  const auto from = idl.find("enum CheckKind {");
  const auto to = idl.find("};", from);
  std::vector<std::string> names;
  std::istringstream body(idl.substr(from + 16, to - from - 16));
  std::string line;
  const std::regex enumerator(R"(^\s*([A-Z0-9_]+)\s*,?)");
  while (std::getline(body, line)) {
    std::smatch m;
    if (!std::regex_search(line, m, enumerator)) continue;
    std::string name = m[1];
    std::transform(name.begin(), name.end(), name.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    names.push_back(name);
  }
  return names;
}

// The instrument: section: the simulator by default; the control-files driver with folders
// relative to the machine file, the archive inside the inbox unless named; every mistake named.
TEST_F(ConfigLayer, TheInstrumentSectionNamesItsDriverAndFoldersRelativeToTheMachineFile) {
  EXPECT_EQ(load_machine_config(kPm1).instrument.driver, InstrumentDriver::Simulator);
  const std::string good = write("ctl.yaml", "extends: " + kPm1 + R"(
machine_id: ctl
instrument: {driver: control-files, dialect: fanuc, outbox: dnc/in, inbox: /srv/dnc/out,
             timeout_s: 900}
)");
  const InstrumentConfig c = load_machine_config(good).instrument;
  EXPECT_EQ(c.driver, InstrumentDriver::ControlFiles);
  EXPECT_EQ(c.dialect, ControlDialect::Fanuc);
  EXPECT_EQ(c.outbox, (dir_ / "dnc/in").string());
  EXPECT_EQ(c.inbox, "/srv/dnc/out");
  EXPECT_EQ(c.archive, "/srv/dnc/out/archive");
  EXPECT_EQ(c.timeout_s, 900);

  const std::string bad = write("bad.yaml", "extends: " + kPm1 + R"(
machine_id: bad
instrument: {driver: control-file, dialect: heidenhain, inbox: x, timeout_s: 0}
)");
  try {
    load_machine_config(bad);
    FAIL() << "loaded a bad instrument section";
  } catch (const ConfigError& e) {
    const auto& p = e.problems();
    EXPECT_TRUE(names(p, bad + ": instrument.driver = 'control-file': expected simulator or "
                               "control-files"))
        << e.what();
    EXPECT_TRUE(names(p, bad + ": instrument.dialect = 'heidenhain': expected one of linuxcnc, "
                               "fanuc, generic-csv"))
        << e.what();
    EXPECT_TRUE(names(p, bad + ": instrument.timeout_s = '0': must be positive")) << e.what();
    EXPECT_TRUE(names(p, bad + ": instrument.inbox = 'x': only the control-files driver reads it"))
        << e.what();
  }
  const std::string same = write("same.yaml", "extends: " + kPm1 + R"(
machine_id: same
instrument: {driver: control-files, inbox: share}
)");
  try {
    load_machine_config(same);
    FAIL() << "loaded a control-files driver without an outbox";
  } catch (const ConfigError& e) {
    EXPECT_TRUE(names(e.problems(), same + ": instrument.outbox = (missing): required"))
        << e.what();
  }
}

// Issue 37 point 5: a plant takes a machine the simulator measures (no instrument: section, or
// driver: simulator) only when it says `simulated: true`; refused, the problem names the plant
// file, the machine's file and id and the way out. A machine measured by its control needs no
// such key, and a simulated plant may mix both.
TEST_F(ConfigLayer, APlantTakesASimulatedMachineOnlyWhenItSaysSimulatedTrue) {
  const std::string sim = write("sim.yaml", "extends: " + kPm1 + R"(
machine_id: sim
instrument: {driver: simulator}
)");
  const std::string ctl = write("ctl.yaml", "extends: " + kPm1 + R"(
machine_id: ctl
instrument: {driver: control-files, outbox: dnc/in, inbox: dnc/out}
)");
  const std::string remedy =
      ", so the simulator would measure it and its results would be simulated; give it an "
      "instrument: section (docs/connecting-a-machine.md) or, for a demo or test bench, say "
      "`simulated: true` in the plant";
  const std::string all = "machines: [" + kPm1 + ", " + sim + ", " + ctl + "]\n";

  for (const char* said : {"", "simulated: false\n"}) {
    const std::string plant = write("plant.yaml", std::string("plant: p\n") + said + all);
    const ConfigReport refused = check_plant_config(plant);
    EXPECT_FALSE(refused.plant);
    ASSERT_EQ(refused.problems.size(), 2u) << said;
    EXPECT_EQ(refused.problems[0], plant + ": machines[0] = '" + kPm1 + "': machine 'pm1' (" +
                                       kPm1 + ") has no instrument: section" + remedy);
    EXPECT_EQ(refused.problems[1], plant + ": machines[1] = '" + sim + "': machine 'sim' (" + sim +
                                       ") says instrument.driver = simulator" + remedy);
    EXPECT_THROW(load_plant_config(plant), ConfigError);
  }

  // Measured by its control: no key needed.
  const PlantConfig measured =
      load_plant_config(write("measured.yaml", "plant: p\nmachines: [" + ctl + "]\n"));
  EXPECT_FALSE(measured.simulated);
  ASSERT_EQ(measured.machines.size(), 1u);
  EXPECT_FALSE(is_simulated(measured.machines[0]));

  // A demo or test bench says so, and may mix both.
  const PlantConfig bench =
      load_plant_config(write("bench.yaml", "plant: p\nsimulated: true\n" + all));
  EXPECT_TRUE(bench.simulated);
  ASSERT_EQ(bench.machines.size(), 3u);
  EXPECT_TRUE(is_simulated(bench.machines[0]));
  EXPECT_TRUE(is_simulated(bench.machines[1]));
  EXPECT_FALSE(is_simulated(bench.machines[2]));

  // A misspelt flag, or a machine whose instrument: section is wrong, is that one problem, not
  // one more for the simulation.
  const ConfigReport yes =
      check_plant_config(write("yes.yaml", "plant: p\nsimulated: yes\nmachines: [" + kPm1 + "]\n"));
  ASSERT_EQ(yes.problems.size(), 1u) << yes.problems.front();
  EXPECT_NE(yes.problems[0].find("simulated = 'yes': expected true or false"), std::string::npos)
      << yes.problems[0];
  const std::string typo = write("typo.yaml", "extends: " + kPm1 + R"(
machine_id: typo
instrument: {driver: control-file}
)");
  const ConfigReport wrong =
      check_plant_config(write("wrong.yaml", "plant: p\nmachines: [" + typo + "]\n"));
  ASSERT_EQ(wrong.problems.size(), 1u) << wrong.problems.front();
  EXPECT_EQ(wrong.problems[0], typo +
                                   ": instrument.driver = 'control-file': expected simulator or "
                                   "control-files");
  // A misspelt key is unknown, with the key it meant; the plant then does not say it simulates.
  const std::string misspelt =
      write("misspelt.yaml", "plant: p\nsimulate: true\nmachines: [" + kPm1 + "]\n");
  const ConfigReport meant = check_plant_config(misspelt);
  ASSERT_EQ(meant.problems.size(), 2u);
  EXPECT_EQ(meant.problems[0].rfind(misspelt + ": simulate = 'true': unknown key; did you mean "
                                               "'simulated'? expected one of: ",
                                    0),
            0u)
      << meant.problems[0];
  EXPECT_TRUE(names(meant.problems, "machine 'pm1'")) << meant.problems[1];
}

// The network: section: the way of discovery and its addresses, each problem named.
TEST_F(ConfigLayer, TheNetworkSectionNamesTheDiscoveryAndItsAddresses) {
  const auto plant_with = [&](const std::string& network) {
    return write("plant.yaml", "plant: p\nsimulated: true\nhistorian: {database: h.db}\n" +
                                   network + "machines: [" + kPm1 + "]\n");
  };
  // Absent: multicast, Fast DDS's own way.
  EXPECT_EQ(load_plant_config(plant_with("")).network.discovery, Discovery::Multicast);

  const PlantConfig servers = load_plant_config(plant_with(
      "network:\n  discovery: server\n  servers: [10.1.0.10, 'ds2.plant.example:14520']\n"));
  EXPECT_EQ(servers.network.discovery, Discovery::Server);
  ASSERT_EQ(servers.network.servers.size(), 2u);
  EXPECT_EQ(servers.network.servers[0].host, "10.1.0.10");
  EXPECT_EQ(servers.network.servers[0].port, 0);  // the default, 11811, applied by the participant
  EXPECT_EQ(to_string(servers.network.servers[1]), "ds2.plant.example:14520");

  const PlantConfig peers =
      load_plant_config(plant_with("network: {discovery: peers, peers: [10.1.0.11, 10.1.0.21]}\n"));
  EXPECT_EQ(peers.network.peers.size(), 2u);

  // A profile of the plant's own carries its addresses.
  EXPECT_EQ(load_plant_config(
                plant_with("network: {discovery: server, participant_profile: site_client}\n"))
                .network.participant_profile,
            "site_client");

  const std::string bad = plant_with(
      "network:\n  discovery: server\n  servers: [10.1.0.300, 'ds:0', 'ds:11811:1', '']\n"
      "  peers: [10.1.0.11]\n");
  try {
    load_plant_config(bad);
    FAIL() << "loaded bad addresses";
  } catch (const ConfigError& e) {
    const auto& p = e.problems();
    EXPECT_EQ(p.size(), 5u) << e.what();
    EXPECT_TRUE(names(p, bad + ": network.servers[0] = '10.1.0.300': expected an address"))
        << e.what();
    EXPECT_TRUE(names(p, "network.servers[1] = 'ds:0'")) << e.what();
    EXPECT_TRUE(names(p, "network.servers[2] = 'ds:11811:1'")) << e.what();
    EXPECT_TRUE(names(p, "network.servers[3] = ''")) << e.what();
    EXPECT_TRUE(names(p, "network.peers = (not a single value): only with discovery: peers"))
        << e.what();
  }
  for (const auto& [network, problem] : std::vector<std::pair<std::string, std::string>>{
           {"network: {discovery: broadcast}\n",
            "network.discovery = 'broadcast': expected multicast, server or peers"},
           {"network: {discovery: server}\n", "network.servers = (missing): required with"},
           {"network: {discovery: peers}\n", "network.peers = (missing): required with"},
           {"network: {discovery: multicast, servers: [10.0.0.1]}\n",
            "only with discovery: server"},
           {"network: {discover: server}\n", "network.discover = 'server': unknown key"}}) {
    try {
      load_plant_config(plant_with(network));
      ADD_FAILURE() << "loaded " << network;
    } catch (const ConfigError& e) {
      EXPECT_TRUE(names(e.problems(), problem)) << network << e.what();
    }
  }
}

// historian.retention: off unless configured; months back from now by the calendar, the last
// day of a shorter month; a bad value or key named.
TEST_F(ConfigLayer, TheRetentionPolicyIsOffByDefaultAndCountsCalendarMonths) {
  const auto plant_with = [&](const std::string& historian) {
    return write("plant.yaml", "plant: p\nsimulated: true\nhistorian: " + historian +
                                   "\nmachines: [" + kPm1 + "]\n");
  };
  const PlantConfig off = load_plant_config(plant_with("{database: h.db}"));
  EXPECT_FALSE(off.retention.thin_points_after_months);
  EXPECT_FALSE(off.retention.thin_points_before_ns(1'800'000'000'000'000'000));

  const PlantConfig on =
      load_plant_config(plant_with("{database: h.db, retention: {thin_points_after_months: 24}}"));
  ASSERT_EQ(on.retention.thin_points_after_months, 24);
  constexpr std::int64_t kDay = 86'400'000'000'000;
  // 2027-01-15T08:00:01.5Z -> 2025-01-15T08:00:01.5Z (days since the epoch: 20833 and 20103).
  const std::int64_t now = 20833 * kDay + 28'801'500'000'000;
  EXPECT_EQ(on.retention.thin_points_before_ns(now), 20103 * kDay + 28'801'500'000'000);
  RetentionConfig one{1};
  // 2027-03-31T00:00Z (20908) -> 2027-02-28T00:00Z (20877).
  EXPECT_EQ(one.thin_points_before_ns(20908 * kDay), 20877 * kDay);

  for (const auto& [historian, problem] : std::vector<std::pair<std::string, std::string>>{
           {"{retention: {thin_points_after_months: 0}}",
            "historian.retention.thin_points_after_months = '0'"},
           {"{retention: {thin_points_after_months: two}}",
            "historian.retention.thin_points_after_months = 'two'"},
           {"{retention: {thin_after_months: 24}}",
            "historian.retention.thin_after_months = '24': unknown key"}}) {
    try {
      load_plant_config(plant_with(historian));
      ADD_FAILURE() << "loaded " << historian;
    } catch (const ConfigError& e) {
      EXPECT_TRUE(names(e.problems(), problem)) << historian << "\n" << e.what();
    }
  }
}

// web: (the dashboard, ncqual-web): the loopback address and port 8470 unless configured; an
// address that is not IPv4, a port out of range and an unknown key named with their values.
TEST_F(ConfigLayer, TheWebSectionListensOnTheLoopbackUnlessConfigured) {
  const auto plant_with = [&](const std::string& web) {
    return write("plant.yaml", "plant: p\nsimulated: true\nhistorian: {database: h.db}\n" + web +
                                   "machines: [" + kPm1 + "]\n");
  };
  const PlantConfig plain = load_plant_config(plant_with(""));
  EXPECT_EQ(plain.web.bind, "127.0.0.1");
  EXPECT_EQ(plain.web.port, 8470);
  const PlantConfig open = load_plant_config(plant_with("web: {bind: 0.0.0.0, port: 8080}\n"));
  EXPECT_EQ(open.web.bind, "0.0.0.0");
  EXPECT_EQ(open.web.port, 8080);
  for (const auto& [web, problem] : std::vector<std::pair<std::string, std::string>>{
           {"web: {bind: dashboard.plant.example}\n",
            "web.bind = 'dashboard.plant.example': expected an IPv4 address"},
           {"web: {bind: 10.0.0.300}\n", "web.bind = '10.0.0.300': expected an IPv4 address"},
           {"web: {bind: '127.0.0.1:80'}\n", "web.bind = '127.0.0.1:80': expected an IPv4"},
           {"web: {port: 0}\n", "web.port = '0'"},
           {"web: {port: 65536}\n", "web.port = '65536'"},
           {"web: {address: 127.0.0.1}\n", "web.address = '127.0.0.1': unknown key"}}) {
    try {
      load_plant_config(plant_with(web));
      ADD_FAILURE() << "loaded " << web;
    } catch (const ConfigError& e) {
      EXPECT_TRUE(names(e.problems(), problem)) << web << "\n" << e.what();
    }
  }
}

TEST(CheckKindTable, OneRowPerKindOfTheWireContractInItsOrder) {
  const std::vector<std::string> idl = idl_check_kinds();
  ASSERT_EQ(idl.size(), static_cast<std::size_t>(kCheckKindCount));
  std::set<std::string_view> tolerance_keys;
  for (int i = 0; i < kCheckKindCount; ++i) {
    const CheckKindInfo& row = check_kinds()[static_cast<std::size_t>(i)];
    EXPECT_EQ(static_cast<int>(row.kind), i);
    EXPECT_EQ(row.name, idl[static_cast<std::size_t>(i)]);
    EXPECT_EQ(to_string(row.kind), row.name);
    EXPECT_EQ(parse_check_kind(row.name), row.kind);
    EXPECT_FALSE(row.title.empty()) << row.name;
    EXPECT_GT(row.duration_min, 0) << row.name;
    EXPECT_FALSE(row.tolerances.empty()) << row.name;
    // A kind re-run after an intervention must be one that can be ordered on its own.
    EXPECT_NE(check_kind_info(rerun_after_intervention(row.kind)).cadence,
              Cadence::AfterCorrection);
    for (auto key : row.tolerances) tolerance_keys.insert(key);
  }
  EXPECT_EQ(to_string(static_cast<CheckKind>(kCheckKindCount)), "unknown");
}

// The example machine configures only tolerance keys of the table, and every key of the table
// that it configures is read by the kind it belongs to (loading it would fail otherwise).
TEST(CheckKindTable, TheExampleMachineLoadsAndItsDefaultCalendarFollowsTheCadences) {
  const MachineConfig m = load_machine_config(kPm1);
  for (const auto& [key, band] : m.tolerances) EXPECT_TRUE(is_tolerance_key(key)) << key;
  const CalendarConfig c = default_calendar_config();
  ASSERT_EQ(c.periods.size(), 3u);
  std::size_t planned = 0;
  for (const auto& period : c.periods) {
    const Cadence cadence = period.unit == PeriodUnit::Month  ? Cadence::Monthly
                            : period.unit == PeriodUnit::Week ? Cadence::Weekly
                                                              : Cadence::Daily;
    for (CheckKind k : period.checks) EXPECT_EQ(check_kind_info(k).cadence, cadence);
    planned += period.checks.size();
  }
  // Every kind but the per-part set points and the post-calibration is in a period.
  EXPECT_EQ(planned, static_cast<std::size_t>(kCheckKindCount) - 2);
  EXPECT_EQ(kinds_passing(CheckKind::FixturePreCalibration),
            (std::vector<CheckKind>{CheckKind::FixturePreCalibration,
                                    CheckKind::FixturePostCalibration}));
  EXPECT_TRUE(
      intervention_matches(CheckKind::FixturePreCalibration, CheckKind::FixturePostCalibration));
  EXPECT_FALSE(intervention_matches(CheckKind::MonumentPositioning, CheckKind::MonumentCAlignment));
}

// docs/architecture.md lists the table for people; it must say what the code says.
TEST(CheckKindTable, TheDocsListEveryRow) {
  std::ifstream in(NCQUAL_SOURCE_DIR "/docs/architecture.md");
  ASSERT_TRUE(in) << "docs/architecture.md is missing";
  // The rows of the table after the marker, up to the blank line that ends it.
  std::vector<std::string> rows;
  std::string line;
  bool in_table = false;
  while (std::getline(in, line)) {
    if (line.find("check-kinds-table") != std::string::npos) in_table = true;
    if (in_table && line.empty()) break;
    if (in_table && line.rfind("| `", 0) == 0) rows.push_back(line);
  }
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(kCheckKindCount));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const CheckKindInfo& row = check_kinds()[i];
    std::string keys;
    for (auto key : row.tolerances) keys += (keys.empty() ? "" : ", ") + std::string(key);
    std::ostringstream minutes;
    minutes << row.duration_min;
    const std::string expected =
        "| `" + std::string(row.name) + "` | " + std::string(to_string(row.cadence)) + " | " +
        std::string(to_string(row.instrument)) + " | " + std::string(to_string(row.needs)) + " | " +
        minutes.str() + " | " + keys + " |";
    EXPECT_EQ(rows[i], expected);
  }
}

}  // namespace
}  // namespace ncqual
