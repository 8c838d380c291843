-- A historian at schema version 1, with rows in every table: the fixture of
-- StorageMigration.VersionOneFileReadsBackEveryRowAtTheLatestVersion (tests/unit/storage).
-- tests/data/README.md says how it was made. Do not edit the schema part: it is version 1 exactly
-- as the first migration created it (the test compares it with that migration).
BEGIN;
-- ---- the first migration, verbatim (storage/src/schema.cpp, kVersion1, commit a7f0026) ----
CREATE TABLE machines (
  machine_id    TEXT NOT NULL PRIMARY KEY,
  first_seen_ns INTEGER NOT NULL,
  last_seen_ns  INTEGER NOT NULL
) STRICT, WITHOUT ROWID;

CREATE TABLE requests (
  request_id   TEXT NOT NULL PRIMARY KEY,
  machine_id   TEXT NOT NULL,
  kind         INTEGER NOT NULL,
  kind_name    TEXT NOT NULL,
  requested_by TEXT NOT NULL,
  time_ns      INTEGER NOT NULL,
  attempt      INTEGER NOT NULL
) STRICT;
CREATE INDEX requests_by_machine_time ON requests (machine_id, time_ns);

CREATE TABLE measurement_sets (
  request_id TEXT NOT NULL PRIMARY KEY,
  machine_id TEXT NOT NULL,
  kind       INTEGER NOT NULL,
  instrument TEXT NOT NULL,
  frame      TEXT NOT NULL,
  time_ns    INTEGER NOT NULL,
  error      TEXT NOT NULL
) STRICT;
CREATE INDEX measurement_sets_by_machine_time ON measurement_sets (machine_id, time_ns);

CREATE TABLE touches (
  request_id TEXT NOT NULL REFERENCES measurement_sets (request_id) ON DELETE CASCADE,
  idx        INTEGER NOT NULL,
  feature    TEXT NOT NULL,
  x_mm REAL NOT NULL, y_mm REAL NOT NULL, z_mm REAL NOT NULL,
  w_mm REAL NOT NULL, a_rad REAL NOT NULL, c_rad REAL NOT NULL,
  ux REAL NOT NULL, uy REAL NOT NULL, uz REAL NOT NULL,
  PRIMARY KEY (request_id, idx)
) STRICT, WITHOUT ROWID;

CREATE TABLE tracker_points (
  request_id TEXT NOT NULL REFERENCES measurement_sets (request_id) ON DELETE CASCADE,
  idx        INTEGER NOT NULL,
  label      TEXT NOT NULL,
  x_mm REAL NOT NULL, y_mm REAL NOT NULL, z_mm REAL NOT NULL,
  w_mm REAL NOT NULL, a_rad REAL NOT NULL, c_rad REAL NOT NULL,
  measured_x_mm REAL NOT NULL, measured_y_mm REAL NOT NULL, measured_z_mm REAL NOT NULL,
  PRIMARY KEY (request_id, idx)
) STRICT, WITHOUT ROWID;

CREATE TABLE results (
  request_id        TEXT NOT NULL PRIMARY KEY,
  machine_id        TEXT NOT NULL,
  kind              INTEGER NOT NULL,
  verdict           TEXT NOT NULL CHECK (verdict IN ('PASS', 'FAIL', 'INVALID')),
  reason            TEXT NOT NULL,
  time_ns           INTEGER NOT NULL,
  correction_target TEXT
) STRICT;
CREATE INDEX results_by_machine_time ON results (machine_id, time_ns);

CREATE TABLE metrics (
  request_id TEXT NOT NULL REFERENCES results (request_id) ON DELETE CASCADE,
  idx        INTEGER NOT NULL,
  name       TEXT NOT NULL,
  value      REAL NOT NULL,
  unit       TEXT NOT NULL,
  lower      REAL NOT NULL,
  upper      REAL NOT NULL,
  pass       INTEGER NOT NULL CHECK (pass IN (0, 1)),
  PRIMARY KEY (request_id, idx)
) STRICT, WITHOUT ROWID;

CREATE TABLE causes (
  request_id TEXT NOT NULL REFERENCES results (request_id) ON DELETE CASCADE,
  rank       INTEGER NOT NULL,
  cause      TEXT NOT NULL,
  PRIMARY KEY (request_id, rank)
) STRICT, WITHOUT ROWID;

CREATE TABLE result_offsets (
  request_id TEXT NOT NULL REFERENCES results (request_id) ON DELETE CASCADE,
  idx        INTEGER NOT NULL,
  name       TEXT NOT NULL,
  value      REAL NOT NULL,
  unit       TEXT NOT NULL,
  PRIMARY KEY (request_id, idx)
) STRICT, WITHOUT ROWID;

CREATE TABLE checks (
  request_id      TEXT NOT NULL PRIMARY KEY,
  machine_id      TEXT NOT NULL,
  kind            INTEGER NOT NULL,
  requested_at_ns INTEGER,
  measured_at_ns  INTEGER,
  result_at_ns    INTEGER,
  sort_ns         INTEGER NOT NULL
                  GENERATED ALWAYS AS (coalesce(result_at_ns, requested_at_ns, measured_at_ns))
) STRICT, WITHOUT ROWID;
CREATE INDEX checks_by_machine_time ON checks (machine_id, sort_ns);
CREATE INDEX checks_by_time ON checks (sort_ns);

CREATE TABLE status_changes (
  id           INTEGER PRIMARY KEY,
  machine_id   TEXT NOT NULL,
  request_id   TEXT NOT NULL,
  state        TEXT NOT NULL,
  last_kind    INTEGER,
  last_verdict TEXT,
  detail       TEXT NOT NULL,
  time_ns      INTEGER NOT NULL,
  UNIQUE (machine_id, time_ns, state, request_id)
) STRICT;

CREATE TABLE interventions (
  intervention_id TEXT NOT NULL PRIMARY KEY,
  machine_id      TEXT NOT NULL,
  kind            INTEGER NOT NULL,
  note            TEXT NOT NULL,
  operator_name   TEXT NOT NULL,
  time_ns         INTEGER NOT NULL
) STRICT;
CREATE INDEX interventions_by_machine_time ON interventions (machine_id, time_ns);

CREATE TABLE compensations (
  id         INTEGER PRIMARY KEY,
  request_id TEXT NOT NULL,
  target     TEXT NOT NULL,
  machine_id TEXT NOT NULL,
  time_ns    INTEGER NOT NULL,
  UNIQUE (request_id, target)
) STRICT;
CREATE INDEX compensations_by_machine_time ON compensations (machine_id, time_ns);

CREATE TABLE compensation_offsets (
  compensation_id INTEGER NOT NULL REFERENCES compensations (id) ON DELETE CASCADE,
  idx             INTEGER NOT NULL,
  name            TEXT NOT NULL,
  value           REAL NOT NULL,
  unit            TEXT NOT NULL,
  PRIMARY KEY (compensation_id, idx)
) STRICT, WITHOUT ROWID;

CREATE TABLE services (
  service       TEXT NOT NULL,
  instance      TEXT NOT NULL,
  machine_id    TEXT NOT NULL,
  state         TEXT NOT NULL,
  first_seen_ns INTEGER NOT NULL,
  last_seen_ns  INTEGER NOT NULL,
  PRIMARY KEY (service, instance)
) STRICT, WITHOUT ROWID;

PRAGMA application_id = 1852010869;

-- ---- rows, as version 1's stores wrote them (storage/src/database.cpp at a7f0026) ----------
-- Reals are binary fractions (exact in decimal), so a value read back compares equal.
-- 9e999 is SQLite's text for an infinite bound (a one-sided tolerance band).

-- pm1-c-align-1: daily check 1, requested, measured (4 touches), PASS.
-- pm1-precal-1: weekly fixture check, FAIL with a correction and its Compensation.
-- pm2-master-1: monthly master frame by laser tracker (3 points), INVALID.
-- pm2-master-2: the tracker could not measure (error), no result.
-- pm1-late-1: a result whose request never arrived.
INSERT INTO requests (request_id, machine_id, kind, kind_name, requested_by, time_ns, attempt) VALUES
  ('pm1-c-align-1', 'pm1', 0, 'monument_c_alignment', 'scheduler', 1780000000000000000, 1),
  ('pm1-precal-1', 'pm1', 4, 'fixture_precal', 'scheduler', 1780000600000000000, 2),
  ('pm2-master-1', 'pm2', 7, 'global_master_frame', 'operator:ada', 1780001200000000000, 1),
  ('pm2-master-2', 'pm2', 7, 'global_master_frame', 'operator:ada', 1780001800000000000, 1);

INSERT INTO measurement_sets (request_id, machine_id, kind, instrument, frame, time_ns, error) VALUES
  ('pm1-c-align-1', 'pm1', 0, 'touch_probe', 'machine', 1780000060000000000, ''),
  ('pm1-precal-1', 'pm1', 4, 'fixture_probe', 'fixture', 1780000660000000000, ''),
  ('pm2-master-1', 'pm2', 7, 'laser_tracker', 'tracker', 1780001260000000000, ''),
  ('pm2-master-2', 'pm2', 7, 'laser_tracker', 'tracker', 1780001860000000000,
   'tracker lost the reflector at P2');

INSERT INTO touches (request_id, idx, feature, x_mm, y_mm, z_mm, w_mm, a_rad, c_rad, ux, uy, uz) VALUES
  ('pm1-c-align-1', 0, 'hole_edge', 1225.0078125, 800.0, 145.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0),
  ('pm1-c-align-1', 1, 'hole_edge', 1174.9921875, 800.0, 145.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0),
  ('pm1-c-align-1', 2, 'hole_edge', 1200.0, 825.00390625, 145.0, 0.0, 0.0, 3.140625, 0.0, -1.0, 0.0),
  ('pm1-c-align-1', 3, 'face', 1200.0, 774.99609375, 145.0, 0.5, -1.5703125, 3.140625, 0.0, 0.0, -1.0),
  ('pm1-precal-1', 0, 'pogo_C2R3', 410.25, 220.5, 95.125, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0),
  ('pm1-precal-1', 1, 'pogo_C4R1', 610.75, 20.5, 95.0625, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0);

INSERT INTO tracker_points (request_id, idx, label, x_mm, y_mm, z_mm, w_mm, a_rad, c_rad,
                            measured_x_mm, measured_y_mm, measured_z_mm) VALUES
  ('pm2-master-1', 0, 'P0', 0.0, 0.0, 500.0, 0.0, 0.0, 0.0, 1500.0078125, -250.00390625, 300.0),
  ('pm2-master-1', 1, 'P1', 500.0, 0.0, 500.0, 0.0, 0.0, 0.0, 2000.015625, -250.0078125, 300.001953125),
  ('pm2-master-1', 2, 'P2', 0.0, 500.0, 500.0, 12.5, 0.25, -0.125, 1499.9921875, 250.0, 300.0);

INSERT INTO results (request_id, machine_id, kind, verdict, reason, time_ns, correction_target) VALUES
  ('pm1-c-align-1', 'pm1', 0, 'PASS', '', 1780000120000000000, NULL),
  ('pm1-precal-1', 'pm1', 4, 'FAIL', 'pogo_C2R3_dx_mm = 0.047 mm: out of tolerance', 1780000720000000000,
   'fixture:F1'),
  ('pm2-master-1', 'pm2', 7, 'INVALID', 'tracker_points: 3, the master frame needs 11', 1780001320000000000,
   NULL),
  ('pm1-late-1', 'pm1', 2, 'PASS', '', 1780002400000000000, NULL);

INSERT INTO metrics (request_id, idx, name, value, unit, lower, upper, pass) VALUES
  ('pm1-c-align-1', 0, 'c_align_dx_mm', 0.00390625, 'mm', -0.015625, 0.015625, 1),
  ('pm1-c-align-1', 1, 'c_align_dy_mm', -0.001953125, 'mm', -0.015625, 0.015625, 1),
  ('pm1-c-align-1', 2, 'probe_c_offset_mm', 0.0078125, 'mm', -9e999, 0.03125, 1),
  ('pm1-precal-1', 0, 'pogo_C2R3_dx_mm', 0.046875, 'mm', -0.03125, 0.03125, 0),
  ('pm1-precal-1', 1, 'fixture_max_dx_mm', 0.046875, 'mm', -9e999, 0.03125, 0),
  ('pm2-master-1', 0, 'master_orthogonality_urad', 12.5, 'urad', -40.0, 40.0, 1),
  ('pm1-late-1', 0, 'center_dx_mm', 0.0009765625, 'mm', -0.03125, 0.03125, 1);

INSERT INTO causes (request_id, rank, cause) VALUES
  ('pm1-c-align-1', 0, 'bent stylus'),
  ('pm1-c-align-1', 1, 'probe microswitches'),
  ('pm1-precal-1', 0, 'pogo C2R3 displaced'),
  ('pm1-precal-1', 1, 'fixture base moved'),
  ('pm1-precal-1', 2, 'thermal growth of the fixture');

INSERT INTO result_offsets (request_id, idx, name, value, unit) VALUES
  ('pm1-precal-1', 0, 'pogo_C2R3_dx_mm', -0.046875, 'mm'),
  ('pm1-precal-1', 1, 'pogo_C2R3_dy_mm', 0.015625, 'mm');

-- Derived: one row per request id, with the time each part arrived with.
INSERT INTO checks (request_id, machine_id, kind, requested_at_ns, measured_at_ns, result_at_ns) VALUES
  ('pm1-c-align-1', 'pm1', 0, 1780000000000000000, 1780000060000000000, 1780000120000000000),
  ('pm1-precal-1', 'pm1', 4, 1780000600000000000, 1780000660000000000, 1780000720000000000),
  ('pm2-master-1', 'pm2', 7, 1780001200000000000, 1780001260000000000, 1780001320000000000),
  ('pm2-master-2', 'pm2', 7, 1780001800000000000, 1780001860000000000, NULL),
  ('pm1-late-1', 'pm1', 2, NULL, NULL, 1780002400000000000);

INSERT INTO status_changes (id, machine_id, request_id, state, last_kind, last_verdict, detail, time_ns) VALUES
  (1, 'pm2', '', 'UNKNOWN', NULL, NULL, 'scheduler started', 1780000000000000000),
  (2, 'pm1', 'pm1-c-align-1', 'QUALIFIED', 0, 'PASS', 'monument_c_alignment PASS', 1780000121000000000),
  (3, 'pm1', 'pm1-precal-1', 'NEEDS_INTERVENTION', 4, 'FAIL', 'fixture_precal FAIL: pogo C2R3',
   1780000721000000000);

INSERT INTO interventions (intervention_id, machine_id, kind, note, operator_name, time_ns) VALUES
  ('int-pm1-1', 'pm1', 4, 're-seated pogo C2R3, torqued to 12 N·m', 'ada', 1780000900000000000);

INSERT INTO compensations (id, request_id, target, machine_id, time_ns) VALUES
  (1, 'pm1-precal-1', 'fixture:F1', 'pm1', 1780000720000000000);
INSERT INTO compensation_offsets (compensation_id, idx, name, value, unit) VALUES
  (1, 0, 'pogo_C2R3_dx_mm', -0.046875, 'mm'),
  (1, 1, 'pogo_C2R3_dy_mm', 0.015625, 'mm');

INSERT INTO services (service, instance, machine_id, state, first_seen_ns, last_seen_ns) VALUES
  ('historian', 'cell-pc:4711', '', 'running', 1779999990000000000, 1780002400000000000),
  ('acquisition', 'cell-pc:4712', 'pm1', 'running', 1779999995000000000, 1780002390000000000);

-- Every machine named by a sample, first and last sample time over all of them.
INSERT INTO machines (machine_id, first_seen_ns, last_seen_ns) VALUES
  ('pm1', 1779999995000000000, 1780002400000000000),
  ('pm2', 1780000000000000000, 1780001860000000000);

PRAGMA user_version = 1;
COMMIT;
