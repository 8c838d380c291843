// SPDX-License-Identifier: Apache-2.0
// A plant of separate hosts: each host a network namespace of its own, joined by veth pairs to a
// bridge (in a namespace of its own too, so nothing of the machine's own network is touched), no
// multicast anywhere, discovery through a discovery server on a host of its own
// (deploy/qos/discovery-server.xml, network: {discovery: server} in the plant config).
//
//   10.231.7.10  ds    fast-discovery-server -i 0 (BACKUP: it keeps what it learnt on disk)
//   10.231.7.11  srv   ncqual-historian, ncqual-solver, ncqual-scheduler
//   10.231.7.21  m1    ncqual-acquisition (beside the machine's control)
//   10.231.7.31  op    the operator station: `ncqual check`
//
// Where namespaces cannot be made (not root, no `ip`), the test is skipped and says why.
//
// The same hosts, secured (docs/deploy.md, "A secured plant of several hosts"): ncqual-pki's
// plant CA and identities, discovery by peers (the discovery server is not secured in Fast DDS
// 2.9), each host holding the material it needs.
#include "harness.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace ncqual::testing {
namespace {

Outcome sh(const std::string& command) {
  return run(Launch({"sh", "-c", command}, Output::Merged));
}

// The namespaces and their links; removed again when it goes (the processes in them first:
// declare it before the Plant and the Processes).
class Lan {
 public:
  struct Host {
    std::string name;  // the namespace's
    std::string address;
  };

  // Empty why() when every host is up.
  Lan() {
    const std::string tag = "nq" + std::to_string(getpid() % 100000);
    bridge_ = tag + "-lan";
    for (const auto& [short_name, address] :
         std::vector<std::pair<std::string, std::string>>{{"ds", "10.231.7.10"},
                                                          {"srv", "10.231.7.11"},
                                                          {"m1", "10.231.7.21"},
                                                          {"op", "10.231.7.31"}}) {
      hosts_.push_back({tag + "-" + short_name, address});
    }
    std::string script = "set -e; ip netns add " + bridge_ + "; ip -n " + bridge_ +
                         " link add br0 type bridge; ip -n " + bridge_ + " link set br0 up; ";
    int n = 0;
    for (const Host& h : hosts_) {
      const std::string port = "v" + std::to_string(n++);
      script += "ip netns add " + h.name + "; ip -n " + bridge_ + " link add " + port +
                " type veth peer name eth0 netns " + h.name + "; ip -n " + bridge_ + " link set " +
                port + " master br0 up; ip -n " + h.name + " addr add " + h.address +
                "/24 dev eth0; ip -n " + h.name + " link set eth0 multicast off up; ip -n " +
                h.name + " link set lo up; ";
    }
    const Outcome made = sh(script);
    if (made.exit_code != 0) why_ = "cannot make network namespaces with `ip netns`: " + made.out;
  }
  ~Lan() {
    std::string script = "ip netns del " + bridge_ + " 2>/dev/null; ";
    for (const Host& h : hosts_) script += "ip netns del " + h.name + " 2>/dev/null; ";
    sh(script);
  }
  Lan(const Lan&) = delete;
  Lan& operator=(const Lan&) = delete;

  const std::string& why() const { return why_; }
  const Host& host(std::size_t i) const { return hosts_.at(i); }
  // The launcher that runs a program on host `i`.
  std::vector<std::string> on(std::size_t i) const {
    return {"ip", "netns", "exec", hosts_.at(i).name};
  }

 private:
  std::string bridge_;
  std::vector<Host> hosts_;
  std::string why_;
};

enum HostIndex : std::size_t { kDs = 0, kSrv = 1, kM1 = 2, kOp = 3 };

// `ncqual check` from the operator's station: the request id it printed, or "" (and `out` says
// why) when no scheduler acknowledged it.
std::string check_from(const Lan& lan, const std::string& plant_file, std::string& out,
                       const std::vector<std::string>& extra = {}) {
  std::vector<std::string> argv = lan.on(kOp);
  for (const char* a :
       {NCQUAL_CLI_EXE, "check", "--machine", "m1", "--kind", "monument_positioning", "--plant"}) {
    argv.emplace_back(a);
  }
  argv.push_back(plant_file);
  argv.insert(argv.end(), extra.begin(), extra.end());
  const Outcome o = run(Launch(argv));
  out = "exit " + std::to_string(o.exit_code) + ": " + o.out + o.err;
  if (o.exit_code != 0) return "";
  return o.out.substr(0, o.out.find('\n'));
}

bool passed(storage::Database& db, const std::string& request_id) {
  const auto rec = db.find_check(request_id);
  return rec && rec->result && rec->result->verdict == Verdict::Pass;
}

TEST(PlantNetwork, HostsWithoutMulticastQualifyThroughADiscoveryServerThatRestarts) {
  Lan lan;
  if (!lan.why().empty()) GTEST_SKIP() << lan.why();
  Plant plant("plant-network", TestDomain::PlantNetwork);
  plant.add_machine("m1", machine_yaml("m1", "    machine_shift_mm: [0.002, 0, 0]\n"));
  const std::string server = lan.host(kDs).address + ":11811";
  plant.write_plant_with("network:\n  discovery: server\n  servers: [" + server + "]\n");
  // The same plant, discovering by multicast: the control that shows there is none.
  const std::string multicast_plant = plant.write_plant_with("", "[]", "multicast.yaml");

  // The discovery server, in the plant's directory (its backup files go there).
  const auto start_server = [&] {
    std::vector<std::string> argv = lan.on(kDs);
    for (const std::string& a :
         {std::string("fast-discovery-server"), std::string("-i"), std::string("0"),
          std::string("-l"), lan.host(kDs).address, std::string("-p"), std::string("11811"),
          std::string("-x"), std::string(NCQUAL_SOURCE_DIR) + "/deploy/qos/discovery-server.xml"}) {
      argv.push_back(a);
    }
    return std::make_unique<Process>(
        Launch(argv).in(plant.dir().string()).log_to((plant.dir() / "discovery.log").string()));
  };
  auto discovery = start_server();
  plant.start_through(lan.on(kSrv), "historian");
  plant.start_through(lan.on(kSrv), "solver");
  plant.start_through(lan.on(kSrv), "scheduler");
  plant.start_through(lan.on(kM1), "acquisition", {"--machine", "m1"});

  // The scheduler's start-up check crosses from srv to m1 and back.
  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) { return db.count_results() >= 1; }))
      << plant.log("scheduler") << plant.log("acquisition") << plant.log("discovery");

  // An operator's check from a fourth host.
  std::string out;
  const std::string first = check_from(lan, plant.plant_file(), out);
  ASSERT_FALSE(first.empty()) << out;
  ASSERT_TRUE(plant.wait_for_db([&](storage::Database& db) { return passed(db, first); }))
      << first << "\n"
      << plant.log("solver");

  // No multicast between the hosts: the same station discovering by multicast finds no one.
  const std::string unheard = check_from(lan, multicast_plant, out);
  EXPECT_TRUE(unheard.empty()) << "a check went through without a discovery server: " << unheard;
  EXPECT_NE(out.find("no scheduler acknowledged"), std::string::npos) << out;

  // The discovery server dies and is started again; a participant that was not there before
  // (the next `ncqual check`) finds the plant through the restarted one.
  discovery->kill();
  discovery->wait();
  discovery = start_server();
  std::string second;
  int attempts = 0;
  while (second.empty() && attempts++ < 3) {
    second = check_from(lan, plant.plant_file(), out);  // each attempt waits up to 15 s
  }
  ASSERT_FALSE(second.empty()) << "no check after the discovery server restarted: " << out
                               << plant.log("discovery");
  ASSERT_TRUE(plant.wait_for_db([&](storage::Database& db) { return passed(db, second); }))
      << second << "\n"
      << plant.log("solver");
  std::cout << "checks through the discovery server: " << first << " before its restart, " << second
            << " after (attempt " << attempts << ")\n";
}

TEST(PlantNetwork, ASecuredPlantOfHostsQualifiesByPeersAndNamesWhoWroteEachPart) {
  Lan lan;
  if (!lan.why().empty()) GTEST_SKIP() << lan.why();
  Plant plant("plant-network-secured", TestDomain::PlantNetworkSecured);
  plant.add_machine("m1", machine_yaml("m1", "    machine_shift_mm: [0.002, 0, 0]\n"));
  plant.write_plant();  // ncqual-pki reads the plant's machines from it
  const std::string pki = (plant.dir() / "pki").string();
  const Outcome made =
      ncqual_pki({"init", "--plant", plant.plant_file(), "--out", pki, "--operator", "station1"});
  ASSERT_EQ(made.exit_code, 0) << made.out;
  // Every ncqual host's address, none of the discovery server's (it has no part here).
  plant.write_plant_with("security: {dir: " + pki + "}\nnetwork:\n  discovery: peers\n  peers: [" +
                         lan.host(kSrv).address + ", " + lan.host(kM1).address + ", " +
                         lan.host(kOp).address + "]\n");
  plant.start_through(lan.on(kSrv), "historian");
  plant.start_through(lan.on(kSrv), "solver");
  plant.start_through(lan.on(kSrv), "scheduler");
  plant.start_through(lan.on(kM1), "acquisition", {"--machine", "m1"});

  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) { return db.count_results() >= 1; }))
      << plant.log("scheduler") << plant.log("acquisition");
  std::string out;
  const std::string ordered =
      check_from(lan, plant.plant_file(), out, {"--identity", "operator-station1"});
  ASSERT_FALSE(ordered.empty()) << out;
  ASSERT_TRUE(plant.wait_for_db([&](storage::Database& db) { return passed(db, ordered); }))
      << ordered << "\n"
      << plant.log("solver");

  // Who wrote each part of the operator's check, from the GUIDs the historian stored. The result
  // (from the solver, on the historian's host) may be stored before the set (from m1's host):
  // wait for both.
  ASSERT_TRUE(plant.wait_for_db([&](storage::Database& db) {
    const auto rec = db.find_check(ordered);
    return rec && rec->request && rec->measurement && rec->result;
  })) << plant.log("historian");
  const Outcome history = run(
      Launch({NCQUAL_CLI_EXE, "history", "--json", "--plant", plant.plant_file(), "--limit", "0"}));
  ASSERT_EQ(history.exit_code, 0) << history.err;
  bool found = false;
  for (const auto& r : nlohmann::json::parse(history.out)) {
    if (r.at("request_id") != ordered) continue;
    found = true;
    const auto& w = r.at("writers");
    EXPECT_EQ(w.at("request").value("identity", ""), "scheduler") << r.dump();
    EXPECT_EQ(w.at("measurement").value("identity", ""), "acquisition-m1") << r.dump();
    EXPECT_EQ(w.at("result").value("identity", ""), "solver") << r.dump();
  }
  EXPECT_TRUE(found) << ordered << " not in\n" << history.out;

  // What listens where (docs/deploy.md): the services bind their UDP sockets to their host's
  // address among the plant's peers, none to every interface (0.0.0.0).
  const Outcome sockets = sh("ip netns exec " + lan.host(kSrv).name + " ss -H -u -l -n -p");
  int ours = 0;
  std::stringstream lines(sockets.out);
  for (std::string line; std::getline(lines, line);) {
    if (line.find("ncqual-") == std::string::npos) continue;
    ++ours;
    // State, Recv-Q, Send-Q, then the local address:port.
    std::stringstream fields(line);
    std::string state, recv_q, send_q, local;
    fields >> state >> recv_q >> send_q >> local;
    EXPECT_EQ(local.rfind(lan.host(kSrv).address + ":", 0), 0u)
        << "not bound to the host's plant address: " << line;
  }
  EXPECT_GE(ours, 6) << sockets.out;  // historian, solver, scheduler: metatraffic and user data
  EXPECT_NE(plant.log("historian").find("listening on " + lan.host(kSrv).address + " only"),
            std::string::npos);
}

}  // namespace
}  // namespace ncqual::testing
