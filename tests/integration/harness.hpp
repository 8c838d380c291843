// SPDX-License-Identifier: Apache-2.0
// Test harness for multi-process tests: starts the real ncqual executables on a private DDS
// domain with a plant config in a temporary directory, and waits on the historian's database.
#pragma once

#include "domains.hpp"
#include "process.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/storage/database.hpp"

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <cstdlib>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace ncqual::testing {

namespace fs = std::filesystem;

// deploy/security/ncqual-pki with `args` (init, add, revoke, ...), as a plant's administrator
// runs it; its output merged.
inline Outcome ncqual_pki(const std::vector<std::string>& args) {
  std::vector<std::string> argv{std::string(NCQUAL_SOURCE_DIR) + "/deploy/security/ncqual-pki"};
  argv.insert(argv.end(), args.begin(), args.end());
  return run(Launch(argv, Output::Merged).with_env("NCQUAL_CLI", NCQUAL_CLI_EXE));
}

// The one flag that runs the integration tests on a secured plant: NCQUAL_TEST_SECURITY=1 (not
// empty, not 0). A Plant whose test writes no security: or network: section of its own is then
// secured as a plant's administrator secures one (docs/deploy.md): ncqual-pki init from the
// plant's machines with an operator station named after this host (the CLI's default identity,
// operator-<host>), the plant's security: section, and discovery by peers on 127.0.0.1 (Fast DDS
// 2.9 and multicast: participant.cpp). Services and `ncqual` runs take it from the plant file;
// an acquisition of several machines gets an identity of its group (--identity). ctest runs a
// set of tests this way too (tests/integration/CMakeLists.txt, label "secured").
inline bool tests_secured() {
  const char* flag = std::getenv("NCQUAL_TEST_SECURITY");
  return flag && *flag && std::string(flag) != "0";
}

// A private plant: a temporary directory, a domain id of its own, machine configs, and the
// four services.
class Plant {
 public:
  static constexpr const char* kRigIdentity = "rig-tests";

  // Every test passes its own domain (tests/integration/domains.hpp allocates them), so tests
  // that ctest runs in parallel never hear each other.
  Plant(const std::string& name, TestDomain domain) : domain_(domain_id(domain)) {
    std::random_device rd;
    dir_ = fs::temp_directory_path() / ("ncqual-it-" + name + "-" + std::to_string(getpid()) + "-" +
                                        std::to_string(rd() % 100000));
    fs::create_directories(dir_);
  }
  ~Plant() {
    processes_.clear();
    if (!std::getenv("NCQUAL_KEEP_TEST_DIRS")) {
      std::error_code ec;
      fs::remove_all(dir_, ec);
    }
  }

  // Writes a machine config with the given YAML text and adds it to the plant.
  std::string add_machine(const std::string& machine_id, const std::string& yaml) {
    const auto path = dir_ / (machine_id + ".yaml");
    std::ofstream(path) << yaml;
    machines_.push_back(path.string());
    return path.string();
  }

  std::string write_plant(const std::string& startup_checks = "[monument_positioning]") {
    return write_plant_file("scheduler:\n  startup_checks: " + startup_checks + "\n");
  }
  // As write_plant, with `sections` (top-level YAML, e.g. a network: section) before the
  // scheduler's, into `file_name` in the plant's directory (plant.yaml: the plant's own file).
  std::string write_plant_with(const std::string& sections,
                               const std::string& startup_checks = "[monument_positioning]",
                               const std::string& file_name = "plant.yaml") {
    return write_plant_file(sections + "scheduler:\n  startup_checks: " + startup_checks + "\n",
                            file_name);
  }

  // A plant on the simulated clock with a calendar: `scheduler_yaml` is the body of the
  // scheduler: section (indented two spaces), the clock starts at `start` (ISO 8601 UTC).
  std::string write_calendar_plant(const std::string& scheduler_yaml, const std::string& start) {
    return write_plant_file("clock: {mode: simulated, start: \"" + start + "\"}\nscheduler:\n" +
                            scheduler_yaml);
  }

  // The QoS lines of the plant files written from now on (default: the project's profiles).
  void set_qos_lines(std::string lines) { qos_lines_ = std::move(lines); }

  // Starts a service of the plant; stdout and stderr are appended to <service>.log in the
  // plant's directory (several instances of one service share the file).
  Process& start(const std::string& service, const std::vector<std::string>& extra = {}) {
    return start_through({}, service, extra);
  }
  // As start, through a launcher that runs its remaining arguments, e.g. {"ip", "netns", "exec",
  // "host1"} (it must exec the service, so that the Process is the service itself).
  Process& start_through(const std::vector<std::string>& launcher, const std::string& service,
                         const std::vector<std::string>& extra = {}) {
    std::vector<std::string> argv = launcher;
    for (const std::string& a : {executable(service), std::string("--plant"), plant_file_,
                                 std::string("--log-level"), std::string("debug")}) {
      argv.push_back(a);
    }
    argv.insert(argv.end(), extra.begin(), extra.end());
    if (!pki_.empty() && service == "acquisition") {
      const std::string group = group_identity(extra);
      if (!group.empty()) {
        argv.push_back("--identity");
        argv.push_back(group);
      }
    }
    processes_.push_back(
        std::make_unique<Process>(Launch(argv).log_to((dir_ / (service + ".log")).string())));
    return *processes_.back();
  }

  static std::string executable(const std::string& service) {
    if (service == "historian") return NCQUAL_HISTORIAN_EXE;
    if (service == "solver") return NCQUAL_SOLVER_EXE;
    if (service == "acquisition") return NCQUAL_ACQUISITION_EXE;
    if (service == "scheduler") return NCQUAL_SCHEDULER_EXE;
    return NCQUAL_CLI_EXE;
  }

  // The identity of the test's own participant (test_participant.hpp): a rig's on a plant
  // tests_secured() secured, else none.
  std::string test_identity() const { return pki_.empty() ? "" : kRigIdentity; }

  std::string db_path() const { return (dir_ / "historian.db").string(); }
  const fs::path& dir() const { return dir_; }
  int domain() const { return domain_; }
  const std::string& plant_file() const { return plant_file_; }

  // Looks again until `done` holds or the timeout passes (what a service did, in a file).
  static bool wait_for(const std::function<bool()>& done,
                       std::chrono::seconds timeout = std::chrono::seconds(60)) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      if (done()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
  }

  // Re-reads the database until `done` holds or the timeout passes. The historian's commit is
  // the event waited for; there is no fixed sleep.
  bool wait_for_db(const std::function<bool(storage::Database&)>& done,
                   std::chrono::seconds timeout = std::chrono::seconds(60)) {
    return wait_for(
        [&] {
          if (!fs::exists(db_path())) return false;
          try {
            auto db = storage::Database::open_readonly(db_path());
            return done(db);
          } catch (const std::exception&) {
            return false;  // the historian may be creating the schema right now; look again
          }
        },
        timeout);
  }

  std::string log(const std::string& service) const {
    std::ifstream in(dir_ / (service + ".log"));
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

 private:
  // plant.yaml: the plant's name, domain, QoS and historian, `sections`, then the machines.
  std::string write_plant_file(const std::string& sections,
                               const std::string& file_name = "plant.yaml") {
    const auto path = dir_ / file_name;
    write_plant_text(path, sections);
    if (file_name != "plant.yaml") return path.string();  // another plant file, for a client
    plant_file_ = path.string();
    if (tests_secured() && sections.find("security:") == std::string::npos &&
        sections.find("network:") == std::string::npos) {
      // ncqual-pki reads the machines from the plant as written; then the plant again, secured.
      const std::string pki = (dir_ / "harness-pki").string();
      char host[256] = {};
      gethostname(host, sizeof host - 1);
      const Outcome made =
          ncqual_pki({"init", "--demo", "--plant", plant_file_, "--out", pki, "--operator", host});
      if (made.exit_code != 0) throw std::runtime_error("ncqual-pki init failed:\n" + made.out);
      if (!fs::exists(fs::path(pki) / "identities" / kRigIdentity)) {
        const Outcome rig =
            ncqual_pki({"add", "--demo", "--out", pki, "--role", "rig", "--name", kRigIdentity});
        if (rig.exit_code != 0) throw std::runtime_error("ncqual-pki add failed:\n" + rig.out);
      }
      write_plant_text(path, sections + "security: {dir: " + pki +
                                 "}\nnetwork: {discovery: peers, peers: [127.0.0.1]}\n");
      pki_ = pki;
    }
    return plant_file_;
  }

  void write_plant_text(const fs::path& path, const std::string& sections) const {
    std::ofstream out(path);
    out << "plant: test-plant\n"
        << "domain_id: " << domain_ << "\n"
        << "simulated: true\n"  // the machines without an instrument: section
        << qos_lines_ << "historian:\n  database: " << db_path() << "\n"
        << sections << "machines:\n";
    for (const auto& m : machines_) out << "  - " << m << "\n";
  }

  // On a secured plant, the identity of an acquisition started with `extra` when it serves more
  // than one machine (--all, --machine a,b), made with ncqual-pki add the first time; "" when
  // it serves one (its identity is acquisition-<id>) or names its own.
  std::string group_identity(const std::vector<std::string>& extra) const {
    std::vector<std::string> ids;
    for (std::size_t k = 0; k < extra.size(); ++k) {
      if (extra[k] == "--identity") return "";
      if (extra[k] == "--all") {
        for (const auto& m : machines_) ids.push_back(fs::path(m).stem().string());
      }
      if (extra[k] == "--machine" && k + 1 < extra.size()) {
        std::stringstream list(extra[k + 1]);
        for (std::string id; std::getline(list, id, ',');) ids.push_back(id);
      }
    }
    if (ids.size() < 2) return "";
    std::string joined;
    for (const auto& id : ids) joined += (joined.empty() ? "" : ",") + id;
    // A certificate's CN has at most 64 characters: the group is named by a hash of its ids.
    const std::string name =
        "acquisition-group-" + std::to_string(std::hash<std::string>{}(joined) % 1000000);
    if (!fs::exists(fs::path(pki_) / "identities" / name)) {
      const Outcome added = ncqual_pki(
          {"add", "--out", pki_, "--role", "acquisition", "--name", name, "--machines", joined});
      if (added.exit_code != 0) throw std::runtime_error("ncqual-pki add failed:\n" + added.out);
    }
    return name;
  }

  fs::path dir_;
  std::string qos_lines_ =
      std::string("qos_profiles: ") + NCQUAL_SOURCE_DIR + "/deploy/qos/ncqual-qos.xml\n";
  int domain_ = 0;
  std::string plant_file_;
  std::string pki_;  // the plant's security material when tests_secured() secured it
  std::vector<std::string> machines_;
  std::vector<std::unique_ptr<Process>> processes_;
};

// A machine config for tests: nominal geometry of deploy/machines/pm1.yaml with the given
// simulator errors section (YAML lines, indented under `errors:`).
inline std::string machine_yaml(const std::string& machine_id, const std::string& errors,
                                int seed = 7) {
  return "machine_id: " + machine_id +
         "\n"
         "probe:\n  tool_length_mm: 350.0\n  ball_radius_mm: 3.0\n"
         "monument:\n  hole_center_mm: [1200.0, 800.0]\n  hole_diameter_mm: 50.0\n"
         "  face_z_mm: 150.0\n  probe_depth_mm: 5.0\n  gauge_width_mm: 200.0\n"
         "tolerances:\n  center_dx_mm: 0.025\n  center_dy_mm: 0.025\n  face_dz_mm: 0.025\n"
         "simulator:\n  seed: " +
         std::to_string(seed) + "\n  trigger_noise_sigma_mm: 0.001\n  errors:\n" + errors;
}

}  // namespace ncqual::testing
