// SPDX-License-Identifier: Apache-2.0
// The dashboard's pages (pages.hpp): HTML written here, every stored text escaped.
#include "pages.hpp"

#include "ncqual/common/check_kinds.hpp"
#include "ncqual/common/version.hpp"

#include "ncqual/report/machine_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

namespace ncqual::web {

std::string escape_html(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

namespace {

std::string esc(std::string_view text) { return escape_html(std::string(text)); }

// A path segment with everything but unreserved characters percent-encoded.
std::string url_segment(const std::string& text) {
  std::string out;
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u) || c == '-' || c == '_' || c == '.' || c == '~') {
      out += c;
    } else {
      out += fmt::format("%{:02X}", u);
    }
  }
  return out;
}

std::string machine_link(const std::string& id) {
  return fmt::format("<a href=\"/machines/{}\">{}</a>", url_segment(id), esc(id));
}
std::string check_link(const std::string& id) {
  return fmt::format("<a href=\"/checks/{}\">{}</a>", url_segment(id), esc(id));
}

// "qualified", "needs-intervention": the CSS class of a state or verdict.
std::string css_name(std::string_view name) {
  std::string out;
  for (const char c : name) {
    out += c == '_' ? '-' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return out;
}

std::string state_badge(MachineState state) {
  return fmt::format("<span class=\"nw-badge nw-state-{}\" data-state=\"{}\">{}</span>",
                     css_name(to_string(state)), esc(to_string(state)), esc(to_string(state)));
}
std::string verdict_badge(Verdict verdict) {
  return fmt::format("<span class=\"nw-badge nw-verdict-{}\">{}</span>",
                     css_name(to_string(verdict)), esc(to_string(verdict)));
}

std::string kind_text(CheckKind kind) {
  const auto& info = check_kind_info(kind);
  return fmt::format("<span title=\"{}\">{}</span>", esc(info.title), esc(info.name));
}

// A value as people read it: six significant digits; NaN (not evaluated) and a missing bound
// (a one-sided band) in words.
std::string number(double v) {
  if (std::isnan(v)) return "not evaluated";
  if (!std::isfinite(v)) return "&mdash;";
  return fmt::format("{:.6g}", v);
}

// A metric's value or one of its bounds as people read it: at a tenth of its tolerance band, as
// the CLI prints it (format_metric_value: 0.000 mm, not 9.34795e-06); NaN and a missing bound in
// words.
std::string metric_number(const Metric& metric, double v) {
  if (!std::isfinite(v)) return number(v);
  Metric shown = metric;
  shown.value = v;
  return format_metric_value(shown);
}

constexpr const char* kStyle = R"css(
:root { color-scheme: light; --ink: #1d2430; --muted: #5b6575; --line: #d8dde5;
  --accent: #1f5fa8; --good: #1b7a3a; --bad: #b3261e; --warn: #a15c00; --idle: #6b7280; }
* { box-sizing: border-box; }
body { margin: 0; font: 15px/1.45 system-ui, -apple-system, "Segoe UI", sans-serif;
  color: var(--ink); background: #f5f7fa; }
header { display: flex; align-items: baseline; gap: 1.5em; padding: .7em 1.5em;
  background: #14263f; color: #fff; }
header a { color: #fff; text-decoration: none; font-weight: 600; }
header nav { flex: 1; }
header nav span { color: #b9c6d8; margin: 0 .4em; }
#live { font-size: 13px; color: #b9c6d8; }
main { padding: 1em 1.5em 2em; max-width: 1400px; }
h1 { font-size: 22px; margin: .2em 0 .1em; }
h2 { font-size: 18px; margin: 1.4em 0 .4em; border-bottom: 1px solid var(--line);
  padding-bottom: .2em; }
h3 { font-size: 16px; margin: 1em 0 .3em; }
table { border-collapse: collapse; background: #fff; border: 1px solid var(--line);
  margin: .3em 0 1em; }
th, td { text-align: left; padding: .35em .7em; border-bottom: 1px solid var(--line);
  vertical-align: top; }
th { background: #eef1f5; font-weight: 600; font-size: 13px; }
a { color: var(--accent); }
.nw-asof, .nw-note { color: var(--muted); margin: 0 0 .8em; font-size: 13px; }
td.nw-num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
.nw-badge { display: inline-block; padding: .05em .55em; border-radius: 3px; font-size: 12px;
  font-weight: 700; letter-spacing: .02em; color: #fff; background: var(--idle);
  white-space: nowrap; }
.nw-state-qualified, .nw-verdict-pass, .nw-ok { background: var(--good); }
.nw-state-needs-intervention, .nw-state-offline, .nw-verdict-fail, .nw-bad,
  .nw-overdue { background: var(--bad); }
.nw-state-overdue, .nw-verdict-invalid, .nw-due { background: var(--warn); }
.nw-state-checking { background: var(--accent); }
.nw-simulated { background: #6a1b9a; }
.nw-simulated-banner { margin: .6em 0 1em; padding: .7em 1em; border: 3px solid #6a1b9a;
  background: #f6edfa; color: #3b0a57; font-size: 15px; }
.nw-simulated-banner strong { color: #6a1b9a; letter-spacing: .04em; }
tr.nw-simulated-row td { background: #faf4fd; }
.nw-origin-unknown { color: var(--muted); font-style: italic; }
.nw-machines { display: grid; grid-template-columns: repeat(auto-fill, minmax(420px, 1fr));
  gap: 1em; }
.nw-machine { background: #fff; border: 1px solid var(--line); border-radius: 4px;
  padding: .8em 1em; min-width: 0; }
.nw-machine h2 { margin-top: 0; border: 0; display: flex; gap: .6em; align-items: center; }
.nw-machine table { width: 100%; margin-bottom: .5em; }
.nw-detail { color: var(--muted); font-size: 13px; margin: 0 0 .5em; }
ul.nw-warnings { margin: .2em 0 .5em; padding-left: 1.2em; }
ul.nw-warnings li { margin: .2em 0; }
.nw-warning-kind { font-weight: 700; color: var(--warn); }
tr.nw-out td { background: #fdecea; }
.nw-empty { color: var(--muted); font-style: italic; }
footer { padding: 1em 1.5em; color: var(--muted); font-size: 12px; }
@media print { header #live, footer { display: none; } body { background: #fff; } }
)css";

// Polls /api/v1/changes; when the token moved, fetches the page again and swaps its <main>
// (and the token). Without script the page is whole as served (and refreshes every 30 s).
constexpr const char* kScript = R"js(
(function () {
  var body = document.body, live = document.getElementById('live');
  var token = body.getAttribute('data-token');
  var every = parseInt(body.getAttribute('data-poll-ms'), 10) || 2000;
  var zone = body.getAttribute('data-time-zone') || 'UTC';
  function stamp(text) { if (live) live.textContent = text; }
  // The plant's clock, as every time on the page (not the browser's).
  function now() {
    try {
      return new Date().toLocaleTimeString('en-GB', {timeZone: zone, timeZoneName: 'short'});
    } catch (e) { return new Date().toISOString().substring(11, 19) + ' UTC'; }
  }
  function poll() {
    fetch('/api/v1/changes?since=' + encodeURIComponent(token), {cache: 'no-store'})
      .then(function (r) { if (!r.ok) throw new Error('HTTP ' + r.status); return r.json(); })
      .then(function (c) {
        body.setAttribute('data-polls', String(1 + (parseInt(body.getAttribute('data-polls'), 10) || 0)));
        if (!c.changed) { stamp('live: up to date ' + now()); return; }
        return fetch(location.pathname + location.search, {cache: 'no-store'})
          .then(function (r) { if (!r.ok) throw new Error('HTTP ' + r.status); return r.text(); })
          .then(function (html) {
            var page = new DOMParser().parseFromString(html, 'text/html');
            var fresh = page.querySelector('main');
            if (!fresh) throw new Error('no <main> in the page');
            document.querySelector('main').replaceWith(document.adoptNode(fresh));
            token = page.body.getAttribute('data-token');
            body.setAttribute('data-token', token);
            body.setAttribute('data-updates', String(1 + (parseInt(body.getAttribute('data-updates'), 10) || 0)));
            stamp('live: updated ' + now());
          });
      })
      .catch(function (e) { stamp('live: ' + e.message + '; retrying'); })
      .then(function () { setTimeout(poll, every); });
  }
  stamp('live');
  setTimeout(poll, every);
})();
)js";

std::string page(const PlantConfig& plant, const std::string& title, const std::string& token,
                 const std::string& nav, const std::string& main, const std::string& api,
                 const Limits& limits, const std::string& extra_style = {}, bool live = true) {
  std::string out;
  out += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  out += "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n";
  out += fmt::format("<title>{} &middot; ncqual</title>\n", esc(title));
  out += "<noscript><meta http-equiv=\"refresh\" content=\"30\"></noscript>\n";
  out += "<style>" + std::string(kStyle) + "</style>\n";
  if (!extra_style.empty()) out += "<style>" + extra_style + "</style>\n";
  out += "</head>\n";
  out += fmt::format(
      "<body data-token=\"{}\" data-poll-ms=\"{}\" data-time-zone=\"{}\" data-updates=\"0\" "
      "data-polls=\"0\">\n",
      esc(token), limits.poll_ms, esc(plant.calendar ? plant.calendar->time_zone : "UTC"));
  out += fmt::format(
      "<header><nav><a href=\"/\">plant {}</a>{}</nav><span id=\"live\">static page</span>"
      "</header>\n",
      esc(plant.plant), nav);
  out += "<main>\n" + main + "</main>\n";
  out += fmt::format(
      "<footer>{} &middot; read-only view of the historian &middot; this page as JSON: "
      "<a href=\"{}\">{}</a></footer>\n",
      esc(version_line("ncqual-web")), esc(api), esc(api));
  if (live) out += "<script>" + std::string(kScript) + "</script>\n";
  out += "</body>\n</html>\n";
  return out;
}

std::string when(const Calendar& calendar, std::optional<std::int64_t> t) {
  return t ? esc(calendar.local_text(*t)) : std::string("never");
}

// The next period to fall due: the earliest next due, "now" when one is due.
std::string next_due_text(const Calendar& calendar, const plant_status::MachineDocument& m) {
  const plant_status::PeriodDocument* next = nullptr;
  for (const auto& p : m.periods) {
    if (p.due) return fmt::format("{} <span class=\"nw-badge nw-due\">due now</span>", esc(p.name));
    if (!next || p.next_due_ns < next->next_due_ns) next = &p;
  }
  if (!next) return "<span class=\"nw-empty\">no period</span>";
  return fmt::format("{} at {}", esc(next->name), when(calendar, next->next_due_ns));
}

std::string periods_table(const Calendar& calendar, const plant_status::MachineDocument& m) {
  if (m.periods.empty()) return "<p class=\"nw-empty\">no period of the calendar applies</p>\n";
  std::string out =
      "<table class=\"nw-periods\"><thead><tr><th>period</th><th>every</th><th>last passed</th>"
      "<th>next due</th><th></th></tr></thead><tbody>\n";
  for (const auto& p : m.periods) {
    out += fmt::format(
        "<tr data-period=\"{}\"><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
        esc(p.name), esc(p.name), esc(p.every), when(calendar, p.last_pass_ns),
        p.due ? std::string("now") : when(calendar, p.next_due_ns),
        p.overdue ? "<span class=\"nw-badge nw-overdue\">OVERDUE</span>"
        : p.due   ? "<span class=\"nw-badge nw-due\">due</span>"
                  : "");
  }
  return out + "</tbody></table>\n";
}

std::string warnings_list(const Calendar& calendar, const plant_status::MachineDocument& m) {
  if (m.warnings.empty()) return "<p class=\"nw-empty\">no active trend warning</p>\n";
  std::string out = "<ul class=\"nw-warnings\">\n";
  for (const auto& w : m.warnings) {
    std::string dates;
    if (w.kind == "forecast") {
      dates = fmt::format("; reaches its tolerance earliest {}, expected {}",
                          when(calendar, w.earliest_crossing_ns),
                          when(calendar, w.expected_crossing_ns));
    }
    out += fmt::format(
        "<li class=\"nw-warning\" data-metric=\"{}\"><span class=\"nw-warning-kind\">{}</span> "
        "<b>{}</b> ({}) since {}{}<br>{}</li>\n",
        esc(w.metric), esc(w.kind), esc(w.metric), esc(w.side), when(calendar, w.started_ns), dates,
        esc(w.text));
  }
  return out + "</ul>\n";
}

std::string failures_table(const Calendar& calendar, const Failures& failures, bool with_machine,
                           const Limits& limits) {
  if (failures.empty()) return "<p class=\"nw-empty\">no failed check stored</p>\n";
  std::string out = fmt::format(
      "<table class=\"nw-failures\"><thead><tr>{}<th>check</th><th>kind</th><th>time</th>"
      "<th>verdict</th><th>reason</th></tr></thead><tbody>\n",
      with_machine ? "<th>machine</th>" : "");
  for (const auto& [machine, f] : failures) {
    out += fmt::format(
        "<tr data-request=\"{}\">{}<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
        esc(f.request_id), with_machine ? "<td>" + machine_link(machine) + "</td>" : "",
        check_link(f.request_id), kind_text(f.kind), when(calendar, f.time_ns),
        verdict_badge(f.verdict), esc(f.reason));
  }
  out += "</tbody></table>\n";
  if (failures.size() >= static_cast<std::size_t>(limits.failures)) {
    out += fmt::format("<p class=\"nw-note\">the newest {} shown</p>\n", limits.failures);
  }
  return out;
}

// A check's or machine's data produced by ncqual's simulator: a badge; measured data has none.
constexpr const char* kSimulatedBadge =
    "<span class=\"nw-badge nw-simulated\" title=\"produced by ncqual's simulator: says nothing "
    "about the machine\">SIMULATED</span>";

std::string simulated_badge(std::optional<DataOrigin> origin) {
  return origin == DataOrigin::Simulated ? std::string(" ") + kSimulatedBadge : std::string();
}

// The data column of a check: SIMULATED, measured, or not recorded (stored before schema 11).
std::string origin_text(DataOrigin origin) {
  switch (origin) {
    case DataOrigin::Simulated: return kSimulatedBadge;
    case DataOrigin::Measured: return "measured";
    case DataOrigin::Unknown: break;
  }
  return "<span class=\"nw-origin-unknown\">not recorded</span>";
}

// The banner above a page whose data is (partly) the simulator's.
std::string simulated_banner(const std::string& what) {
  return "<div class=\"nw-simulated-banner\" role=\"alert\"><strong>SIMULATED DATA</strong>: " +
         what +
         " produced by ncqual's simulator, not measured on a machine: its verdicts say nothing "
         "about a machine's accuracy.</div>\n";
}

std::string overdue_text(const plant_status::MachineDocument& m) {
  std::string names;
  for (const auto& p : m.periods) {
    if (p.overdue) names += (names.empty() ? "" : ", ") + esc(p.name);
  }
  return names.empty() ? std::string("none")
                       : "<span class=\"nw-badge nw-overdue\">OVERDUE</span> " + names;
}

}  // namespace

std::string plant_html(const PlantConfig& plant, const Calendar& calendar, const PlantView& view,
                       const Limits& limits) {
  const auto& status = view.status;
  std::string main;
  main += fmt::format("<h1>Plant {}</h1>\n", esc(plant.plant));
  main += fmt::format(
      "<p class=\"nw-asof\">as of {} ({}{}); {} machine{}</p>\n",
      esc(calendar.local_text(status.wall_now_ns, true)), esc(calendar.config().time_zone),
      plant.simulated_clock ? ", simulated clock: due dates as of each machine's newest status"
                            : "",
      status.machines.size(), status.machines.size() == 1 ? "" : "s");
  std::string simulated;
  for (const auto& m : status.machines) {
    if (m.last_check_origin == DataOrigin::Simulated) {
      simulated += (simulated.empty() ? "" : ", ") + esc(m.machine_id);
    }
  }
  if (!simulated.empty()) {
    main += simulated_banner("the newest check of " + simulated + " was");
  }
  main += "<div class=\"nw-machines\">\n";
  for (const auto& m : status.machines) {
    main += fmt::format("<section class=\"nw-machine\" id=\"machine-{}\" data-machine=\"{}\">\n",
                        esc(m.machine_id), esc(m.machine_id));
    main +=
        fmt::format("<h2>{} {}{}{}</h2>\n", machine_link(m.machine_id), state_badge(m.state),
                    simulated_badge(m.last_check_origin),
                    m.conflicts > 0 ? fmt::format(" <span class=\"nw-badge nw-bad\">CONFLICT: {}"
                                                  "</span>",
                                                  m.conflicts)
                                    : "");
    main += fmt::format("<p class=\"nw-detail\">{} &middot; since {}</p>\n", esc(m.detail),
                        when(calendar, m.status_time_ns));
    if (m.scheduler != "live") {
      main += fmt::format(
          "<p class=\"nw-no-scheduler\"><span class=\"nw-badge nw-bad\">no scheduler</span> {}: "
          "nothing is ordered, and <code>ncqual check</code> and <code>ncqual intervene</code> "
          "need a running one</p>\n",
          m.scheduler == "none" ? "none was heard" : "it " + m.scheduler);
    }
    main += "<table class=\"nw-summary\"><tbody>\n";
    main += fmt::format("<tr><th>next due</th><td class=\"nw-next-due\">{}</td></tr>\n",
                        next_due_text(calendar, m));
    main += fmt::format("<tr><th>overdue</th><td class=\"nw-overdue-periods\">{}</td></tr>\n",
                        overdue_text(m));
    std::string last_failure = "<span class=\"nw-empty\">none stored</span>";
    for (const auto& [machine, f] : view.failures) {
      if (machine != m.machine_id) continue;
      last_failure = fmt::format("{} {} {} at {}", check_link(f.request_id), kind_text(f.kind),
                                 verdict_badge(f.verdict), when(calendar, f.time_ns));
      break;
    }
    main += fmt::format("<tr><th>last failure</th><td class=\"nw-last-failure\">{}</td></tr>\n",
                        last_failure);
    main += "</tbody></table>\n";
    main += periods_table(calendar, m);
    main += fmt::format("<h3>Active trend warnings ({})</h3>\n", m.warnings.size());
    main += warnings_list(calendar, m);
    main += "</section>\n";
  }
  if (status.machines.empty())
    main += "<p class=\"nw-empty\">the plant configures no machine</p>\n";
  main += "</div>\n";
  main += "<h2>Last failures</h2>\n" + failures_table(calendar, view.failures, true, limits);
  main += fmt::format(
      "<h2>Services</h2>\n<p class=\"nw-note\">the last heartbeat the historian stored of each "
      "(one every {} ms); ages as of this page</p>\n",
      status.heartbeat_period_ms);
  if (status.services.empty()) {
    main += "<p class=\"nw-empty\">no heartbeat stored yet</p>\n";
  } else {
    main +=
        "<table class=\"nw-services\"><thead><tr><th>service</th><th>instance</th><th>state</th>"
        "<th>health</th><th>outbox</th><th>last heartbeat</th></tr></thead><tbody>\n";
    for (const auto& s : status.services) {
      const std::string health = s.health == "ok"
                                     ? "<span class=\"nw-badge nw-ok\">ok</span>"
                                     : fmt::format("<span class=\"nw-badge nw-bad\">{}</span> {}",
                                                   esc(s.health), esc(s.health_detail));
      main += fmt::format(
          "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"nw-num\">{}</td>"
          "<td>{}</td></tr>\n",
          esc(s.service), esc(s.instance),
          s.liveness == "live"      ? esc(s.state)
          : s.liveness == "stopped" ? std::string("stopped")
                                    : std::string("<span class=\"nw-badge nw-bad\">stale</span>"),
          health, s.outbox_depth, esc(calendar.local_text(s.time_ns, true)));
    }
    main += "</tbody></table>\n";
  }
  return page(plant, "plant " + plant.plant, view.token, "", main, "/api/v1/plant", limits);
}

std::string machine_html(const PlantConfig& plant, const Calendar& calendar,
                         const MachineView& view, const Limits& limits) {
  const auto& m = view.machine;
  std::string main;
  main +=
      fmt::format("<h1 data-machine=\"{}\">Machine {} {}{}</h1>\n", esc(m.machine_id),
                  esc(m.machine_id), state_badge(m.state), simulated_badge(m.last_check_origin));
  if (m.last_check_origin == DataOrigin::Simulated) {
    main += simulated_banner("its newest check (" + check_link(*m.last_check) + ") was");
  }
  if (const MachineConfig* config = plant.find_machine(m.machine_id);
      config && !config->description.empty()) {
    main += fmt::format("<p class=\"nw-detail\">{}</p>\n", esc(config->description));
  }
  main += fmt::format("<p class=\"nw-asof\">{} &middot; since {} &middot; as of {}</p>\n",
                      esc(m.detail), when(calendar, m.status_time_ns),
                      esc(calendar.local_text(view.wall_now_ns, true)));
  main += "<h2>Qualification</h2>\n" + periods_table(calendar, m);
  if (view.report_sections.empty()) {  // else the report has them, ended ones too
    main += fmt::format("<h2>Active trend warnings ({})</h2>\n", m.warnings.size());
    main += warnings_list(calendar, m);
  }
  main += "<h2>Last failures</h2>\n" + failures_table(calendar, view.failures, false, limits);
  if (!view.report_sections.empty()) {
    main += fmt::format(
        "<p class=\"nw-note\">the report of the last {} days (<a href=\"?days={}\">a year</a>, "
        "<a href=\"?days={}\">{} days</a>)</p>\n",
        view.days, limits.max_days, limits.days, limits.days);
    main += "<div class=\"nw-report\">\n" + view.report_sections + "</div>\n";
  } else {
    main += fmt::format("<h2>Report</h2>\n<p class=\"nw-empty\">no report: {}</p>\n",
                        esc(view.report_problem.empty() ? "no sections" : view.report_problem));
  }
  main += "<h2>Checks</h2>\n";
  if (view.checks.empty()) {
    main += "<p class=\"nw-empty\">no check stored</p>\n";
  } else {
    main +=
        "<table class=\"nw-checks\"><thead><tr><th>check</th><th>kind</th><th>time</th>"
        "<th>verdict</th><th>data</th><th>out of tolerance</th></tr></thead><tbody>\n";
    for (const auto& c : view.checks) {
      std::string out_of_tolerance;
      std::optional<std::int64_t> t;
      if (c.request) t = c.request->time_ns;
      if (c.result) {
        t = c.result->time_ns;
        for (const auto& metric : c.result->metrics) {
          if (metric.pass) continue;
          out_of_tolerance += (out_of_tolerance.empty() ? "" : ", ") +
                              fmt::format("{} {} {}", esc(metric.name),
                                          metric_number(metric, metric.value), esc(metric.unit));
        }
      }
      const DataOrigin origin = storage::origin_of(c);
      main += fmt::format(
          "<tr data-request=\"{}\" "
          "data-origin=\"{}\"{}><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
          "<td>{}</td><td>{}</td></tr>\n",
          esc(c.request_id), to_string(origin),
          origin == DataOrigin::Simulated ? " class=\"nw-simulated-row\"" : "",
          check_link(c.request_id), kind_text(c.kind), when(calendar, t),
          c.result ? verdict_badge(c.result->verdict) : std::string("pending"), origin_text(origin),
          out_of_tolerance);
    }
    main += "</tbody></table>\n";
    main += fmt::format(
        "<p class=\"nw-note\">the newest {} (at most {} listed); <a "
        "href=\"/api/v1/machines/{}?checks={}\">as JSON, up to {}</a></p>\n",
        view.checks.size(), limits.checks, url_segment(m.machine_id), limits.max_checks,
        limits.max_checks);
  }
  const std::string style = report::report_stylesheet();
  return page(plant, "machine " + m.machine_id, view.token,
              " <span>/</span> machine " + esc(m.machine_id), main,
              "/api/v1/machines/" + url_segment(m.machine_id), limits, style);
}

std::string check_html(const PlantConfig& plant, const Calendar& calendar,
                       const storage::CheckRecord& check, const std::string& token,
                       const Limits& limits) {
  std::string main;
  const DataOrigin origin = storage::origin_of(check);
  main += fmt::format("<h1 data-request=\"{}\" data-origin=\"{}\">Check {}{}</h1>\n",
                      esc(check.request_id), to_string(origin), esc(check.request_id),
                      simulated_badge(origin));
  if (origin == DataOrigin::Simulated) main += simulated_banner("this check was");
  main += fmt::format(
      "<p class=\"nw-asof\">machine {} &middot; {} &middot; {}</p>\n",
      plant.find_machine(check.machine_id) ? machine_link(check.machine_id) : esc(check.machine_id),
      kind_text(check.kind), esc(check_kind_info(check.kind).title));
  main += "<h2>Request</h2>\n";
  if (!check.request) {
    main += "<p class=\"nw-empty\">the request has not arrived</p>\n";
  } else {
    const auto& r = *check.request;
    main += "<table class=\"nw-request\"><tbody>\n";
    main += fmt::format("<tr><th>requested by</th><td>{}</td></tr>\n", esc(r.requested_by));
    main += fmt::format("<tr><th>requested at</th><td>{}</td></tr>\n", when(calendar, r.time_ns));
    main += fmt::format("<tr><th>attempt</th><td>{}</td></tr>\n", r.attempt);
    for (const auto& p : r.parameters) {
      main += fmt::format("<tr><th>{}</th><td>{} {}</td></tr>\n", esc(p.name), number(p.value),
                          esc(p.unit));
    }
    if (!r.verifies_correction_of.empty()) {
      main += fmt::format("<tr><th>verifies the correction of</th><td>{}</td></tr>\n",
                          check_link(r.verifies_correction_of));
    }
    main += "</tbody></table>\n";
  }
  main += "<h2>Measurement</h2>\n";
  if (!check.measurement) {
    main += "<p class=\"nw-empty\">the measurement has not arrived</p>\n";
  } else {
    const auto& s = *check.measurement;
    main += fmt::format(
        "<table class=\"nw-measurement\"><tbody><tr><th>instrument</th><td>{}</td></tr>"
        "<tr><th>data</th><td class=\"nw-origin\">{}</td></tr>"
        "<tr><th>measured at</th><td>{}</td></tr><tr><th>touches</th><td class=\"nw-num\">{}</td>"
        "</tr><tr><th>tracker points</th><td class=\"nw-num\">{}</td></tr>{}{}</tbody></table>\n",
        esc(s.instrument), origin_text(s.origin), when(calendar, s.time_ns), s.touches,
        s.tracker_points,
        s.error.empty() ? "" : "<tr><th>error</th><td>" + esc(s.error) + "</td></tr>",
        s.points_thinned_ns
            ? "<tr><th>points thinned</th><td>" + when(calendar, s.points_thinned_ns) + "</td></tr>"
            : "");
  }
  main += "<h2>Verdict</h2>\n";
  if (!check.result) {
    main += "<p class=\"nw-empty\">no result yet</p>\n";
  } else {
    const auto& r = *check.result;
    main += fmt::format("<p class=\"nw-verdict\">{}{} at {}{}</p>\n", verdict_badge(r.verdict),
                        simulated_badge(origin), when(calendar, r.time_ns),
                        r.reason.empty() ? "" : " &middot; " + esc(r.reason));
    if (!r.produced_by.empty()) {
      main += fmt::format("<p class=\"nw-note\">judged by {}</p>\n", esc(r.produced_by));
    }
    main += "<h2>Metrics</h2>\n";
    if (r.metrics.empty()) {
      main += "<p class=\"nw-empty\">none</p>\n";
    } else {
      main +=
          "<table class=\"nw-metrics\"><thead><tr><th>metric</th><th>value</th><th>lower</th>"
          "<th>upper</th><th>unit</th><th></th></tr></thead><tbody>\n";
      for (const auto& m : r.metrics) {
        main += fmt::format(
            "<tr data-metric=\"{}\"{}><td>{}</td><td class=\"nw-num nw-value\">{}</td>"
            "<td class=\"nw-num\">{}</td><td class=\"nw-num\">{}</td><td>{}</td><td>{}</td></tr>\n",
            esc(m.name), m.pass ? "" : " class=\"nw-out\"", esc(m.name), metric_number(m, m.value),
            metric_number(m, m.lower), metric_number(m, m.upper), esc(m.unit),
            m.pass ? "<span class=\"nw-badge nw-ok\">in</span>"
                   : "<span class=\"nw-badge nw-bad\">OUT</span>");
      }
      main += "</tbody></table>\n";
    }
    main += "<h2>Likely causes</h2>\n";
    if (r.likely_causes.empty()) {
      main += "<p class=\"nw-empty\">none named</p>\n";
    } else {
      main += "<ol class=\"nw-causes\">\n";
      for (const auto& c : r.likely_causes) main += "<li>" + esc(c) + "</li>\n";
      main += "</ol>\n";
    }
    main += "<h2>Correction</h2>\n";
    if (!r.correction) {
      main += "<p class=\"nw-empty\">none</p>\n";
    } else {
      main += fmt::format(
          "<p>target <b>{}</b></p>\n<table class=\"nw-correction\"><thead><tr><th>offset</th>"
          "<th>value</th><th>unit</th></tr></thead><tbody>\n",
          esc(r.correction->target));
      for (const auto& o : r.correction->offsets) {
        main += fmt::format("<tr><td>{}</td><td class=\"nw-num\">{}</td><td>{}</td></tr>\n",
                            esc(o.name), number(o.value), esc(o.unit));
      }
      main += "</tbody></table>\n";
    }
  }
  if (check.conflicts > 0) {
    main += fmt::format(
        "<p class=\"nw-note\"><span class=\"nw-badge nw-bad\">CONFLICT: {}</span> sample{} of this "
        "request "
        "kept beside these for other content</p>\n",
        check.conflicts, check.conflicts == 1 ? "" : "s");
  }
  const std::string nav = fmt::format(
      " <span>/</span> {} <span>/</span> check {}",
      plant.find_machine(check.machine_id) ? machine_link(check.machine_id) : esc(check.machine_id),
      esc(check.request_id));
  return page(plant, "check " + check.request_id, token, nav, main,
              "/api/v1/checks/" + url_segment(check.request_id), limits);
}

std::string error_page(const PlantConfig& plant, int status, const std::string& message) {
  const std::string main =
      fmt::format("<h1>{}</h1>\n<p class=\"nw-error\">{}</p>\n", status, esc(message)) +
      "<p><a href=\"/\">the plant page</a></p>\n";
  return page(plant, std::to_string(status), "", "", main, "/api/v1/plant", Limits{}, {}, false);
}

std::string report_sections(storage::Database& db, const MachineConfig& machine,
                            const Calendar& calendar, std::int64_t since_ns, std::int64_t now_ns,
                            report::BudgetMemo* budgets) {
  report::MachineReportQuery query;
  query.calendar = &calendar;
  query.budget_memo = budgets;
  query.machine_id = machine.machine_id;
  query.since_ns = since_ns;
  query.now_ns = now_ns;
  query.machine = &machine;
  return report::machine_report_sections(report::gather_machine_report(db, query));
}

}  // namespace ncqual::web
