// SPDX-License-Identifier: Apache-2.0
// ncqual-cyclone-peer: a DDS application of another vendor (Eclipse Cyclone DDS 0.10, C) that
// reads every ncqual topic and sends CheckCommands and Interventions. Its types are generated at
// build time by Cyclone's idlc from idl/ncqual.idl, the same file fastddsgen compiles for ncqual;
// nothing here is shared with ncqual's code. docs/integrators.md explains every choice below.
//
//   ncqual-cyclone-peer read --domain N --topic ncqual/<Type> --count K [--machine M]
//                            [--timeout S]
//     Prints each sample as one JSON line (every field; doubles with 17 significant digits, so
//     they read back bit for bit; a non-finite double as "NaN", "Infinity", "-Infinity"; enums by
//     their IDL name) until K distinct samples were printed. ncqual's producers send a sample
//     again until it is acknowledged, so a writer's history may hold one sample twice: a sample
//     equal in every field to one printed already is left out.
//   ncqual-cyclone-peer command --domain N --machine M --kind KIND [--request-id ID]
//                               [--requested-by WHO] [--param NAME=VALUE[:UNIT]]...
//                               [--readers R] [--timeout S]
//   ncqual-cyclone-peer intervene --domain N --machine M --check KIND --note TEXT
//                                 [--operator NAME] [--id ID] [--readers R] [--timeout S]
//     Waits until R readers of the topic have matched (default 1: the scheduler's); writes the
//     sample, and again while the scheduler has not answered on ncqual/Acknowledgement (0.25 s,
//     then twice as long each time, at most 2 s apart: ncqual's own tool does the same); then
//     waits until every matched reader has acknowledged what was written (dds_wait_for_acks).
//     Prints the sample sent, then the scheduler's Acknowledgement. The ids, the requester and
//     the time are made as ncqual's tool makes them unless given.
//
// Discovery and network: Cyclone's own configuration (CYCLONEDDS_URI). Exit codes: 0 done (the
// scheduler ACCEPTED the order), 1 failed or timed out, 2 bad usage, 4 the scheduler REFUSED it.
#define _GNU_SOURCE  // asprintf, strndup, open_memstream

#include "ncqual.h"

#include <dds/dds.h>

#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>
#include <unistd.h>

enum { kExitOk = 0, kExitFailed = 1, kExitUsage = 2, kExitRefused = 4 };

static const char* program = "ncqual-cyclone-peer";

static void fail(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  fprintf(stderr, "%s: ", program);
  vfprintf(stderr, fmt, args);
  fputc('\n', stderr);
  va_end(args);
  exit(kExitFailed);
}

static void print_usage(FILE* f) {
  fprintf(f,
          "usage: %s read --domain N --topic ncqual/<Type> --count K [--machine M] "
          "[--timeout S]\n"
          "       %s command --domain N --machine M --kind KIND [--request-id ID] "
          "[--requested-by WHO] [--param NAME=VALUE[:UNIT]]... [--readers R] [--timeout S]\n"
          "       %s intervene --domain N --machine M --check KIND --note TEXT "
          "[--operator NAME] [--id ID] [--readers R] [--timeout S]\n"
          "Discovery: Cyclone DDS's configuration, CYCLONEDDS_URI (docs/integrators.md).\n",
          program, program, program);
}

// Bad usage: what is wrong, then the usage; exit 2.
static void usage(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  fprintf(stderr, "%s: ", program);
  vfprintf(stderr, fmt, args);
  fputc('\n', stderr);
  va_end(args);
  print_usage(stderr);
  exit(kExitUsage);
}

// A DDS call that must succeed: its name and Cyclone's reason when it did not.
static dds_entity_t check(dds_entity_t rc, const char* what) {
  if (rc < 0) fail("%s failed: %s", what, dds_strretcode(rc));
  return rc;
}

// ---------------------------------------------------------------------------------------------
// JSON output

static const char* const kCheckKinds[] = {"MONUMENT_C_ALIGNMENT",
                                          "MONUMENT_TOOL_LENGTH",
                                          "MONUMENT_POSITIONING",
                                          "MONUMENT_C_ROTATION",
                                          "FIXTURE_PRECAL",
                                          "FIXTURE_POSTCAL",
                                          "PART_SETPOINTS",
                                          "GLOBAL_MASTER_FRAME",
                                          "GLOBAL_GRID",
                                          "ROTARY_W",
                                          "ROTARY_A",
                                          "ROTARY_C",
                                          "CIRCLE_XY",
                                          "CIRCLE_YZ",
                                          "CIRCLE_XZ",
                                          "LINEAR_AXIS_RUN"};
static const char* const kVerdicts[] = {"VERDICT_PASS", "VERDICT_FAIL", "VERDICT_INVALID"};
static const char* const kStates[] = {"STATE_UNKNOWN",  "STATE_QUALIFIED",
                                      "STATE_CHECKING", "STATE_NEEDS_INTERVENTION",
                                      "STATE_OVERDUE",  "STATE_OFFLINE"};
static const char* const kAckOutcomes[] = {"ACK_STORED", "ACK_DUPLICATE", "ACK_CONFLICT",
                                           "ACK_REFUSED", "ACK_ACCEPTED"};
static const char* const kAlarmKinds[] = {"ALARM_CONFLICT", "ALARM_STORAGE"};
static const char* const kOrigins[] = {"ORIGIN_UNKNOWN", "ORIGIN_MEASURED", "ORIGIN_SIMULATED"};
#define COUNT(a) (sizeof(a) / sizeof((a)[0]))
// The tables above follow the IDL's enumerators in order (a value beyond them is printed as its
// number, so a peer built from an older IDL still prints what a newer ncqual sends).
_Static_assert(ncqual_msg_LINEAR_AXIS_RUN == COUNT(kCheckKinds) - 1, "kCheckKinds");
_Static_assert(ncqual_msg_VERDICT_INVALID == COUNT(kVerdicts) - 1, "kVerdicts");
_Static_assert(ncqual_msg_STATE_OFFLINE == COUNT(kStates) - 1, "kStates");
_Static_assert(ncqual_msg_ACK_ACCEPTED == COUNT(kAckOutcomes) - 1, "kAckOutcomes");
_Static_assert(ncqual_msg_ALARM_STORAGE == COUNT(kAlarmKinds) - 1, "kAlarmKinds");
_Static_assert(ncqual_msg_ORIGIN_SIMULATED == COUNT(kOrigins) - 1, "kOrigins");

// One JSON object being written: its stream and whether a member came before.
typedef struct {
  FILE* f;
  bool members;
} Obj;

static Obj begin(FILE* f) {
  fputc('{', f);
  return (Obj){f, false};
}
static void end(Obj* o) { fputc('}', o->f); }
static FILE* key(Obj* o, const char* name) {
  fprintf(o->f, "%s\"%s\":", o->members ? "," : "", name);
  o->members = true;
  return o->f;
}

static void put_string(FILE* f, const char* s) {
  fputc('"', f);
  for (const unsigned char* p = (const unsigned char*)(s ? s : ""); *p; ++p) {
    if (*p == '"' || *p == '\\') {
      fprintf(f, "\\%c", *p);
    } else if (*p < 0x20) {
      fprintf(f, "\\u%04x", *p);
    } else {
      fputc(*p, f);  // UTF-8 passes through as it is
    }
  }
  fputc('"', f);
}
// 17 significant digits read back to the same double; ".0" keeps an integral value a JSON
// float (so -0 stays -0.0); JSON has no NaN or infinity: they are strings.
static void put_double(FILE* f, double v) {
  if (isnan(v)) {
    fputs("\"NaN\"", f);
  } else if (isinf(v)) {
    fputs(v > 0 ? "\"Infinity\"" : "\"-Infinity\"", f);
  } else {
    char text[40];
    snprintf(text, sizeof text, "%.17g", v);
    fprintf(f, "%s%s", text, strpbrk(text, ".e") ? "" : ".0");
  }
}
static void put_enum(FILE* f, const char* const* names, size_t count, int v) {
  if (v >= 0 && (size_t)v < count) {
    put_string(f, names[v]);
  } else {
    fprintf(f, "%d", v);  // not in this build's IDL: the number as it came
  }
}

static void str(Obj* o, const char* name, const char* v) { put_string(key(o, name), v); }
static void num(Obj* o, const char* name, double v) { put_double(key(o, name), v); }
static void i64(Obj* o, const char* name, int64_t v) { fprintf(key(o, name), "%" PRId64, v); }
static void boolean(Obj* o, const char* name, bool v) { fputs(v ? "true" : "false", key(o, name)); }
#define ENUM(o, name, table, v) put_enum(key(o, name), table, COUNT(table), (int)(v))
// A sequence member: `print` writes each element.
#define SEQ(o, name, seq, print)                      \
  do {                                                \
    FILE* f_ = key(o, name);                          \
    fputc('[', f_);                                   \
    for (uint32_t i_ = 0; i_ < (seq)._length; ++i_) { \
      if (i_) fputc(',', f_);                         \
      print(f_, &(seq)._buffer[i_]);                  \
    }                                                 \
    fputc(']', f_);                                   \
  } while (0)

static void print_axes(FILE* f, const ncqual_msg_AxisPosition* v) {
  Obj o = begin(f);
  num(&o, "x_mm", v->x_mm);
  num(&o, "y_mm", v->y_mm);
  num(&o, "z_mm", v->z_mm);
  num(&o, "w_mm", v->w_mm);
  num(&o, "a_rad", v->a_rad);
  num(&o, "c_rad", v->c_rad);
  end(&o);
}
static void print_vector(FILE* f, const ncqual_msg_Vector3* v) {
  Obj o = begin(f);
  num(&o, "x", v->x);
  num(&o, "y", v->y);
  num(&o, "z", v->z);
  end(&o);
}
static void print_touch(FILE* f, const ncqual_msg_Touch* v) {
  Obj o = begin(f);
  str(&o, "feature", v->feature);
  print_axes(key(&o, "axes"), &v->axes);
  print_vector(key(&o, "approach"), &v->approach);
  end(&o);
}
static void print_tracker_point(FILE* f, const ncqual_msg_TrackerPoint* v) {
  Obj o = begin(f);
  str(&o, "label", v->label);
  print_axes(key(&o, "commanded"), &v->commanded);
  print_vector(key(&o, "measured_mm"), &v->measured_mm);
  end(&o);
}
static void print_named_value(FILE* f, const ncqual_msg_NamedValue* v) {
  Obj o = begin(f);
  str(&o, "name", v->name);
  num(&o, "value", v->value);
  str(&o, "unit", v->unit);
  end(&o);
}
static void print_metric(FILE* f, const ncqual_msg_Metric* v) {
  Obj o = begin(f);
  str(&o, "name", v->name);
  num(&o, "value", v->value);
  str(&o, "unit", v->unit);
  num(&o, "lower", v->lower);
  num(&o, "upper", v->upper);
  boolean(&o, "pass", v->pass);
  end(&o);
}
static void print_string_element(FILE* f, char* const* v) { put_string(f, *v); }
static void print_correction(FILE* f, const ncqual_msg_SoftwareCorrection* v) {
  Obj o = begin(f);
  str(&o, "target", v->target);
  SEQ(&o, "offsets", v->offsets, print_named_value);
  end(&o);
}

static void print_check_request(FILE* f, const void* sample) {
  const ncqual_msg_CheckRequest* v = sample;
  Obj o = begin(f);
  str(&o, "machine_id", v->machine_id);
  str(&o, "request_id", v->request_id);
  ENUM(&o, "kind", kCheckKinds, v->kind);
  str(&o, "requested_by", v->requested_by);
  i64(&o, "time_ns", v->time_ns);
  i64(&o, "attempt", v->attempt);
  SEQ(&o, "parameters", v->parameters, print_named_value);
  str(&o, "verifies_correction_of", v->verifies_correction_of);
  end(&o);
}
static void print_check_command(FILE* f, const void* sample) {
  const ncqual_msg_CheckCommand* v = sample;
  Obj o = begin(f);
  str(&o, "machine_id", v->machine_id);
  str(&o, "request_id", v->request_id);
  ENUM(&o, "kind", kCheckKinds, v->kind);
  str(&o, "requested_by", v->requested_by);
  i64(&o, "time_ns", v->time_ns);
  SEQ(&o, "parameters", v->parameters, print_named_value);
  end(&o);
}
static void print_measurement_set(FILE* f, const void* sample) {
  const ncqual_msg_v2_MeasurementSet* v = sample;
  Obj o = begin(f);
  str(&o, "machine_id", v->machine_id);
  str(&o, "request_id", v->request_id);
  ENUM(&o, "kind", kCheckKinds, v->kind);
  str(&o, "instrument", v->instrument);
  str(&o, "frame", v->frame);
  i64(&o, "time_ns", v->time_ns);
  SEQ(&o, "touches", v->touches, print_touch);
  SEQ(&o, "tracker_points", v->tracker_points, print_tracker_point);
  str(&o, "error", v->error);
  SEQ(&o, "parameters", v->parameters, print_named_value);
  ENUM(&o, "origin", kOrigins, v->origin);
  end(&o);
}
static void print_check_result(FILE* f, const void* sample) {
  const ncqual_msg_v2_CheckResult* v = sample;
  Obj o = begin(f);
  str(&o, "machine_id", v->machine_id);
  str(&o, "request_id", v->request_id);
  ENUM(&o, "kind", kCheckKinds, v->kind);
  ENUM(&o, "verdict", kVerdicts, v->verdict);
  SEQ(&o, "metrics", v->metrics, print_metric);
  SEQ(&o, "likely_causes", v->likely_causes, print_string_element);
  str(&o, "reason", v->reason);
  boolean(&o, "has_correction", v->has_correction);
  print_correction(key(&o, "correction"), &v->correction);
  i64(&o, "time_ns", v->time_ns);
  str(&o, "produced_by", v->produced_by);
  ENUM(&o, "origin", kOrigins, v->origin);
  end(&o);
}
static void print_machine_status(FILE* f, const void* sample) {
  const ncqual_msg_MachineStatus* v = sample;
  Obj o = begin(f);
  str(&o, "machine_id", v->machine_id);
  str(&o, "request_id", v->request_id);
  ENUM(&o, "state", kStates, v->state);
  boolean(&o, "has_last_check", v->has_last_check);
  ENUM(&o, "last_kind", kCheckKinds, v->last_kind);
  ENUM(&o, "last_verdict", kVerdicts, v->last_verdict);
  str(&o, "detail", v->detail);
  i64(&o, "time_ns", v->time_ns);
  end(&o);
}
static void print_intervention(FILE* f, const void* sample) {
  const ncqual_msg_Intervention* v = sample;
  Obj o = begin(f);
  str(&o, "machine_id", v->machine_id);
  str(&o, "intervention_id", v->intervention_id);
  ENUM(&o, "kind", kCheckKinds, v->kind);
  str(&o, "note", v->note);
  str(&o, "operator_name", v->operator_name);
  i64(&o, "time_ns", v->time_ns);
  end(&o);
}
static void print_compensation(FILE* f, const void* sample) {
  const ncqual_msg_Compensation* v = sample;
  Obj o = begin(f);
  str(&o, "machine_id", v->machine_id);
  str(&o, "request_id", v->request_id);
  print_correction(key(&o, "correction"), &v->correction);
  i64(&o, "time_ns", v->time_ns);
  end(&o);
}
static void print_heartbeat(FILE* f, const void* sample) {
  const ncqual_msg_Heartbeat* v = sample;
  Obj o = begin(f);
  str(&o, "machine_id", v->machine_id);
  str(&o, "service", v->service);
  str(&o, "instance", v->instance);
  str(&o, "state", v->state);
  i64(&o, "time_ns", v->time_ns);
  str(&o, "health", v->health);
  str(&o, "health_detail", v->health_detail);
  i64(&o, "outbox_depth", v->outbox_depth);
  i64(&o, "oldest_unacknowledged_ns", v->oldest_unacknowledged_ns);
  end(&o);
}
static void print_acknowledgement(FILE* f, const void* sample) {
  const ncqual_msg_Acknowledgement* v = sample;
  Obj o = begin(f);
  str(&o, "machine_id", v->machine_id);
  str(&o, "topic", v->topic);
  str(&o, "sample_id", v->sample_id);
  str(&o, "content_hash", v->content_hash);
  ENUM(&o, "outcome", kAckOutcomes, v->outcome);
  str(&o, "by", v->by);
  str(&o, "instance", v->instance);
  str(&o, "detail", v->detail);
  i64(&o, "time_ns", v->time_ns);
  end(&o);
}
static void print_alarm(FILE* f, const void* sample) {
  const ncqual_msg_Alarm* v = sample;
  Obj o = begin(f);
  str(&o, "machine_id", v->machine_id);
  str(&o, "alarm_id", v->alarm_id);
  ENUM(&o, "kind", kAlarmKinds, v->kind);
  boolean(&o, "active", v->active);
  str(&o, "source", v->source);
  str(&o, "instance", v->instance);
  str(&o, "text", v->text);
  i64(&o, "time_ns", v->time_ns);
  end(&o);
}

// ---------------------------------------------------------------------------------------------
// The topics and the QoS of deploy/qos/ncqual-qos.xml

typedef enum { kDurable, kCommand, kAck, kAlarm, kHeartbeat } Profile;

typedef struct {
  const char* name;
  const dds_topic_descriptor_t* type;
  Profile profile;
  void (*print)(FILE*, const void*);
  // Written in the machine's partition "ncqual/machine/<id>" (docs/integrators.md).
  bool per_machine;
} TopicInfo;

static const TopicInfo kTopics[] = {
    {"ncqual/CheckRequest", &ncqual_msg_CheckRequest_desc, kDurable, print_check_request, true},
    {"ncqual/MeasurementSet", &ncqual_msg_v2_MeasurementSet_desc, kDurable, print_measurement_set,
     true},
    {"ncqual/CheckResult", &ncqual_msg_v2_CheckResult_desc, kDurable, print_check_result, false},
    {"ncqual/MachineStatus", &ncqual_msg_MachineStatus_desc, kDurable, print_machine_status, false},
    {"ncqual/Compensation", &ncqual_msg_Compensation_desc, kDurable, print_compensation, true},
    {"ncqual/CheckCommand", &ncqual_msg_CheckCommand_desc, kCommand, print_check_command, false},
    {"ncqual/Intervention", &ncqual_msg_Intervention_desc, kCommand, print_intervention, false},
    {"ncqual/Acknowledgement", &ncqual_msg_Acknowledgement_desc, kAck, print_acknowledgement,
     false},
    {"ncqual/Alarm", &ncqual_msg_Alarm_desc, kAlarm, print_alarm, false},
    {"ncqual/Heartbeat", &ncqual_msg_Heartbeat_desc, kHeartbeat, print_heartbeat, false},
};

// Every topic type begins with `@key string machine_id`: the --machine filter reads it there.
_Static_assert(offsetof(ncqual_msg_CheckRequest, machine_id) == 0, "machine_id first");
_Static_assert(offsetof(ncqual_msg_v2_MeasurementSet, machine_id) == 0, "machine_id first");
_Static_assert(offsetof(ncqual_msg_v2_CheckResult, machine_id) == 0, "machine_id first");
_Static_assert(offsetof(ncqual_msg_MachineStatus, machine_id) == 0, "machine_id first");
_Static_assert(offsetof(ncqual_msg_Compensation, machine_id) == 0, "machine_id first");
_Static_assert(offsetof(ncqual_msg_CheckCommand, machine_id) == 0, "machine_id first");
_Static_assert(offsetof(ncqual_msg_Intervention, machine_id) == 0, "machine_id first");
_Static_assert(offsetof(ncqual_msg_Acknowledgement, machine_id) == 0, "machine_id first");
_Static_assert(offsetof(ncqual_msg_Alarm, machine_id) == 0, "machine_id first");
_Static_assert(offsetof(ncqual_msg_Heartbeat, machine_id) == 0, "machine_id first");

static const TopicInfo* topic_named(const char* name) {
  for (size_t i = 0; i < COUNT(kTopics); ++i) {
    if (strcmp(kTopics[i].name, name) == 0) return &kTopics[i];
  }
  return NULL;
}

// The reader or writer QoS of a topic's profile in deploy/qos/ncqual-qos.xml. Reliability and
// durability decide matching (a reader may not ask for more than the writer offers); the
// history depth is the profile's. Data representation: XCDR1 only, the one Fast DDS 2.9 speaks.
static dds_qos_t* profile_qos(Profile profile) {
  dds_qos_t* qos = dds_create_qos();
  const bool reliable = profile != kHeartbeat;
  dds_qset_reliability(qos, reliable ? DDS_RELIABILITY_RELIABLE : DDS_RELIABILITY_BEST_EFFORT,
                       DDS_SECS(1));
  const bool durable = profile == kDurable || profile == kAlarm;
  dds_qset_durability(qos, durable ? DDS_DURABILITY_TRANSIENT_LOCAL : DDS_DURABILITY_VOLATILE);
  int32_t depth = 1;
  switch (profile) {
    case kDurable: depth = 500; break;
    case kCommand: depth = 100; break;
    case kAck: depth = 250; break;
    case kAlarm: depth = 100; break;
    case kHeartbeat: depth = 1; break;
  }
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, depth);
  const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
  dds_qset_data_representation(qos, 1, &xcdr1);
  return qos;
}

static dds_entity_t create_topic(dds_entity_t participant, const TopicInfo* t) {
  char what[160];
  snprintf(what, sizeof what, "dds_create_topic(%s, %s)", t->name, t->type->m_typename);
  return check(dds_create_topic(participant, t->type, t->name, NULL, NULL), what);
}

static dds_entity_t create_endpoint(dds_entity_t participant, const TopicInfo* t, bool writer) {
  dds_qos_t* qos = profile_qos(t->profile);
  const dds_entity_t topic = create_topic(participant, t);
  char what[160];
  snprintf(what, sizeof what, "%s of %s", writer ? "dds_create_writer" : "dds_create_reader",
           t->name);
  dds_entity_t e;
  if (writer) {
    e = dds_create_writer(participant, topic, qos, NULL);
  } else if (t->per_machine) {
    // Every machine's partition: a reader in the default partition would hear none of them.
    const char* every_machine[] = {"ncqual/machine/*"};
    dds_qos_t* in_every_machine = dds_create_qos();
    dds_qset_partition(in_every_machine, 1, every_machine);
    const dds_entity_t subscriber =
        check(dds_create_subscriber(participant, in_every_machine, NULL), "dds_create_subscriber");
    dds_delete_qos(in_every_machine);
    e = dds_create_reader(subscriber, topic, qos, NULL);
  } else {
    e = dds_create_reader(participant, topic, qos, NULL);
  }
  dds_delete_qos(qos);
  return check(e, what);
}

// ---------------------------------------------------------------------------------------------
// Time and waiting

static dds_time_t deadline_after(double seconds) {
  return dds_time() + (dds_duration_t)(seconds * 1e9);
}

// Blocks on `waitset` until it triggers or `deadline` passes; false at the deadline.
static bool wait_until(dds_entity_t waitset, dds_time_t deadline) {
  const dds_return_t rc = dds_waitset_wait_until(waitset, NULL, 0, deadline);
  if (rc < 0) fail("dds_waitset_wait_until failed: %s", dds_strretcode(rc));
  return rc > 0;
}

// ---------------------------------------------------------------------------------------------
// read

typedef struct {
  char** lines;
  size_t count, capacity;
} Lines;

static bool seen(const Lines* printed, const char* line) {
  for (size_t i = 0; i < printed->count; ++i) {
    if (strcmp(printed->lines[i], line) == 0) return true;
  }
  return false;
}

static void remember(Lines* printed, char* line) {
  if (printed->count == printed->capacity) {
    printed->capacity = printed->capacity ? 2 * printed->capacity : 64;
    printed->lines = realloc(printed->lines, printed->capacity * sizeof *printed->lines);
    if (!printed->lines) fail("out of memory");
  }
  printed->lines[printed->count++] = line;
}

// The sample as one JSON line (malloc'd, without the newline).
static char* json_line(const TopicInfo* t, const void* sample) {
  char* text = NULL;
  size_t size = 0;
  FILE* f = open_memstream(&text, &size);
  if (!f) fail("open_memstream: %s", strerror(errno));
  t->print(f, sample);
  if (fclose(f) != 0) fail("writing JSON: %s", strerror(errno));
  return text;
}

static int run_read(int domain, const TopicInfo* t, long count, const char* machine,
                    double timeout_s) {
  const dds_entity_t participant =
      check(dds_create_participant((dds_domainid_t)domain, NULL, NULL), "dds_create_participant");
  const dds_entity_t reader = create_endpoint(participant, t, false);
  const dds_entity_t waitset = check(dds_create_waitset(participant), "dds_create_waitset");
  const dds_entity_t ready =
      check(dds_create_readcondition(reader, DDS_ANY_STATE), "dds_create_readcondition");
  check(dds_waitset_attach(waitset, ready, 0), "dds_waitset_attach");

  const dds_time_t deadline = deadline_after(timeout_s);
  Lines printed = {0};
  long repeats = 0;
  enum { kBatch = 64 };
  while ((long)printed.count < count) {
    if (!wait_until(waitset, deadline)) {
      fprintf(stderr,
              "%s: %zu of %ld samples of %s%s%s within %g s (no more arrived; are the ncqual "
              "services running on domain %d, and is discovery configured, CYCLONEDDS_URI?)\n",
              program, printed.count, count, t->name, machine ? " of machine " : "",
              machine ? machine : "", timeout_s, domain);
      dds_delete(participant);
      return kExitFailed;
    }
    void* samples[kBatch] = {NULL};
    dds_sample_info_t infos[kBatch];
    const dds_return_t n = dds_take(reader, samples, infos, kBatch, kBatch);
    if (n < 0) fail("dds_take of %s failed: %s", t->name, dds_strretcode(n));
    for (dds_return_t i = 0; i < n && (long)printed.count < count; ++i) {
      if (!infos[i].valid_data) continue;  // an instance's state changed: no sample
      const char* machine_id = *(char* const*)samples[i];
      if (machine && strcmp(machine_id, machine) != 0) continue;
      char* line = json_line(t, samples[i]);
      if (seen(&printed, line)) {
        ++repeats;
        free(line);
        continue;
      }
      puts(line);
      remember(&printed, line);
    }
    fflush(stdout);
    if (n > 0) dds_return_loan(reader, samples, n);
  }
  if (repeats > 0) {
    fprintf(stderr, "%s: %ld repeated samples (sent again by their producer) left out\n", program,
            repeats);
  }
  for (size_t i = 0; i < printed.count; ++i) free(printed.lines[i]);
  free(printed.lines);
  dds_delete(participant);
  return kExitOk;
}

// ---------------------------------------------------------------------------------------------
// command, intervene

static int64_t now_ns(void) {
  struct timespec ts;
  clock_gettime(CLOCK_REALTIME, &ts);
  return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

// The scheduler's Acknowledgement of `sample_id` on `t` among what `acks` has received: printed,
// and the exit code it means; -1 while there is none.
static int take_answer(dds_entity_t acks, const TopicInfo* t, const char* sample_id) {
  const TopicInfo* ack_topic = topic_named("ncqual/Acknowledgement");
  int rc = -1;
  void* samples[16] = {NULL};
  dds_sample_info_t infos[16];
  const dds_return_t n = dds_take(acks, samples, infos, 16, 16);
  if (n < 0) fail("dds_take of ncqual/Acknowledgement failed: %s", dds_strretcode(n));
  for (dds_return_t i = 0; i < n && rc < 0; ++i) {
    const ncqual_msg_Acknowledgement* a = samples[i];
    if (!infos[i].valid_data || strcmp(a->topic, t->name) != 0 ||
        strcmp(a->sample_id, sample_id) != 0 || strcmp(a->by, "scheduler") != 0) {
      continue;  // another sample's, or another role's (the historian's of a relayed one)
    }
    char* line = json_line(ack_topic, a);
    puts(line);
    free(line);
    if (a->outcome == ncqual_msg_ACK_REFUSED) {
      fprintf(stderr, "%s: the scheduler refused %s: %s\n", program, sample_id, a->detail);
      rc = kExitRefused;
    } else {
      fprintf(stderr, "%s: the scheduler accepted %s%s%s\n", program, sample_id,
              a->detail[0] ? ": " : "", a->detail);
      rc = kExitOk;
    }
  }
  if (n > 0) dds_return_loan(acks, samples, n);
  return rc;
}

// Sends `sample` on `t` and waits for the scheduler's answer (see the top of the file).
static int send_order(int domain, const TopicInfo* t, const void* sample, const char* sample_id,
                      long readers, double timeout_s) {
  const dds_entity_t participant =
      check(dds_create_participant((dds_domainid_t)domain, NULL, NULL), "dds_create_participant");
  const dds_entity_t writer = create_endpoint(participant, t, true);
  // Before the first write: acknowledgements are volatile too.
  const dds_entity_t acks =
      create_endpoint(participant, topic_named("ncqual/Acknowledgement"), false);
  const dds_time_t deadline = deadline_after(timeout_s);
  int rc = -1;

  // 1. ncqual's readers of the topic are volatile: what is written before they match never
  //    reaches them. Wait on the writer's publication-matched status.
  const dds_entity_t matching = check(dds_create_waitset(participant), "dds_create_waitset");
  check(dds_set_status_mask(writer, DDS_PUBLICATION_MATCHED_STATUS), "dds_set_status_mask");
  check(dds_waitset_attach(matching, writer, 0), "dds_waitset_attach");
  dds_publication_matched_status_t matched;
  for (;;) {
    // Reading the status also resets it, so the waitset waits for the next change.
    check(dds_get_publication_matched_status(writer, &matched),
          "dds_get_publication_matched_status");
    if (matched.current_count >= (uint32_t)readers) break;
    if (!wait_until(matching, deadline)) {
      fprintf(stderr,
              "%s: %u of %ld reader(s) of %s matched within %g s: is a scheduler running on "
              "domain %d, and is discovery configured (CYCLONEDDS_URI)?\n",
              program, matched.current_count, readers, t->name, timeout_s, domain);
      dds_delete(participant);
      return kExitFailed;
    }
  }

  // 2. Written, and again while the scheduler has not answered (after 0.25 s, then twice as long
  //    each time, at most every 2 s): its acknowledgement may have gone out before our reader
  //    matched its writer. The scheduler takes a repeated order or intervention once.
  const dds_entity_t answers = check(dds_create_waitset(participant), "dds_create_waitset");
  const dds_entity_t ready =
      check(dds_create_readcondition(acks, DDS_ANY_STATE), "dds_create_readcondition");
  check(dds_waitset_attach(answers, ready, 0), "dds_waitset_attach");
  char what[120];
  snprintf(what, sizeof what, "dds_write of %s", t->name);
  dds_duration_t interval = DDS_MSECS(250);
  dds_time_t next_write = dds_time();
  bool printed = false;
  while (rc < 0) {
    if (dds_time() >= deadline) {
      fprintf(stderr, "%s: no scheduler acknowledged %s %s within %g s\n", program, t->name,
              sample_id, timeout_s);
      rc = kExitFailed;
      break;
    }
    if (dds_time() >= next_write) {
      check(dds_write(writer, sample), what);
      if (!printed) {
        char* sent = json_line(t, sample);
        puts(sent);
        fflush(stdout);
        free(sent);
        printed = true;
      }
      next_write = dds_time() + interval;
      interval = interval * 2 < DDS_SECS(2) ? interval * 2 : DDS_SECS(2);
    }
    wait_until(answers, next_write < deadline ? next_write : deadline);
    rc = take_answer(acks, t, sample_id);
  }
  fflush(stdout);

  // 3. Before leaving: every matched reader (the historian's too) has acknowledged what we wrote.
  const dds_duration_t left = deadline - dds_time();
  const dds_return_t acked = dds_wait_for_acks(writer, left > 0 ? left : 0);
  if (acked != DDS_RETCODE_OK) {
    fprintf(stderr, "%s: %s %s was not acknowledged by every matched reader within %g s: %s\n",
            program, t->name, sample_id, timeout_s, dds_strretcode(acked));
    if (rc == kExitOk) rc = kExitFailed;
  }
  dds_delete(participant);
  return rc;
}

// ---------------------------------------------------------------------------------------------
// Command line

typedef struct {
  const char* mode;
  long domain;
  const char* topic;
  long count;
  const char* machine;
  double timeout_s;
  const char* kind;
  const char* request_id;
  const char* requested_by;
  const char* note;
  const char* operator_name;
  long readers;
  ncqual_msg_NamedValue params[16];
  uint32_t param_count;
} Args;

static long parse_long(const char* flag, const char* text, long min, long max) {
  char* end = NULL;
  errno = 0;
  const long v = strtol(text, &end, 10);
  if (errno || end == text || *end || v < min || v > max) {
    usage("%s = '%s': expected an integer from %ld to %ld", flag, text, min, max);
  }
  return v;
}

static double parse_double(const char* flag, const char* text) {
  char* end = NULL;
  errno = 0;
  const double v = strtod(text, &end);
  if (errno || end == text || *end || !isfinite(v)) {
    usage("%s = '%s': expected a finite number", flag, text);
  }
  return v;
}

static int parse_kind(const char* flag, const char* text) {
  for (size_t i = 0; i < COUNT(kCheckKinds); ++i) {
    // The IDL name (MONUMENT_POSITIONING) or ncqual's (monument_positioning).
    if (strcasecmp(text, kCheckKinds[i]) == 0) return (int)i;
  }
  usage("%s = '%s': not a check kind of idl/ncqual.idl (e.g. monument_positioning)", flag, text);
  return -1;
}

// NAME=VALUE[:UNIT]
static ncqual_msg_NamedValue parse_param(const char* text) {
  const char* eq = strchr(text, '=');
  if (!eq || eq == text) usage("--param = '%s': expected NAME=VALUE[:UNIT]", text);
  ncqual_msg_NamedValue v = {0};
  v.name = strndup(text, (size_t)(eq - text));
  const char* colon = strchr(eq + 1, ':');
  char* number = colon ? strndup(eq + 1, (size_t)(colon - eq - 1)) : strdup(eq + 1);
  v.value = parse_double("--param", number);
  free(number);
  v.unit = strdup(colon ? colon + 1 : "");
  return v;
}

static Args parse(int argc, char** argv) {
  Args a = {0};
  a.domain = -1;
  a.timeout_s = 30;
  a.readers = 1;
  if (argc < 2) usage("no mode given");
  a.mode = argv[1];
  if (strcmp(a.mode, "-h") == 0 || strcmp(a.mode, "--help") == 0) {
    print_usage(stdout);
    exit(kExitOk);
  }
  if (strcmp(a.mode, "read") && strcmp(a.mode, "command") && strcmp(a.mode, "intervene")) {
    usage("unknown mode '%s'", a.mode);
  }
  for (int i = 2; i < argc; ++i) {
    const char* flag = argv[i];
    if (i + 1 >= argc) usage("%s needs a value", flag);
    const char* value = argv[++i];
    if (strcmp(flag, "--domain") == 0) {
      a.domain = parse_long(flag, value, 0, 232);
    } else if (strcmp(flag, "--topic") == 0) {
      a.topic = value;
    } else if (strcmp(flag, "--count") == 0) {
      a.count = parse_long(flag, value, 1, 100000000);
    } else if (strcmp(flag, "--machine") == 0) {
      a.machine = value;
    } else if (strcmp(flag, "--timeout") == 0) {
      a.timeout_s = parse_double(flag, value);
      if (a.timeout_s <= 0) usage("--timeout = '%s': expected seconds above 0", value);
    } else if (strcmp(flag, "--kind") == 0 || strcmp(flag, "--check") == 0) {
      a.kind = value;
    } else if (strcmp(flag, "--request-id") == 0 || strcmp(flag, "--id") == 0) {
      a.request_id = value;
    } else if (strcmp(flag, "--requested-by") == 0) {
      a.requested_by = value;
    } else if (strcmp(flag, "--note") == 0) {
      a.note = value;
    } else if (strcmp(flag, "--operator") == 0) {
      a.operator_name = value;
    } else if (strcmp(flag, "--readers") == 0) {
      a.readers = parse_long(flag, value, 1, 64);
    } else if (strcmp(flag, "--param") == 0) {
      if (a.param_count == COUNT(a.params)) usage("at most %zu --param", COUNT(a.params));
      a.params[a.param_count++] = parse_param(value);
    } else {
      usage("unknown flag '%s'", flag);
    }
  }
  if (a.domain < 0) usage("--domain is required (the plant's domain_id)");
  return a;
}

// "<prefix>-<machine>-<ns>-<pid>", as ncqual's own tool makes its ids.
static char* new_id(const char* prefix, const char* machine) {
  char* id = NULL;
  if (asprintf(&id, "%s-%s-%" PRId64 "-%ld", prefix, machine, now_ns(), (long)getpid()) < 0) {
    fail("out of memory");
  }
  return id;
}

static const char* user_name(void) {
  const char* user = getenv("USER");
  return user && *user ? user : "cyclone-peer";
}

int main(int argc, char** argv) {
  const Args a = parse(argc, argv);
  if (strcmp(a.mode, "read") == 0) {
    if (!a.topic) usage("--topic is required (e.g. ncqual/CheckResult)");
    const TopicInfo* t = topic_named(a.topic);
    if (!t) usage("--topic = '%s': not an ncqual topic (ncqual/CheckResult, ...)", a.topic);
    if (a.count <= 0) usage("--count is required: how many samples to print");
    return run_read((int)a.domain, t, a.count, a.machine, a.timeout_s);
  }
  if (!a.machine || !*a.machine) usage("--machine is required");
  if (!a.kind) usage("%s is required", strcmp(a.mode, "command") == 0 ? "--kind" : "--check");
  const int kind = parse_kind(strcmp(a.mode, "command") == 0 ? "--kind" : "--check", a.kind);

  if (strcmp(a.mode, "command") == 0) {
    char* who = NULL;
    if (!a.requested_by && asprintf(&who, "operator:%s", user_name()) < 0) fail("out of memory");
    ncqual_msg_CheckCommand cmd = {0};
    cmd.machine_id = (char*)a.machine;
    cmd.request_id = a.request_id ? (char*)a.request_id : new_id("cyclone", a.machine);
    cmd.kind = (ncqual_msg_CheckKind)kind;
    cmd.requested_by = a.requested_by ? (char*)a.requested_by : who;
    cmd.time_ns = now_ns();
    cmd.parameters._length = cmd.parameters._maximum = a.param_count;
    cmd.parameters._buffer = (ncqual_msg_NamedValue*)a.params;
    return send_order((int)a.domain, topic_named("ncqual/CheckCommand"), &cmd, cmd.request_id,
                      a.readers, a.timeout_s);
  }
  if (a.param_count) usage("--param is for command only");
  if (!a.note || !a.note[strspn(a.note, " \t")]) {
    usage("--note is required: say what was done (e.g. \"stylus replaced\")");
  }
  ncqual_msg_Intervention iv = {0};
  iv.machine_id = (char*)a.machine;
  iv.intervention_id = a.request_id ? (char*)a.request_id : new_id("iv-cyclone", a.machine);
  iv.kind = (ncqual_msg_CheckKind)kind;
  iv.note = (char*)a.note;
  iv.operator_name = a.operator_name ? (char*)a.operator_name : (char*)user_name();
  iv.time_ns = now_ns();
  return send_order((int)a.domain, topic_named("ncqual/Intervention"), &iv, iv.intervention_id,
                    a.readers, a.timeout_s);
}
