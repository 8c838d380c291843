// SPDX-License-Identifier: Apache-2.0
// The fault campaign: a plant of simulated machines runs two simulated weeks once undisturbed and
// once while its four services are killed (SIGKILL) at random points, alone and in pairs a few
// seconds apart, and restarted 0.2-2 s later. The historian of the disturbed run must hold exactly
// what the undisturbed one holds, compared on an identity that does not depend on the run
// (machine, kind, simulated request time): every request, measurement set, result and status
// change stored once, the same verdicts, the same final states, no conflicts. A second campaign
// runs the plant over a network that loses, duplicates and reorders datagrams (netem, or nftables
// and HTB where the kernel has no netem) in a network namespace of its own, and compares the same.
//
// The size comes from the environment so that deploy/campaign.sh can run a longer one by hand:
// NCQUAL_CAMPAIGN_MACHINES (default 10), NCQUAL_CAMPAIGN_DAYS (14), NCQUAL_CAMPAIGN_KILLS (24),
// NCQUAL_CAMPAIGN_SEED (random; printed, so a failing campaign can be run again); the network one
// NCQUAL_CAMPAIGN_NETWORK_MACHINES (4) and NCQUAL_CAMPAIGN_NETWORK_DAYS (7).
#include "harness.hpp"

#include <gtest/gtest.h>

#include <sched.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <map>
#include <random>
#include <set>

namespace ncqual::testing {
namespace {

int env_int(const char* name, int fallback) {
  const char* text = std::getenv(name);
  if (!text || !*text) return fallback;
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (*end != '\0' || value <= 0 || value > 1000000000L) {
    throw std::invalid_argument(std::string(name) + "='" + text + "' is not a positive integer");
  }
  return static_cast<int>(value);
}

std::string machine_id(int i) {
  char id[16];
  std::snprintf(id, sizeof id, "c%02d", i);
  return id;
}

// Four kinds of machine in turn: pm1 as it is (monument, fixture, laser tracker: the monthly check
// on the first shift), one whose fixture zeros drifted (the fixture loop publishes zero offsets),
// one with a fixture and no tracker, one with the monument only.
std::string machine_file(int i, unsigned seed) {
  const std::string id = machine_id(i);
  std::string yaml = "extends: " + std::string(NCQUAL_SOURCE_DIR) + "/deploy/machines/pm1.yaml\n" +
                     "machine_id: " + id + "\n";
  const unsigned machine_seed = (seed + static_cast<unsigned>(i) * 7919U) % 1000000U;
  switch (i % 4) {
    case 1: yaml += "simulator: {seed: " + std::to_string(machine_seed) + "}\n"; break;
    case 2:
      yaml += "global_check: null\nsimulator:\n  seed: " + std::to_string(machine_seed) +
              "\n  fixture:\n    column_x: {offset_mm: 0.040}\n";
      break;
    case 3:
      yaml += "global_check: null\nsimulator: {seed: " + std::to_string(machine_seed) + "}\n";
      break;
    default:
      yaml +=
          "global_check: null\nfixture: null\nsimulator: {seed: " + std::to_string(machine_seed) +
          ", fixture: null}\n";
  }
  if (i % 4 != 0) yaml += "fixture: {fixture_id: F-" + id + "}\n";
  return yaml;
}

const char* const kScheduler =
    "  calendar:\n"
    "    time_zone: Europe/Berlin\n"
    "    parts: {cycle_min: 240}\n";

// What a historian holds, keyed on identities that do not depend on the run.
struct Snapshot {
  struct Check {
    int records = 0;  // request ids stored for this identity (1 when all is well)
    int requests = 0, measurements = 0, results = 0;
    std::string verdict;
  };
  std::map<std::string, Check> checks;        // "machine|kind|request time" -> what is stored
  std::map<std::string, int> status_changes;  // "machine|time|state|kind|verdict" -> times
  std::map<std::string, std::string> finals;  // machine -> its latest state
  std::size_t conflicts = 0;
  std::int64_t results = 0;
};

Snapshot snapshot(storage::Database& db) {
  Snapshot s;
  storage::HistoryQuery q;
  q.limit = 0;
  for (const auto& r : db.history(q)) {
    if (!r.request) {
      // A result or set without its request cannot be placed by identity: count it under its id.
      auto& c = s.checks["(no request) " + r.request_id];
      ++c.records;
      c.measurements += r.measurement ? 1 : 0;
      c.results += r.result ? 1 : 0;
      continue;
    }
    auto& c = s.checks[r.machine_id + "|" + std::string(to_string(r.kind)) + "|" +
                       std::to_string(r.request->time_ns)];
    ++c.records;
    ++c.requests;
    c.measurements += r.measurement ? 1 : 0;
    c.results += r.result ? 1 : 0;
    if (r.result) c.verdict = to_string(r.result->verdict);
  }
  for (const auto& machine : db.machines()) {
    for (const auto& st : db.status_history(machine)) {
      ++s.status_changes[machine + "|" + std::to_string(st.time_ns) + "|" +
                         std::string(to_string(st.state)) + "|" +
                         (st.last_kind ? std::string(to_string(*st.last_kind)) : "") + "|" +
                         (st.last_verdict ? std::string(to_string(*st.last_verdict)) : "")];
      s.finals[machine] = to_string(st.state);
    }
  }
  s.conflicts = db.conflicts().size();
  s.results = db.count_results();
  return s;
}

// Every check complete and as many results and status changes as `want`.
bool caught_up(storage::Database& db, const Snapshot& want) {
  if (db.count_results() < want.results) return false;
  const Snapshot got = snapshot(db);
  std::size_t statuses = 0;
  for (const auto& [key, n] : got.status_changes) statuses += static_cast<std::size_t>(n);
  if (statuses < want.status_changes.size()) return false;
  for (const auto& [key, c] : got.checks) {
    if (c.requests < 1 || c.measurements < 1 || c.results < 1) return false;
  }
  return true;
}

struct Services {
  Plant& plant;
  std::string days;
  std::string speed;  // the scheduler's --speed; empty: as fast as it goes
  std::vector<std::string> acquisition_lists;
  std::map<std::string, Process*> running;  // "historian", "solver", "scheduler", "acquisition0".

  void start(const std::string& name) {
    if (name == "scheduler") {
      std::vector<std::string> args{"--days", days};
      if (!speed.empty()) args.insert(args.end(), {"--speed", speed});
      running[name] = &plant.start("scheduler", args);
    } else if (name.rfind("acquisition", 0) == 0) {
      const auto k = static_cast<std::size_t>(std::stoi(name.substr(11)));
      running[name] = &plant.start("acquisition", {"--machine", acquisition_lists.at(k)});
    } else {
      running[name] = &plant.start(name);
    }
  }
};

std::string service_of(const std::string& name) {
  return name.rfind("acquisition", 0) == 0 ? "acquisition" : name;
}

// A plant of `machines` campaign machines (machine_file) over `days` simulated days, its five
// processes started; `speed`: the scheduler's --speed (empty: as fast as it goes).
Services set_up(Plant& plant, int machines, int days, unsigned seed, const std::string& speed) {
  Services services{plant, std::to_string(days), speed, {"", ""}, {}};
  for (int i = 1; i <= machines; ++i) {
    plant.add_machine(machine_id(i), machine_file(i, seed));
    auto& list = services.acquisition_lists[i <= (machines + 1) / 2 ? 0 : 1];
    list += (list.empty() ? "" : ",") + machine_id(i);
  }
  plant.write_calendar_plant(kScheduler, "2026-03-02T00:00:00Z");
  for (const char* name : {"historian", "solver", "acquisition0", "acquisition1", "scheduler"}) {
    services.start(name);
  }
  return services;
}

// Waits for the scheduler's run to end and the historian to hold as much as `want` (complete
// checks only, for an undisturbed run: an empty Snapshot), stops the others (they empty their
// outboxes as they stop) and returns what the historian holds.
Snapshot finish(Plant& plant, Services& services, const Snapshot& want,
                std::chrono::seconds patience) {
  Snapshot got;
  EXPECT_EQ(services.running["scheduler"]->wait(), 0) << plant.log("scheduler");
  EXPECT_TRUE(plant.wait_for_db(
      [&](storage::Database& db) { return db.count_results() > 0 && caught_up(db, want); },
      patience))
      << plant.log("historian");
  for (const char* name : {"acquisition0", "acquisition1", "solver", "historian"}) {
    services.running[name]->terminate();
    EXPECT_EQ(services.running[name]->wait(), 0) << name << "\n" << plant.log(service_of(name));
  }
  auto db = storage::Database::open_readonly(plant.db_path());
  return snapshot(db);
}

// How a disturbed run differs from the undisturbed one. Lost: a sample of the reference not
// stored; duplicated: one stored more than once (a second request id for the same check, a second
// status change); extra: stored, not in the reference. Each difference is also a test failure.
struct Tally {
  std::int64_t lost = 0, duplicated = 0, extra = 0, different = 0;
};

Tally compare(const Snapshot& reference, const Snapshot& got) {
  Tally t;
  for (const auto& [key, want] : reference.checks) {
    const auto it = got.checks.find(key);
    const Snapshot::Check none;
    const Snapshot::Check& have = it == got.checks.end() ? none : it->second;
    t.lost += std::max(0, want.requests - have.requests) +
              std::max(0, want.measurements - have.measurements) +
              std::max(0, want.results - have.results);
    t.duplicated += std::max(0, have.records - want.records);
    if (have.records > 0 && have.verdict != want.verdict) {
      ++t.different;
      ADD_FAILURE() << key << ": " << have.verdict << ", undisturbed " << want.verdict;
    }
    if (have.records < want.records) ADD_FAILURE() << "lost: " << key;
    if (have.records > want.records) ADD_FAILURE() << "stored twice: " << key;
  }
  for (const auto& [key, have] : got.checks) {
    if (!reference.checks.count(key)) {
      ++t.extra;
      ADD_FAILURE() << "not in the undisturbed run: " << key;
    }
  }
  for (const auto& [key, n] : reference.status_changes) {
    const auto it = got.status_changes.find(key);
    const int have = it == got.status_changes.end() ? 0 : it->second;
    t.lost += std::max(0, n - have);
    t.duplicated += std::max(0, have - n);
    if (have != n) ADD_FAILURE() << "status change " << key << " stored " << have << " times";
  }
  for (const auto& [key, n] : got.status_changes) {
    if (!reference.status_changes.count(key)) {
      ++t.extra;
      ADD_FAILURE() << "status change not in the undisturbed run: " << key;
    }
  }
  EXPECT_EQ(t.lost, 0);
  EXPECT_EQ(t.duplicated, 0);
  EXPECT_EQ(t.extra, 0);
  EXPECT_EQ(got.conflicts, 0U);
  EXPECT_EQ(got.finals, reference.finals);
  return t;
}

TEST(FaultCampaign, KilledServicesLoseAndDuplicateNothing) {
  const int machines = env_int("NCQUAL_CAMPAIGN_MACHINES", 10);
  const int days = env_int("NCQUAL_CAMPAIGN_DAYS", 14);
  const int kills_wanted = env_int("NCQUAL_CAMPAIGN_KILLS", 24);
  const unsigned seed = static_cast<unsigned>(
      env_int("NCQUAL_CAMPAIGN_SEED", static_cast<int>(std::random_device{}() % 1000000U + 1U)));
  ASSERT_GE(kills_wanted, 12) << "each of the four services is killed at least three times";
  std::cerr << "fault campaign: seed " << seed << " (NCQUAL_CAMPAIGN_SEED), " << machines
            << " machines, " << days << " simulated days, " << kills_wanted << " kills\n";
  SCOPED_TRACE("NCQUAL_CAMPAIGN_SEED=" + std::to_string(seed));

  // The undisturbed run.
  Snapshot reference;
  {
    Plant plant("campaign-ref", TestDomain::CampaignReference);
    Services services = set_up(plant, machines, days, seed, "");
    reference = finish(plant, services, Snapshot{}, std::chrono::seconds(60));
  }
  ASSERT_GT(reference.results, 100) << "the campaign is too short to mean anything";
  EXPECT_EQ(reference.conflicts, 0U);

  // The kill plan: each service at least three times, the rest drawn at random; every third
  // event kills two services a few seconds apart, the first pair being the historian and then
  // the scheduler. That pair is taken out of the draw before the shuffle, so no service loses a
  // kill to it (overwriting a drawn pair once left the solver with two).
  std::mt19937 rng(seed);
  const std::vector<std::string> all = {"historian", "solver", "acquisition", "scheduler"};
  std::vector<std::string> victims;
  for (int k = 0; k < 3; ++k) victims.insert(victims.end(), all.begin(), all.end());
  while (static_cast<int>(victims.size()) < kills_wanted) {
    victims.push_back(all[std::uniform_int_distribution<std::size_t>(0, 3)(rng)]);
  }
  for (const char* s : {"historian", "scheduler"}) {
    victims.erase(std::find(victims.begin(), victims.end(), s));
  }
  std::shuffle(victims.begin(), victims.end(), rng);
  std::vector<std::vector<std::string>> events;
  bool first_pair = true;
  for (std::size_t k = 0; k < victims.size();) {
    if (events.size() % 3 == 1 && first_pair) {
      events.push_back({"historian", "scheduler"});
      first_pair = false;
    } else if (events.size() % 3 == 1 && k + 1 < victims.size() && victims[k] != victims[k + 1]) {
      events.push_back({victims[k], victims[k + 1]});
      k += 2;
    } else {
      events.push_back({victims[k]});
      k += 1;
    }
  }
  std::uniform_int_distribution<int> restart_ms(200, 2000);
  std::uniform_int_distribution<int> pair_gap_ms(200, 3000);

  // The disturbed run is paced (the scheduler's --speed) to last about three wall seconds a kill,
  // time for each to land while there is work; the decisions are the same at any speed.
  const double speed = days * 86400.0 / (3.0 * kills_wanted);
  Plant plant("campaign-kill", TestDomain::CampaignKill);
  Services services = set_up(plant, machines, days, seed, std::to_string(speed));
  std::map<std::string, int> kills;  // per service, of processes that were running
  int pairs = 0;
  const auto n_events = static_cast<std::int64_t>(events.size());
  for (std::int64_t e = 0; e < n_events; ++e) {
    // A point in the run: a share of the reference's results, spread over its first nine tenths
    // with some jitter, so every kill lands while the scheduler still has work.
    const std::int64_t slot = reference.results * 9 / 10 / (n_events + 1);
    const std::int64_t at =
        slot * (e + 1) + std::uniform_int_distribution<std::int64_t>(-slot / 3, slot / 3)(rng);
    std::int64_t seen = 0;
    ASSERT_TRUE(
        plant.wait_for_db([&](storage::Database& db) { return (seen = db.count_results()) >= at; },
                          std::chrono::seconds(120)))
        << "waiting for " << at << " results, " << seen << " stored\n"
        << plant.log("scheduler");
    std::vector<std::string> killed;
    for (std::size_t v = 0; v < events[e].size(); ++v) {
      std::string name = events[e][v];
      if (name == "acquisition") {
        name += std::to_string(std::uniform_int_distribution<int>(0, 1)(rng));
      }
      if (v > 0) {
        // The second of a pair: a few seconds after the first, while it is still down. The pause
        // is the fault being injected, not a wait for anything.
        std::this_thread::sleep_for(std::chrono::milliseconds(pair_gap_ms(rng)));
      }
      Process* p = services.running[name];
      if (!p->running()) continue;  // e.g. the scheduler at the end of its run
      p->kill();
      p->wait();
      ++kills[service_of(name)];
      killed.push_back(name);
      std::cerr << "kill " << name << " at " << seen << " results\n";
    }
    if (killed.size() == 2) ++pairs;
    for (const auto& name : killed) {
      std::this_thread::sleep_for(std::chrono::milliseconds(restart_ms(rng)));
      services.start(name);
    }
  }
  const Snapshot got = finish(plant, services, reference, std::chrono::seconds(180));
  const Tally t = compare(reference, got);
  int total_kills = 0;
  for (const auto& [service, n] : kills) total_kills += n;
  std::cout << "checks " << reference.checks.size() << ", kills " << total_kills << ", lost "
            << t.lost << ", duplicated " << t.duplicated << ", conflicts " << got.conflicts << "\n"
            << "(extra " << t.extra << ", different verdicts " << t.different << ", kill pairs "
            << pairs << "; historian " << kills["historian"] << ", solver " << kills["solver"]
            << ", acquisition " << kills["acquisition"] << ", scheduler " << kills["scheduler"]
            << "; seed " << seed << ")\n";
  EXPECT_GE(total_kills, 20);
  for (const auto& service : all) {
    EXPECT_GE(kills[service], 3) << service << " was not killed often enough while running";
  }
  EXPECT_GE(pairs, 2);
}

// The network made bad on purpose, inside a network namespace of this test's own (its services
// inherit it, so nothing else on the machine is touched). netem where the kernel has it (loss,
// duplication, reordering); else the same from nftables and HTB: 5 % of datagrams dropped and 5 %
// duplicated as they arrive, 20 % sent through a slow lane so that later ones overtake them.
// Returns what was set up, or why it could not be (the test is then skipped, saying so).
struct Impairment {
  std::string how;  // what was set up
  std::string why;  // why it could not be, when `how` is empty
  bool netem = false;
};

Outcome sh(const std::string& command) {
  return run(Launch({"sh", "-c", command}, Output::Merged));
}

// The namespace's loopback up and multicast (for DDS discovery); empty, or why not.
std::string bring_up_loopback() {
  const Outcome up = sh("ip link set lo up && ip link set lo multicast on");
  return up.exit_code == 0 ? "" : "`ip link set lo up` failed: " + up.out;
}

Impairment impair_loopback() {
  Impairment imp;
  const Outcome netem =
      sh("tc qdisc add dev lo root netem loss 5% duplicate 5% delay 2ms reorder 75% 50% 2>&1");
  if (netem.exit_code == 0) {
    imp.netem = true;
    imp.how = "tc netem: loss 5%, duplicate 5%, delay 2 ms with 25% sent at once (reordered)";
    return imp;
  }
  const Outcome nft = sh(
      "tc qdisc add dev lo root handle 1: htb default 10 && "
      "tc class add dev lo parent 1: classid 1:10 htb rate 1gbit quantum 1514 && "
      "tc class add dev lo parent 1: classid 1:20 htb rate 2mbit burst 2k cburst 2k && "
      "nft add table inet ncqual_impair && "
      "nft add chain inet ncqual_impair out '{ type filter hook output priority 0; }' && "
      "nft add rule inet ncqual_impair out meta l4proto udp numgen random mod 100 '<' 20 "
      "counter meta priority set 1:20 && "
      "nft add table netdev ncqual_impair && "
      "nft add chain netdev ncqual_impair in '{ type filter hook ingress device lo priority 0; }' "
      "&& nft add rule netdev ncqual_impair in meta l4proto udp numgen random mod 100 '<' 5 "
      "counter drop && "
      "nft add rule netdev ncqual_impair in meta l4proto udp numgen random mod 100 '<' 5 "
      "counter dup to lo");
  if (nft.exit_code != 0) {
    imp.why = "netem is not available (" + netem.out.substr(0, netem.out.find('\n')) +
              ") and neither are nftables with HTB (" + nft.out +
              "): install nftables, or run on a kernel with sch_netem";
    return imp;
  }
  imp.how =
      "nftables + HTB (this kernel has no sch_netem): 5% of UDP datagrams dropped, 5% duplicated, "
      "20% through a 2 Mbit/s lane that later ones overtake";
  return imp;
}

// What the impairment did: netem's or nftables' counters.
std::string impairment_counters(const Impairment& imp) {
  if (imp.netem) return sh("tc -s qdisc show dev lo").out;
  return sh("nft list ruleset | grep counter; tc -s class show dev lo | grep -A1 '1:20'").out;
}

// Loss, duplication and reordering between the services change nothing stored: the reliable DDS
// protocol repairs what it can, the outboxes resend what is not acknowledged, the historian
// stores a duplicate once. Compared with an undisturbed run on the same (namespaced) loopback.
TEST(FaultCampaign, ALossyDuplicatingReorderingNetworkChangesNothingStored) {
  const int machines = env_int("NCQUAL_CAMPAIGN_NETWORK_MACHINES", 4);
  const int days = env_int("NCQUAL_CAMPAIGN_NETWORK_DAYS", 7);
  const unsigned seed = static_cast<unsigned>(
      env_int("NCQUAL_CAMPAIGN_SEED", static_cast<int>(std::random_device{}() % 1000000U + 1U)));
  SCOPED_TRACE("NCQUAL_CAMPAIGN_SEED=" + std::to_string(seed));
  if (unshare(CLONE_NEWNET) != 0) {
    GTEST_SKIP() << "cannot make a network namespace (unshare(CLONE_NEWNET): "
                 << std::strerror(errno) << "); run as root or where user namespaces are allowed";
  }
  if (const std::string why = bring_up_loopback(); !why.empty()) GTEST_SKIP() << why;

  Snapshot reference;
  {
    Plant plant("network-ref", TestDomain::NetworkReference);
    Services services = set_up(plant, machines, days, seed, "");
    reference = finish(plant, services, Snapshot{}, std::chrono::seconds(60));
  }
  ASSERT_GT(reference.results, 20) << "the run is too short to mean anything";

  const Impairment imp = impair_loopback();
  if (imp.how.empty()) GTEST_SKIP() << imp.why;
  std::cerr << "network: " << imp.how << "\n";
  Plant plant("network-bad", TestDomain::NetworkImpaired);
  Services services = set_up(plant, machines, days, seed, "");
  const Snapshot got = finish(plant, services, reference, std::chrono::seconds(240));
  const std::string counters = impairment_counters(imp);
  const Tally t = compare(reference, got);
  std::cout << "checks " << reference.checks.size() << ", network " << (imp.netem ? "netem" : "nft")
            << ", lost " << t.lost << ", duplicated " << t.duplicated << ", conflicts "
            << got.conflicts << " (extra " << t.extra << ", different verdicts " << t.different
            << "; seed " << seed << ")\n"
            << counters;
  // The network was bad: datagrams were dropped and duplicated (no counter stayed at zero).
  EXPECT_EQ(counters.find(imp.netem ? "dropped 0," : "packets 0 "), std::string::npos) << counters;
}

}  // namespace
}  // namespace ncqual::testing
