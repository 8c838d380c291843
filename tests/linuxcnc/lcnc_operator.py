#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
# The stand-in operator of ncqual's LinuxCNC test, started by LinuxCNC as its DISPLAY program (no
# GUI). It does what a machine's operator or DNC watcher does with ncqual's control-files driver:
# switches the machine on and homes it, then for each probing program that appears in the outbox
# folder (in the order of their names) runs it in AUTO and, when the program has ended, moves the
# probe log LinuxCNC wrote (PROBEOPEN names it relative to the configuration's folder) into the
# inbox folder. It stops
# after NCQUAL_PROGRAMS programs or NCQUAL_DEADLINE_S seconds, and LinuxCNC ends with it.
# Environment: NCQUAL_OUTBOX, NCQUAL_INBOX (folders), NCQUAL_PROGRAMS (default 1),
# NCQUAL_DEADLINE_S (default 300), NCQUAL_OPERATOR_LOG (a file it also writes to: LinuxCNC sends a
# display's output to a temporary file it removes). Exit 0 when every program ran to its end.
import os
import re
import shutil
import sys
import time

import linuxcnc

outbox = os.environ["NCQUAL_OUTBOX"]
inbox = os.environ["NCQUAL_INBOX"]
wanted = int(os.environ.get("NCQUAL_PROGRAMS", "1"))
deadline = time.monotonic() + float(os.environ.get("NCQUAL_DEADLINE_S", "300"))

stat = linuxcnc.stat()
command = linuxcnc.command()
errors = linuxcnc.error_channel()


def say(text):
    line = "lcnc_operator: " + text
    print(line, flush=True)
    if os.environ.get("NCQUAL_OPERATOR_LOG"):
        with open(os.environ["NCQUAL_OPERATOR_LOG"], "a") as log:
            log.write(line + "\n")


def check_errors():
    message = errors.poll()
    if message:
        kind, text = message
        say("LinuxCNC %s: %s" % ("error" if kind in (linuxcnc.NML_ERROR, linuxcnc.OPERATOR_ERROR)
                                  else "message", text))
        return kind in (linuxcnc.NML_ERROR, linuxcnc.OPERATOR_ERROR)
    return False


def wait_until(condition, what, timeout=30.0):
    end = min(deadline, time.monotonic() + timeout)
    while time.monotonic() < end:
        stat.poll()
        if condition():
            return
        check_errors()
        time.sleep(0.05)
    raise RuntimeError("timed out waiting for " + what)


def switch_on_and_home():
    command.state(linuxcnc.STATE_ESTOP_RESET)
    wait_until(lambda: stat.task_state == linuxcnc.STATE_ESTOP_RESET, "E-stop reset")
    command.state(linuxcnc.STATE_ON)
    wait_until(lambda: stat.task_state == linuxcnc.STATE_ON, "machine on")
    command.mode(linuxcnc.MODE_MANUAL)
    wait_until(lambda: stat.task_mode == linuxcnc.MODE_MANUAL, "manual mode")
    command.home(-1)
    wait_until(lambda: all(stat.homed[j] for j in range(stat.joints)), "homing")
    say("machine on and homed")


def run(program):
    text = open(program).read()
    # A program without (PROBEOPEN file) only moves the machine (a test sets its state with one).
    match = re.search(r"\(PROBEOPEN ([^)]+)\)", text)
    log_name = match.group(1).strip() if match else None
    command.mode(linuxcnc.MODE_AUTO)
    wait_until(lambda: stat.task_mode == linuxcnc.MODE_AUTO, "auto mode")
    command.program_open(program)
    command.auto(linuxcnc.AUTO_RUN, 0)
    say("running " + program)
    wait_until(lambda: stat.interp_state != linuxcnc.INTERP_IDLE, "the program to start")
    failed = False
    while True:
        stat.poll()
        failed = check_errors() or failed
        if stat.interp_state == linuxcnc.INTERP_IDLE:
            break
        if time.monotonic() > deadline:
            command.abort()
            raise RuntimeError("deadline passed while running " + program)
        time.sleep(0.05)
    if log_name is None:
        return not failed
    # The log is where LinuxCNC opened it: relative to the configuration's folder (its cwd).
    log = os.path.join(os.getcwd(), log_name)
    if os.path.exists(log):
        shutil.move(log, os.path.join(inbox, log_name))
        say("moved %s to %s" % (log_name, inbox))
    else:
        say("the program wrote no probe log " + log)
    return not failed


def main():
    switch_on_and_home()
    done, ok = [], True
    while len(done) < wanted:
        if time.monotonic() > deadline:
            say("deadline passed after %d of %d programs" % (len(done), wanted))
            return 1
        # A program stays in the outbox until ncqual archives it with its log.
        programs = sorted(f for f in os.listdir(outbox)
                          if f.startswith("ncqual-") and f.endswith(".ngc") and f not in done)
        if not programs:
            time.sleep(0.1)
            continue
        ok = run(os.path.join(outbox, programs[0])) and ok
        done.append(programs[0])
    command.state(linuxcnc.STATE_OFF)
    say("%d program(s) run%s" % (len(done), "" if ok else " with errors"))
    return 0 if ok else 1


if __name__ == "__main__":
    try:
        sys.exit(main())
    except Exception as e:  # reported, and LinuxCNC ends with the operator
        say("stopped: %s" % e)
        sys.exit(1)
