// SPDX-License-Identifier: Apache-2.0
// Another vendor's DDS against the real services: ncqual-cyclone-peer (tests/interop/cyclone),
// a C program on Eclipse Cyclone DDS 0.10 whose types Cyclone's idlc generated from
// idl/ncqual.idl, runs as a process of its own beside a plant of two machines. It reads every
// topic, and what it printed must equal, field by field and every double bit for bit, what the
// historian stored (decoded by Fast DDS's generated code, then SQLite): two decoders of the same
// bytes that share no code. It orders a check and records the intervention that re-arms a held
// machine, and the historian must show both carried out. docs/integrators.md is the guide.
#include "harness.hpp"
#include "test_participant.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/dds/acknowledged_send.hpp"
#include "ncqual/dds/endpoint.hpp"
#include "ncqual/dds/topics.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#ifndef NCQUAL_CYCLONE_PEER_EXE
// tests/interop/cyclone/CMakeLists.txt builds it only where find_package(CycloneDDS) succeeds.
#define NCQUAL_CYCLONE_PEER_EXE ""
#endif

namespace ncqual::testing {
namespace {

using nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Running the peer

class CyclonePeer {
 public:
  explicit CyclonePeer(const Plant& plant)
      : domain_(std::to_string(plant.domain())),
        // Cyclone's defaults (its interface, SPDP multicast: the plant's `discovery: multicast`),
        // with its warnings in a log of the plant's directory.
        config_("<CycloneDDS><Domain><Tracing><Verbosity>warning</Verbosity><OutputFile>" +
                (plant.dir() / "cyclone.log").string() +
                "</OutputFile></Tracing></Domain></CycloneDDS>") {}

  Launch launch(const std::string& mode, const std::vector<std::string>& args) const {
    std::vector<std::string> argv{NCQUAL_CYCLONE_PEER_EXE, mode, "--domain", domain_};
    argv.insert(argv.end(), args.begin(), args.end());
    return Launch(argv).with_env("CYCLONEDDS_URI", config_);
  }
  Outcome run(const std::string& mode, const std::vector<std::string>& args) const {
    return testing::run(launch(mode, args));
  }
  // `count` distinct samples of `topic`, one JSON line each.
  Outcome read(const std::string& topic, std::size_t count) const {
    return run("read", {"--topic", topic, "--count", std::to_string(count), "--timeout", "60"});
  }

 private:
  std::string domain_;
  std::string config_;
};

std::vector<json> json_lines(const std::string& text) {
  std::vector<json> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) lines.push_back(json::parse(line));
  }
  return lines;
}

// ---------------------------------------------------------------------------------------------
// What the peer must print for a sample the historian stored: the IDL's members, enums by their
// IDL names, a non-finite double as a string.

std::string upper(std::string_view name) {
  std::string out(name);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}
std::string idl(CheckKind k) { return upper(to_string(k)); }
std::string idl(Verdict v) { return "VERDICT_" + std::string(to_string(v)); }
std::string idl(MachineState s) { return "STATE_" + std::string(to_string(s)); }
std::string idl(AlarmKind k) { return "ALARM_" + std::string(to_string(k)); }
std::string idl(DataOrigin o) { return "ORIGIN_" + upper(to_string(o)); }

json number(double v) {
  if (std::isnan(v)) return "NaN";
  if (std::isinf(v)) return v > 0 ? "Infinity" : "-Infinity";
  return v;
}
json values(const std::vector<NamedValue>& vs) {
  json out = json::array();
  for (const auto& v : vs)
    out.push_back({{"name", v.name}, {"value", number(v.value)}, {"unit", v.unit}});
  return out;
}
json axes(const AxisPosition& a) {
  return {{"x_mm", number(a.x_mm)}, {"y_mm", number(a.y_mm)},   {"z_mm", number(a.z_mm)},
          {"w_mm", number(a.w_mm)}, {"a_rad", number(a.a_rad)}, {"c_rad", number(a.c_rad)}};
}
json vector3(const Eigen::Vector3d& v) {
  return {{"x", number(v.x())}, {"y", number(v.y())}, {"z", number(v.z())}};
}
json correction(const std::optional<Correction>& c) {
  return {{"target", c ? c->target : ""},
          {"offsets", values(c ? c->offsets : std::vector<NamedValue>{})}};
}

json expected(const CheckRequest& r) {
  return {{"machine_id", r.machine_id},
          {"request_id", r.request_id},
          {"kind", idl(r.kind)},
          {"requested_by", r.requested_by},
          {"time_ns", r.time_ns},
          {"attempt", r.attempt},
          {"parameters", values(r.parameters)},
          {"verifies_correction_of", r.verifies_correction_of}};
}
json expected(const CheckCommand& c) {
  return {{"machine_id", c.machine_id}, {"request_id", c.request_id},
          {"kind", idl(c.kind)},        {"requested_by", c.requested_by},
          {"time_ns", c.time_ns},       {"parameters", values(c.parameters)}};
}
json expected(const MeasurementSet& m) {
  json touches = json::array();
  for (const auto& t : m.touches) {
    touches.push_back(
        {{"feature", t.feature}, {"axes", axes(t.axes)}, {"approach", vector3(t.approach)}});
  }
  json points = json::array();
  for (const auto& p : m.tracker_points) {
    points.push_back({{"label", p.label},
                      {"commanded", axes(p.commanded)},
                      {"measured_mm", vector3(p.measured_mm)}});
  }
  return {{"machine_id", m.machine_id}, {"request_id", m.request_id},
          {"kind", idl(m.kind)},        {"instrument", m.instrument},
          {"frame", m.frame},           {"time_ns", m.time_ns},
          {"touches", touches},         {"tracker_points", points},
          {"error", m.error},           {"parameters", values(m.parameters)},
          {"origin", idl(m.origin)}};
}
json expected(const CheckResult& r) {
  json metrics = json::array();
  for (const auto& m : r.metrics) {
    metrics.push_back({{"name", m.name},
                       {"value", number(m.value)},
                       {"unit", m.unit},
                       {"lower", number(m.lower)},
                       {"upper", number(m.upper)},
                       {"pass", m.pass}});
  }
  return {{"machine_id", r.machine_id},
          {"request_id", r.request_id},
          {"kind", idl(r.kind)},
          {"verdict", idl(r.verdict)},
          {"metrics", metrics},
          {"likely_causes", r.likely_causes},
          {"reason", r.reason},
          {"has_correction", r.correction.has_value()},
          {"correction", correction(r.correction)},
          {"time_ns", r.time_ns},
          {"produced_by", r.produced_by},
          {"origin", idl(r.origin)}};
}
json expected(const MachineStatus& s) {
  json out = {{"machine_id", s.machine_id}, {"request_id", s.request_id},
              {"state", idl(s.state)},      {"has_last_check", s.last_kind.has_value()},
              {"detail", s.detail},         {"time_ns", s.time_ns}};
  // Without a last check the wire's last_kind and last_verdict say nothing: any value (null).
  out["last_kind"] = s.last_kind ? json(idl(*s.last_kind)) : json(nullptr);
  out["last_verdict"] = s.last_verdict ? json(idl(*s.last_verdict)) : json(nullptr);
  return out;
}
json expected(const Intervention& i) {
  return {{"machine_id", i.machine_id},
          {"intervention_id", i.intervention_id},
          {"kind", idl(i.kind)},
          {"note", i.note},
          {"operator_name", i.operator_name},
          {"time_ns", i.time_ns}};
}
json expected(const Compensation& c) {
  return {{"machine_id", c.machine_id},
          {"request_id", c.request_id},
          {"correction", correction(c.correction)},
          {"time_ns", c.time_ns}};
}

std::uint64_t bits(double v) {
  std::uint64_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

std::string exact(double v) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g (%a)", v, v);
  return text;
}

// Where `actual` (a line the peer printed) differs from `expected`; "" when nowhere. Doubles are
// compared bit for bit; an expected null takes any value. With `negative_zeros`, `expected` is a
// historian's row, and one loss of the historian's is counted there instead: SQLite writes a
// double without fractional part into a REAL column as an integer, so a -0.0 (the sign of a zero
// component of a touch's approach direction) reads back as 0.0. Nothing else may differ.
std::string difference(const json& actual, const json& expected,
                       std::size_t* negative_zeros = nullptr, const std::string& path = "") {
  if (expected.is_null()) return "";
  if (expected.is_number_float()) {
    if (!actual.is_number_float()) return path + ": " + actual.dump() + ", expected a double";
    const double a = actual.get<double>();
    const double e = expected.get<double>();
    if (bits(a) == bits(e)) return "";
    if (negative_zeros && a == 0.0 && std::signbit(a) && !std::signbit(e)) {
      ++*negative_zeros;
      return "";
    }
    return path + ": " + exact(a) + " != " + exact(e);
  }
  if (expected.is_object()) {
    if (!actual.is_object()) return path + ": " + actual.dump() + ", expected an object";
    for (const auto& [name, value] : expected.items()) {
      if (!actual.contains(name)) return path + "." + name + " missing";
      std::string d = difference(actual.at(name), value, negative_zeros, path + "." + name);
      if (!d.empty()) return d;
    }
    for (const auto& [name, value] : actual.items()) {
      if (!expected.contains(name)) return path + "." + name + " not expected";
    }
    return "";
  }
  if (expected.is_array()) {
    if (!actual.is_array() || actual.size() != expected.size()) {
      return path + ": " + std::to_string(actual.size()) + " elements, expected " +
             std::to_string(expected.size());
    }
    for (std::size_t i = 0; i < expected.size(); ++i) {
      std::string d =
          difference(actual[i], expected[i], negative_zeros, path + "[" + std::to_string(i) + "]");
      if (!d.empty()) return d;
    }
    return "";
  }
  return actual == expected ? "" : path + ": " + actual.dump() + " != " + expected.dump();
}

// ---------------------------------------------------------------------------------------------
// The historian's rows, per topic

storage::HistoryQuery everything() {
  storage::HistoryQuery q;
  q.limit = 0;
  return q;
}

std::size_t stored_statuses(storage::Database& db) {
  std::size_t n = 0;
  for (const auto& m : db.machines()) n += db.status_history(m).size();
  return n;
}

std::optional<MachineStatus> stored_status(storage::Database& db, const json& line) {
  for (const auto& s : db.status_history(line.at("machine_id").get<std::string>())) {
    if (s.time_ns == line.at("time_ns").get<std::int64_t>() &&
        idl(s.state) == line.at("state").get<std::string>() &&
        s.request_id == line.at("request_id").get<std::string>()) {
      return s;
    }
  }
  return std::nullopt;
}

std::optional<Compensation> stored_compensation(storage::Database& db, const json& line) {
  for (const auto& c : db.compensations(line.at("machine_id").get<std::string>())) {
    if (c.request_id == line.at("request_id").get<std::string>() &&
        c.correction.target == line.at("correction").at("target").get<std::string>()) {
      return c;
    }
  }
  return std::nullopt;
}

// Reads `count` distinct samples of `topic` with the peer and compares each with the row `find`
// gives for it: each must be there and equal (`negative_zeros`: see difference()). Returns what
// the peer printed.
using RowOf = std::function<std::optional<json>(storage::Database&, const json&)>;

std::vector<json> read_and_compare(const CyclonePeer& peer, const Plant& plant,
                                   const std::string& topic, std::size_t count, const RowOf& find,
                                   std::size_t& negative_zeros) {
  const Outcome read = peer.read(topic, count);
  EXPECT_EQ(read.exit_code, 0) << topic << ": " << read.err;
  std::vector<json> lines = json_lines(read.out);
  EXPECT_EQ(lines.size(), count) << topic << ": " << read.err;
  auto db = storage::Database::open_readonly(plant.db_path());
  for (const json& line : lines) {
    const std::optional<json> row = find(db, line);
    if (!row) {
      ADD_FAILURE() << topic << ": the historian has no row for " << line.dump();
      continue;
    }
    EXPECT_EQ(difference(line, *row, &negative_zeros), "") << topic << " " << line.dump();
  }
  return lines;
}

std::size_t doubles_in(const json& j) {
  if (j.is_number_float()) return 1;
  std::size_t n = 0;
  if (j.is_structured()) {
    for (const auto& element : j) n += doubles_in(element);
  }
  return n;
}

template <typename T>
std::optional<json> expected_of(const std::optional<T>& row) {
  return row ? std::optional<json>(expected(*row)) : std::nullopt;
}

// ---------------------------------------------------------------------------------------------

std::string fixture_machine(const std::string& machine_id) {
  // deploy/machines/pm1.yaml with a fixture whose zeros drifted: the pre-calibration fails with
  // zero offsets (a Compensation) and the post-calibration passes (as in FixtureLoop.*).
  return "extends: " + std::string(NCQUAL_SOURCE_DIR) + "/deploy/machines/pm1.yaml\n" +
         "machine_id: " + machine_id +
         "\nsimulator:\n  fixture:\n    column_x: {offset_mm: 0.040}\n"
         "    pogo_offsets_mm: {C2R2: [0, 0.03, -0.03]}\n";
}

// Writes `sample` again until `listener` (a Cyclone reader of its topic, --count 1) has printed it
// and ended, as ncqual's senders write until acknowledged. On a volatile topic a sample written
// before the reader's side has matched the writer is not delivered to it, and the writer's side
// matching first (wait_for_readers) does not say the reader's side has. Repeats are harmless:
// the scheduler and the historian take a sample once, and the peer prints a repeat once.
template <typename Topic>
bool written_until_heard(ncqual::dds::Writer<Topic>& writer, const typename Topic::Model& sample,
                         Process& listener) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::chrono::steady_clock::now() < deadline) {
    if (!listener.running()) return true;
    writer.write(sample);
    if (listener.wait_for(std::chrono::milliseconds(250))) return true;
  }
  return false;
}

// A command topic's `sample` sent by ncqual's own writer code (the `ncqual` tool's: written until
// the scheduler acknowledges it), as a Cyclone reader started first printed it; nullopt (with the
// failures said) when the scheduler did not answer or Cyclone printed anything else. `readers`:
// the readers to match first, the Cyclone reader's among them.
template <typename Model>
std::optional<json> heard_by_cyclone(const CyclonePeer& peer, ncqual::dds::Participant& participant,
                                     const Model& sample, int readers) {
  using Topic = std::conditional_t<std::is_same_v<Model, CheckCommand>,
                                   ncqual::dds::CheckCommandTopic, ncqual::dds::InterventionTopic>;
  Process listener(peer.launch("read", {"--topic", Topic::kName, "--machine", sample.machine_id,
                                        "--count", "1", "--timeout", "60"}));
  ncqual::dds::Writer<Topic> writer(participant);
  EXPECT_TRUE(writer.wait_for_readers(readers, std::chrono::seconds(30)));
  const auto answer = ncqual::dds::send_acknowledged(participant, writer, sample,
                                                     {roles::kScheduler}, std::chrono::seconds(30));
  if (!answer.silent.empty()) {
    ADD_FAILURE() << Topic::kName << ": the scheduler did not acknowledge";
    return std::nullopt;
  }
  if (!written_until_heard(writer, sample, listener)) {
    ADD_FAILURE() << Topic::kName << ": Cyclone did not print it: " << listener.err();
    return std::nullopt;
  }
  EXPECT_EQ(listener.wait(), 0) << listener.err();
  const auto got = json_lines(listener.out());
  if (got.size() != 1) {
    ADD_FAILURE() << Topic::kName << ": Cyclone printed " << got.size() << " lines";
    return std::nullopt;
  }
  return got[0];
}

bool complete(const std::optional<storage::CheckRecord>& r) {
  return r && r->request && r->measurement && r->result;
}

std::optional<storage::CheckRecord> requested_by(storage::Database& db, const std::string& machine,
                                                 const std::string& who) {
  storage::HistoryQuery q = everything();
  q.machine_id = machine;
  for (auto& r : db.history(q)) {
    if (r.request && r.request->requested_by == who) return r;
  }
  return std::nullopt;
}

TEST(Cyclone, ACycloneDdsPeerReadsEveryTopicExactlyAndItsOrdersAreCarriedOut) {
  if (std::string(NCQUAL_CYCLONE_PEER_EXE).empty()) {
    GTEST_SKIP() << "ncqual-cyclone-peer was not built: Cyclone DDS was not found when CMake "
                    "configured the build (apt-get install cyclonedds-dev cyclonedds-tools, or "
                    "deploy/install-deps.sh --test; then cmake -S . -B build)";
  }
  Plant plant("cyclone", TestDomain::Cyclone);
  plant.add_machine("pm-fix", fixture_machine("pm-fix"));
  plant.add_machine("pm-held",
                    machine_yaml("pm-held", "    machine_shift_mm: [0.040, -0.031, 0.027]\n", 12));
  plant.write_plant("[monument_positioning]");
  plant.start("historian");
  plant.start("solver");
  plant.start("acquisition", {"--machine", "pm-fix,pm-held"});
  plant.start("scheduler");
  const CyclonePeer peer(plant);
  const auto logs = [&] {
    return plant.log("scheduler") + plant.log("historian") + plant.log("acquisition") +
           plant.log("solver");
  };

  // The start-up check: pm-fix passes, pm-held fails (its machine shifted) and is held.
  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) {
    const auto fix = db.latest_status("pm-fix");
    const auto held = db.latest_status("pm-held");
    return fix && fix->state == MachineState::Qualified && held &&
           held->state == MachineState::NeedsIntervention;
  })) << logs();

  // 1. An order from Cyclone: the weekly fixture check of configuration 2. The scheduler accepts
  //    it, and the check runs: request, measurement, FAIL with zero offsets, their Compensation,
  //    and the post-calibration that verifies them.
  const std::string order_id = "cyclone-order-1";
  const Outcome order =
      peer.run("command", {"--machine", "pm-fix", "--kind", "fixture_precal", "--request-id",
                           order_id, "--requested-by", "operator:cyclone", "--param",
                           "fixture_configuration=2", "--timeout", "60"});
  ASSERT_EQ(order.exit_code, 0) << order.err << logs();
  const std::vector<json> order_lines = json_lines(order.out);
  ASSERT_EQ(order_lines.size(), 2u) << order.out;  // the order sent, the scheduler's answer
  EXPECT_EQ(order_lines[1].at("outcome"), "ACK_ACCEPTED") << order_lines[1];
  EXPECT_EQ(order_lines[1].at("by"), "scheduler");
  EXPECT_EQ(order_lines[1].at("topic"), "ncqual/CheckCommand");
  EXPECT_EQ(order_lines[1].at("sample_id"), order_id);
  EXPECT_EQ(order_lines[1].at("content_hash").get<std::string>().size(), 64u);

  ASSERT_TRUE(plant.wait_for_db([&](storage::Database& db) {
    storage::HistoryQuery q = everything();
    q.kind = CheckKind::FixturePostCalibration;
    const auto post = db.history(q);
    return complete(db.find_check(order_id)) && !post.empty() && complete(post.front());
  })) << logs();
  {
    auto db = storage::Database::open_readonly(plant.db_path());
    const auto pre = db.find_check(order_id);
    EXPECT_EQ(pre->machine_id, "pm-fix");
    EXPECT_EQ(pre->kind, CheckKind::FixturePreCalibration);
    EXPECT_EQ(pre->request->requested_by, "operator:cyclone");
    EXPECT_GT(pre->request->time_ns, order_lines[0].at("time_ns").get<std::int64_t>());
    ASSERT_EQ(pre->request->parameters.size(), 1u);
    EXPECT_EQ(pre->request->parameters[0].name, "fixture_configuration");
    EXPECT_EQ(pre->request->parameters[0].value, 2.0);
    EXPECT_FALSE(pre->measurement->instrument.empty());
    EXPECT_GT(pre->measurement->touches, 0);
    EXPECT_EQ(pre->result->verdict, Verdict::Fail);
    ASSERT_TRUE(pre->result->correction.has_value());
    const auto compensations = db.compensations("pm-fix");
    ASSERT_EQ(compensations.size(), 1u);
    EXPECT_EQ(compensations[0].request_id, order_id);
    storage::HistoryQuery q = everything();
    q.kind = CheckKind::FixturePostCalibration;
    const auto post = db.history(q).front();
    EXPECT_EQ(post.request->verifies_correction_of, order_id);
    EXPECT_EQ(post.result->verdict, Verdict::Pass) << post.result->reason;
  }

  // 2. An intervention from Cyclone re-arms the held machine: the scheduler runs its check again
  //    (requested by the intervention), and the historian keeps the intervention as sent.
  const Outcome intervened =
      peer.run("intervene", {"--machine", "pm-held", "--check", "monument_positioning", "--note",
                             "machine re-levelled, \"anchors\" tightened", "--operator",
                             "cyclone-ann", "--readers", "2", "--timeout", "60"});
  ASSERT_EQ(intervened.exit_code, 0) << intervened.err << logs();
  const std::vector<json> intervention_lines = json_lines(intervened.out);
  ASSERT_EQ(intervention_lines.size(), 2u) << intervened.out;
  EXPECT_EQ(intervention_lines[1].at("outcome"), "ACK_ACCEPTED") << intervention_lines[1];
  const std::string iv_id = intervention_lines[0].at("intervention_id");
  ASSERT_TRUE(plant.wait_for_db([&](storage::Database& db) {
    const auto rerun = requested_by(db, "pm-held", "intervention:" + iv_id);
    const auto status = db.latest_status("pm-held");
    return !db.interventions("pm-held").empty() && complete(rerun) && status &&
           status->request_id == rerun->request_id &&
           status->state == MachineState::NeedsIntervention;  // still shifted: held again
  })) << logs();
  {
    auto db = storage::Database::open_readonly(plant.db_path());
    const auto stored = db.interventions("pm-held");
    ASSERT_EQ(stored.size(), 1u);
    EXPECT_EQ(difference(intervention_lines[0], expected(stored[0])), "");
    EXPECT_EQ(stored[0].note, "machine re-levelled, \"anchors\" tightened");
    const auto rerun = requested_by(db, "pm-held", "intervention:" + iv_id);
    EXPECT_EQ(rerun->kind, CheckKind::MonumentPositioning);
    EXPECT_EQ(rerun->result->verdict, Verdict::Fail);
  }

  // 3. The command topics as ncqual's own writers send them (the `ncqual` tool's code), read by a
  //    Cyclone reader started first.
  ncqual::dds::Participant participant(test_participant(plant, "cyclone-test"));
  {
    const CheckCommand cmd{"pm-fix",
                           "op-from-fast-dds-1",
                           CheckKind::MonumentCRotation,
                           "operator:fast-dds",
                           WallClock().now_ns(),
                           {}};
    const std::optional<json> got = heard_by_cyclone(peer, participant, cmd, 2);  // scheduler
    ASSERT_TRUE(got) << logs();
    EXPECT_EQ(difference(*got, expected(cmd)), "");
  }
  {
    const Intervention iv{"pm-fix",
                          "iv-from-fast-dds-1",
                          CheckKind::MonumentPositioning,
                          "nothing held: recorded only",
                          "fast-dds-bob",
                          WallClock().now_ns()};
    // scheduler, historian, Cyclone
    const std::optional<json> got = heard_by_cyclone(peer, participant, iv, 3);
    ASSERT_TRUE(got) << logs();
    EXPECT_EQ(difference(*got, expected(iv)), "");
    ASSERT_TRUE(plant.wait_for_db([&](storage::Database& db) {
      const auto stored = db.interventions("pm-fix");
      return stored.size() == 1 && difference(*got, expected(stored[0])).empty();
    })) << logs();
  }

  // The plant is quiet once the ordered check is stored and both machines' state settled.
  ASSERT_TRUE(plant.wait_for_db([](storage::Database& db) {
    const auto check = db.find_check("op-from-fast-dds-1");
    const auto fix = db.latest_status("pm-fix");
    return complete(check) && fix && fix->request_id == "op-from-fast-dds-1" &&
           fix->state == MachineState::Qualified;
  })) << logs();

  // 4. Every durable topic from the writers' histories: as many distinct samples as the
  //    historian has rows, each equal to its row (so every row was read).
  const auto stored_counts = [&] {
    auto db = storage::Database::open_readonly(plant.db_path());
    std::map<std::string, std::size_t> n;
    for (const auto& r : db.history(everything())) {
      n["ncqual/CheckRequest"] += r.request ? 1 : 0;
      n["ncqual/MeasurementSet"] += r.measurement ? 1 : 0;
      n["ncqual/CheckResult"] += r.result ? 1 : 0;
    }
    n["ncqual/MachineStatus"] = stored_statuses(db);
    for (const auto& m : db.machines()) n["ncqual/Compensation"] += db.compensations(m).size();
    return n;
  };
  const std::map<std::string, std::size_t> counts = stored_counts();
  // 2 start-up checks, the order, its post-calibration, the re-run, the order from Fast DDS
  ASSERT_EQ(counts.at("ncqual/CheckResult"), 6u);
  ASSERT_EQ(counts.at("ncqual/Compensation"), 1u);
  const std::map<std::string, RowOf> rows = {
      {"ncqual/CheckRequest",
       [](storage::Database& db, const json& line) {
         const auto r = db.find_check(line.at("request_id").get<std::string>());
         return r ? expected_of(r->request) : std::nullopt;
       }},
      {"ncqual/MeasurementSet",
       [](storage::Database& db, const json& line) {
         return expected_of(db.load_measurement_set(line.at("request_id").get<std::string>()));
       }},
      {"ncqual/CheckResult",
       [](storage::Database& db, const json& line) {
         const auto r = db.find_check(line.at("request_id").get<std::string>());
         return r ? expected_of(r->result) : std::nullopt;
       }},
      {"ncqual/MachineStatus",
       [](storage::Database& db, const json& line) {
         return expected_of(stored_status(db, line));
       }},
      {"ncqual/Compensation",
       [](storage::Database& db, const json& line) {
         return expected_of(stored_compensation(db, line));
       }},
  };
  std::size_t doubles = 0, negative_zeros = 0;
  std::string figures;
  for (const auto& [topic, find] : rows) {
    const std::vector<json> lines =
        read_and_compare(peer, plant, topic, counts.at(topic), find, negative_zeros);
    for (const auto& line : lines) doubles += doubles_in(line);
    figures += (figures.empty() ? "" : ", ") + std::to_string(lines.size()) + " " + topic;
  }
  EXPECT_EQ(stored_counts(), counts) << "the plant was not quiet while Cyclone read";
  std::cout << "Cyclone DDS read " << figures << ": each sample equal to the historian's row, "
            << doubles << " doubles bit for bit (but " << negative_zeros
            << " negative zeros, which the historian stored as 0.0)\n";

  // One machine's samples only (a key filter of the reader's own).
  {
    auto db = storage::Database::open_readonly(plant.db_path());
    storage::HistoryQuery q = everything();
    q.machine_id = "pm-held";
    const std::size_t held_results = db.history(q).size();
    const Outcome read =
        peer.run("read", {"--topic", "ncqual/CheckResult", "--machine", "pm-held", "--count",
                          std::to_string(held_results), "--timeout", "60"});
    ASSERT_EQ(read.exit_code, 0) << read.err;
    const auto lines = json_lines(read.out);
    EXPECT_EQ(lines.size(), held_results);
    for (const auto& l : lines) EXPECT_EQ(l.at("machine_id"), "pm-held");
  }

  // 5. Heartbeats (read best effort, volatile: the next ones), from the services the historian
  // lists.
  {
    const Outcome read = peer.read("ncqual/Heartbeat", 4);
    ASSERT_EQ(read.exit_code, 0) << read.err;
    auto db = storage::Database::open_readonly(plant.db_path());
    std::set<std::pair<std::string, std::string>> known;
    for (const auto& s : db.services()) known.emplace(s.service, s.instance);
    for (const auto& beat : json_lines(read.out)) {
      EXPECT_EQ(known.count({beat.at("service").get<std::string>(),
                             beat.at("instance").get<std::string>()}),
                1u)
          << beat;
      EXPECT_EQ(beat.at("health"), "ok") << beat;
      EXPECT_GT(beat.at("time_ns").get<std::int64_t>(), 0) << beat;
    }
  }

  // 6. An alarm: a second, different result for a stored request (sent here through ncqual's
  //    writer) is kept as a conflict and raised on ncqual/Alarm, which Cyclone reads.
  {
    auto db = storage::Database::open_readonly(plant.db_path());
    storage::HistoryQuery q = everything();
    q.machine_id = "pm-fix";
    q.kind = CheckKind::MonumentPositioning;
    const auto startup = db.history(q);
    ASSERT_EQ(startup.size(), 1u);
    ASSERT_TRUE(startup[0].result.has_value());
    CheckResult forged = *startup[0].result;
    forged.verdict = Verdict::Fail;
    forged.reason = "forged for the test";
    ncqual::dds::Writer<ncqual::dds::CheckResultTopic> writer(participant);
    const auto answer = ncqual::dds::send_acknowledged(
        participant, writer, forged, {roles::kHistorian}, std::chrono::seconds(30));
    ASSERT_EQ(answer.answers.count(roles::kHistorian), 1u) << logs();
    EXPECT_EQ(answer.answers.at(roles::kHistorian).outcome, AckOutcome::Conflict);
    const Outcome read = peer.read("ncqual/Alarm", 1);
    ASSERT_EQ(read.exit_code, 0) << read.err;
    const auto alarms = json_lines(read.out);
    ASSERT_EQ(alarms.size(), 1u);
    const auto conflicts = db.conflicts("pm-fix");
    ASSERT_EQ(conflicts.size(), 1u);
    const json& alarm = alarms[0];
    EXPECT_EQ(alarm.at("alarm_id"),
              "conflict/ncqual/CheckResult/" + forged.request_id + "/" + conflicts[0].content_hash);
    EXPECT_EQ(alarm.at("machine_id"), "pm-fix");
    EXPECT_EQ(alarm.at("kind"), idl(AlarmKind::Conflict));
    EXPECT_EQ(alarm.at("active"), true);
    EXPECT_EQ(alarm.at("source"), "historian");
    EXPECT_EQ(alarm.at("text").get<std::string>().rfind(
                  "conflicting results of " + forged.request_id + " of machine 'pm-fix' from ", 0),
              0u)
        << alarm;
  }
}

}  // namespace
}  // namespace ncqual::testing
