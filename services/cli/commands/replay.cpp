// SPDX-License-Identifier: Apache-2.0
// `ncqual replay`: a recording's samples into a domain again, or judged again by this build's
// solver (docs/recordings.md).
//
//   ncqual replay FILE.mcap [--rate X | --fast] [--topics T,...] [--machine M,...]
//                 [--from T] [--to T] [--readers N] [--plant F] [--domain N] [--secure DIR]
//                 [--identity NAME]
//     Writes the recorded bytes again, with their keys, through writers with each topic's profile
//     QoS (a per-machine topic in its machine's partition) and the recorded source timestamps, in
//     log-time order, paced by the recorded times divided by the rate (default 1) or, with
//     --fast, as fast as the readers acknowledge. --readers N waits for N readers of each topic
//     before its first sample. On a secured plant it runs as an identity of the `rig` role.
//   ncqual replay FILE.mcap --resolve [--json] [--machine M,...] [--from T] [--to T]
//                 [--metric-tolerance F] [--plant F]
//     Judges every recorded MeasurementSet again with this build's solver (in process, no DDS)
//     against the plant config, and compares each result with the recorded CheckResult of the
//     same request: verdicts changed, metrics moved beyond F of their tolerance band (default
//     0.01), causes changed or reordered, corrections changed.
//
// Exit codes: 0 (replayed; resolved with no change), 1 error (a file that cannot be read, no
// ncqual topic in it, samples not written), 2 bad usage, 3 resolved with changes.
#include "commands.hpp"

#include "ncqual/common/clock.hpp"
#include "ncqual/dds/convert.hpp"
#include "ncqual/dds/dispatcher.hpp"
#include "ncqual/dds/serialized.hpp"
#include "ncqual/dds/topics.hpp"
#include "ncqual/common/json.hpp"
#include "ncqual/recording/recording.hpp"
#include "ncqual/recording/replayer.hpp"
#include "ncqual/solver/compare.hpp"
#include "ncqual/solver/solve.hpp"
#include "ncqual/common/version.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <iostream>
#include <map>
#include <thread>

namespace ncqual::cli {
namespace {

struct Options {
  DdsOptions dds;
  std::string file;
  double rate = 1.0;
  bool fast = false;
  std::vector<std::string> topics, machines;
  std::string from, to;
  int readers = 0;
  bool resolve = false;
  bool json = false;
  double metric_tolerance = 0.01;
};

std::optional<std::int64_t> time_option(const std::string& flag, const std::string& text) {
  if (text.empty()) return std::nullopt;
  if (const auto t = parse_iso8601(text)) return t;
  throw UsageError(flag + " '" + text + "': expected a UTC time such as 2026-11-24T06:00Z");
}

recording::Filter filter_of(const Options& o) {
  recording::Filter f;
  for (const auto* t : topics_option(o.topics)) f.topics.insert(t->name);
  f.machines = std::set<std::string>(o.machines.begin(), o.machines.end());
  f.from_ns = time_option("--from", o.from);
  f.to_ns = time_option("--to", o.to);
  if (f.from_ns && f.to_ns && *f.to_ns < *f.from_ns) {
    throw UsageError("--to " + o.to + " is before --from " + o.from);
  }
  return f;
}

void print_skipped(const recording::Selection& s) {
  for (const auto& line : s.skipped) std::cerr << "skipped: " << line << "\n";
  // Recorded by an older version: read in this build's layout, their new fields unknown.
  for (const auto& [topic, per_contract] : s.upgraded) {
    for (const auto& [contract, n] : per_contract) {
      std::cerr << "note: " << n << " " << topic << " samples were recorded in wire contract "
                << contract << " and are read in contract " << ncqual::dds::kWireContract
                << " (their data origin unknown)\n";
    }
  }
}

// ---- replay into a domain --------------------------------------------------------------------

int run_replay(const Options& o) {
  std::atomic<bool> stop{false};
  ncqual::dds::handle_termination_signals([&stop](int) { stop = true; });
  const PlantConfig plant = plant_from(o.dds.plant);
  const recording::Filter filter = filter_of(o);
  const mcap::Recording r = mcap::read_file(o.file);
  for (const auto& w : r.warnings) std::cerr << "warning: " << w << "\n";
  const recording::Selection selection = recording::select(r, filter, o.file);
  print_skipped(selection);
  recording::ReplayOptions options;
  options.rate = o.fast ? 0 : o.rate;
  options.readers = o.readers;
  const ncqual::dds::ParticipantOptions participant_options =
      command_participant(plant, o.dds, "ncqual-replay", "rig");
  ncqual::dds::Participant participant(participant_options);
  recording::Replayer replayer(participant, options);
  std::cerr << "replaying " << selection.samples.size() << " samples of " << o.file
            << " into domain " << participant_options.domain_id
            << (o.fast ? " as fast as the readers acknowledge"
                       : " at " + std::to_string(o.rate) + " times the recorded pace")
            << std::endl;
  const auto start = std::chrono::steady_clock::now();
  const recording::ReplayReport report =
      replayer.run(selection, [&](std::chrono::nanoseconds offset) {
        // Real time, by design: a replay keeps the plant's pace. Sleeps in short steps so that
        // Ctrl-C stops it.
        const auto due = start + offset;
        while (!stop && std::chrono::steady_clock::now() < due) {
          std::this_thread::sleep_until(
              std::min(due, std::chrono::steady_clock::now() + std::chrono::milliseconds(100)));
        }
        return !stop.load();
      });
  for (const auto& p : report.problems) std::cerr << "problem: " << p << "\n";
  std::cerr << report.written << " samples written";
  for (const auto& [topic, n] : report.per_topic) std::cerr << ", " << topic << " " << n;
  if (selection.filtered_out != 0) {
    std::cerr << "; " << selection.filtered_out << " left out by --topics/--machine/--from/--to";
  }
  if (selection.skipped_messages != 0) {
    std::cerr << "; " << selection.skipped_messages << " skipped (not ncqual samples)";
  }
  std::cerr << (report.acknowledged ? "" : "; not every reader acknowledged them") << "\n";
  if (report.not_written != 0) return kExitError;
  return stop ? kExitError : kExitOk;
}

// ---- judged again ----------------------------------------------------------------------------

template <typename Topic>
std::optional<typename Topic::Model> decode(const recording::Sample& s, std::string& error) {
  typename Topic::Wire wire;
  if (!ncqual::dds::deserialize<Topic>(s.bytes(), wire)) {
    error = mcap::location(*s.message) + ": not a readable " + Topic::kName;
    return std::nullopt;
  }
  std::string problem;
  auto model = ncqual::dds::from_wire(wire, problem);
  if (!problem.empty()) {
    error = mcap::location(*s.message) + ": " + problem;
    // Judged all the same: the solver made its result of the same malformed sample.
  }
  return model;
}

struct Judged {
  MeasurementSet set;
  std::optional<CheckResult> recorded;
  CheckResult fresh;
  std::vector<solver::ResultDifference> differences;
  std::string note;  // why not compared
};

int run_resolve(const Options& o) {
  const PlantConfig plant = plant_from(o.dds.plant);
  recording::Filter filter = filter_of(o);
  if (!filter.topics.empty()) throw UsageError("--topics does not go with --resolve");
  filter.topics = {ncqual::dds::MeasurementSetTopic::kName, ncqual::dds::CheckResultTopic::kName};
  const mcap::Recording r = mcap::read_file(o.file);
  for (const auto& w : r.warnings) std::cerr << "warning: " << w << "\n";
  const recording::Selection selection = recording::select(r, filter, o.file);
  print_skipped(selection);

  std::vector<Judged> judged;
  std::map<std::string, std::size_t> by_request;  // request id -> index in judged
  std::map<std::string, CheckResult> results;     // request id -> the last recorded result
  std::vector<std::string> problems;
  for (const auto& s : selection.samples) {
    std::string error;
    if (s.topic->name == ncqual::dds::CheckResultTopic::kName) {
      if (auto result = decode<ncqual::dds::CheckResultTopic>(s, error)) {
        results[result->request_id] = *result;
      }
    } else if (auto set = decode<ncqual::dds::MeasurementSetTopic>(s, error)) {
      // A set sent again (its acknowledgement was lost) is judged once.
      if (by_request.emplace(set->request_id, judged.size()).second) {
        judged.push_back(Judged{*set, std::nullopt, {}, {}, {}});
      }
    }
    if (!error.empty()) problems.push_back(error);
  }
  const solver::CompareOptions compare{o.metric_tolerance};
  std::size_t changed = 0;
  std::size_t without_result = 0;
  for (auto& j : judged) {
    const auto it = results.find(j.set.request_id);
    if (it != results.end()) j.recorded = it->second;
    const std::int64_t time = j.recorded ? j.recorded->time_ns : j.set.time_ns;
    j.fresh = solver::solve(j.set, plant, time);
    j.fresh.produced_by = version_line("ncqual");
    if (!j.recorded) {
      j.note = "no recorded result";
      ++without_result;
      continue;
    }
    j.differences = solver::compare_results(*j.recorded, j.fresh, compare);
    if (!j.differences.empty()) ++changed;
  }

  std::stable_sort(judged.begin(), judged.end(), [](const Judged& a, const Judged& b) {
    return a.set.machine_id < b.set.machine_id;
  });
  if (o.json) {
    nlohmann::ordered_json out;
    out["file"] = o.file;
    out["solver"] = version_line("ncqual");
    out["sets"] = judged.size();
    out["changed"] = changed;
    out["without_recorded_result"] = without_result;
    out["checks"] = nlohmann::json::array();
    for (const auto& j : judged) {
      nlohmann::ordered_json c;
      c["machine"] = j.set.machine_id;
      c["request"] = j.set.request_id;
      c["kind"] = std::string(to_string(j.set.kind));
      c["recorded_verdict"] = j.recorded
                                  ? nlohmann::json(std::string(to_string(j.recorded->verdict)))
                                  : nlohmann::json();
      c["recorded_by"] = j.recorded ? j.recorded->produced_by : "";
      c["verdict"] = std::string(to_string(j.fresh.verdict));
      c["changed"] = !j.differences.empty();
      c["differences"] = nlohmann::json::array();
      for (const auto& d : j.differences) {
        c["differences"].push_back(
            {{"kind", std::string(solver::to_string(d.kind))}, {"text", d.text}});
      }
      if (!j.note.empty()) c["note"] = j.note;
      out["checks"].push_back(c);
    }
    out["problems"] = problems;
    std::cout << out.dump(2) << "\n";
  } else {
    std::cout << "judged " << judged.size() << " recorded measurement sets of " << o.file
              << " again with " << version_line("ncqual") << "\n";
    std::string machine;
    for (const auto& j : judged) {
      if (j.differences.empty() && j.note.empty()) continue;
      if (j.set.machine_id != machine) {
        machine = j.set.machine_id;
        std::cout << "\n" << machine << "\n";
      }
      std::cout << "  " << j.set.request_id << " " << to_string(j.set.kind) << ": ";
      if (!j.note.empty()) {
        std::cout << j.note << "; now " << to_string(j.fresh.verdict) << "\n";
        continue;
      }
      std::cout << to_string(j.recorded->verdict) << " -> " << to_string(j.fresh.verdict)
                << " (recorded by "
                << (j.recorded->produced_by.empty() ? "an unnamed solver" : j.recorded->produced_by)
                << ")\n";
      for (const auto& d : j.differences) std::cout << "    " << d.text << "\n";
    }
    std::cout << "\n"
              << judged.size() - changed - without_result << " unchanged, " << changed
              << " changed, " << without_result << " without a recorded result\n";
  }
  for (const auto& p : problems) std::cerr << "problem: " << p << "\n";
  if (judged.empty()) {
    std::cerr << "ncqual replay: " << o.file << " holds no MeasurementSet"
              << (filter.machines.empty() && !filter.from_ns && !filter.to_ns ? "" : " selected")
              << "\n";
    return kExitNotFound;
  }
  return changed != 0 ? kExitFail : kExitOk;
}

int run(const Options& o) {
  if (o.resolve) return run_resolve(o);
  if (o.json) throw UsageError("--json goes with --resolve");
  if (!o.fast && !(o.rate > 0)) throw UsageError("--rate must be more than 0 (or use --fast)");
  return run_replay(o);
}

}  // namespace

void add_replay(CLI::App& app, Commands& commands) {
  const auto [cmd, o] = add_command(
      app, commands, "replay",
      "replay a recording into a domain, or judge its measurement sets again (--resolve)", run);
  cmd->add_option("file", o->file, "the recording")->type_name("FILE.mcap")->required();
  auto* rate =
      cmd->add_option("--rate", o->rate, "times the recorded pace (default 1)")->type_name("X");
  cmd->add_flag("--fast", o->fast, "as fast as the readers acknowledge")->excludes(rate);
  add_sample_filter_options(cmd, o->topics, o->machines);
  cmd->add_option("--from", o->from, "from this recorded time (UTC, 2026-11-24T06:00Z)")
      ->type_name("TIME");
  cmd->add_option("--to", o->to, "up to this recorded time (UTC)")->type_name("TIME");
  cmd->add_option("--readers", o->readers, "wait for N readers of each topic first (30 s at most)")
      ->type_name("N");
  cmd->add_flag("--resolve", o->resolve,
                "judge every recorded MeasurementSet again and compare with its recorded result");
  add_json_flag(cmd, o->json);
  cmd->add_option("--metric-tolerance", o->metric_tolerance,
                  "--resolve: a metric has moved past this fraction of its band (default 0.01)")
      ->type_name("F");
  add_dds_options(cmd, o->dds);
}

}  // namespace ncqual::cli
