#!/usr/bin/env python3
"""Smoke run of `humandyn bench --quick`: the JSON and CSV outputs exist, parse and hold every section with
sane values, the crowd's cores being those the process may run on (one, pinned to one CPU). Never checks a
speed (CI machines are shared).

usage: bench_smoke.py HUMANDYN_EXECUTABLE OUTPUT_DIR
"""
import csv
import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time


def fail(message):
    print("bench smoke: " + message, file=sys.stderr)
    sys.exit(1)


def main():
    exe, out = sys.argv[1], sys.argv[2]
    shutil.rmtree(out, ignore_errors=True)  # (what an earlier run left is no part of this one's outputs)
    os.makedirs(out)
    json_path = os.path.join(out, "bench.json")
    cmd = [exe, "bench", "--quick", "--model", "default", "--characters", "4",
           "--json", json_path, "--csv", out]
    run = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    if run.returncode != 0:
        fail("exit code %d\n%s%s" % (run.returncode, run.stdout, run.stderr))
    for section in ("1 kHz loop", "error against run time"):
        if section not in run.stdout:
            fail("stdout lacks the section '%s'" % section)

    with open(json_path) as f:
        doc = json.load(f)
    for key in ("machine", "model", "loop", "variants", "ratios", "work_precision", "crowd"):
        if key not in doc:
            fail("JSON lacks '%s'" % key)
    runs = doc["loop"]["runs"]
    if not runs:
        fail("no loop runs")
    for r in runs:
        if r["ticks"] < 1 or not (r["p50_us"] <= r["p99_us"] <= r["p999_us"] <= r["max_us"]):
            fail("loop run with inconsistent percentiles: %r" % r)
    variants = doc["variants"]
    names = {v["name"] for v in variants}
    for must in ("ID full double", "ID no-Coriolis double", "ID gravity double", "ID full float"):
        if must not in names:
            fail("variant '%s' missing" % must)
    for v in variants:
        if not (v["ns_per_call"] > 0 and math.isfinite(v["max_rel_error"])):
            fail("variant without a time or an error: %r" % v)
        if v["name"] == "ID full double" and v["max_rel_error"] > 1e-9:
            fail("full double inverse dynamics is not at round-off: %r" % v)
        if v["name"] == "ID full float" and v["max_rel_error"] == 0:
            fail("float shows no error at all: the comparison is not real")

    # the crowd's cores: those this process may run on; and on one CPU of them (as `taskset -c N` runs
    # it), one, not the machine's count
    cores = len(os.sched_getaffinity(0))
    if doc["crowd"]["cores"] != cores:
        fail("the crowd counts %r cores where the process may run on %d" % (doc["crowd"]["cores"], cores))
    one_cpu = min(os.sched_getaffinity(0))
    one_json = os.path.join(out, "one_cpu.json")
    pinned = subprocess.run([exe, "bench", "--quick", "--characters", "4", "--json", one_json], capture_output=True,
                            text=True, timeout=120, preexec_fn=lambda: os.sched_setaffinity(0, {one_cpu}))
    if pinned.returncode != 0:
        fail("on one CPU: exit code %d\n%s" % (pinned.returncode, pinned.stderr))
    with open(one_json) as f:
        one = json.load(f)["crowd"]
    if one["cores"] != 1 or "(1 core)" not in pinned.stdout or any(r["threads"] != 1 for r in one["rows"]):
        fail("on one CPU the crowd counts %r cores, threads %r" % (one["cores"], [r["threads"] for r in one["rows"]]))
    crowd = doc["crowd"]["rows"]
    if not any(r["lanes"] == "scalar loop" for r in crowd) or not any(r["lanes"].startswith("sse2") for r in crowd):
        fail("crowd rows lack the scalar loop or the SSE2 lanes: %r" % crowd)
    for r in crowd:
        if not (r["crowd"] >= 1024 and r["ns_per_character"] > 0 and r["refused"] == 0):
            fail("crowd row without a crowd, a time, or with refused steps: %r" % r)

    for name in ("bench_loop.csv", "bench_variants.csv"):
        with open(os.path.join(out, name)) as f:
            rows = list(csv.DictReader(f))
        if not rows:
            fail(name + " is empty")
    # the work-precision CSV says what the JSON says: a diverged run's error is an empty cell where it is null
    with open(os.path.join(out, "bench_work_precision.csv")) as f:
        rows = list(csv.DictReader(f))
    points = doc["work_precision"]["points"] if isinstance(doc["work_precision"], dict) else doc["work_precision"]
    if len(rows) != len(points):
        fail("bench_work_precision.csv has %d rows, the JSON %d points" % (len(rows), len(points)))
    for row, point in zip(rows, points):
        for key in ("q_error", "qd_error"):
            if (row[key] == "") != (point[key] is None) or (row[key] != "" and not math.isfinite(float(row[key]))):
                fail("work-precision %s differs between CSV (%r) and JSON (%r)" % (key, row[key], point[key]))
    print("bench smoke: outputs parse; %d loop runs, %d variant rows" % (len(runs), len(variants)))
    stopped_run(exe, out)
    other_model(exe, out)


# A model of another shape (a two-link arm from a URDF) runs the bench too: its loops on its own motion, in
# the runtime shape beside KDL, the seed's own rows left out.
ARM_URDF = """<robot name="arm">
  <link name="base"/>
  <link name="upper"><inertial><origin xyz="0.15 0 0"/><mass value="2"/>
    <inertia ixx="0.002" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial></link>
  <link name="fore"><inertial><origin xyz="0.12 0 0"/><mass value="1.2"/>
    <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="shoulder" type="continuous"><parent link="base"/><child link="upper"/><axis xyz="0 1 0"/></joint>
  <joint name="elbow" type="continuous"><parent link="upper"/><child link="fore"/><origin xyz="0.3 0 0"/>
    <axis xyz="0 1 0"/></joint>
</robot>
"""


def stopped_run(exe, out):
    """A run stopped on its way makes no --csv folder: it is made after the run, with the files."""
    folder = os.path.join(out, "stopped", "results")
    run = subprocess.Popen([exe, "bench", "--quick", "--characters", "4", "--csv", folder, "--json",
                            os.path.join(folder, "bench.json")], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(0.5)
    if run.poll() is not None:
        fail("the run to stop ended within half a second (exit code %d): nothing to stop" % run.returncode)
    run.send_signal(signal.SIGINT)
    run.wait(timeout=60)
    if os.path.exists(os.path.join(out, "stopped")):
        fail("a run stopped on its way (exit status %d) left its --csv folder: %s"
             % (run.returncode, os.listdir(os.path.join(out, "stopped"))))
    # a write that fails at the end (the JSON on a full device) removes the folders made for the CSV files
    full = subprocess.run([exe, "bench", "--quick", "--characters", "4", "--csv", folder, "--json", "/dev/full"],
                          capture_output=True, text=True, timeout=120)
    if full.returncode != 1 or "/dev/full: writing failed" not in full.stderr:
        fail("the JSON on /dev/full: exit code %d\n%s" % (full.returncode, full.stderr))
    if os.path.exists(os.path.join(out, "stopped")):
        fail("a run whose JSON could not be written left its --csv folder")
    # run through, the same command makes the folders and writes the JSON inside them
    done = subprocess.run([exe, "bench", "--quick", "--characters", "4", "--csv", folder, "--json",
                           os.path.join(folder, "bench.json")], capture_output=True, text=True, timeout=120)
    if done.returncode != 0:
        fail("into a new folder: exit code %d\n%s%s" % (done.returncode, done.stdout, done.stderr))
    made = sorted(os.listdir(folder))
    if made != ["bench.json", "bench_loop.csv", "bench_variants.csv", "bench_work_precision.csv"]:
        fail("into a new folder: %s" % made)


def other_model(exe, out):
    urdf = os.path.join(out, "arm.urdf")
    with open(urdf, "w") as f:
        f.write(ARM_URDF)
    json_path = os.path.join(out, "arm_bench.json")
    # its CSV folder holds an earlier run's work-precision file: replaced by one without points
    with open(os.path.join(out, "bench_work_precision.csv")) as f:
        if len(f.readlines()) < 2:
            fail("the seed body's work-precision CSV has no points")
    run = subprocess.run([exe, "bench", "--quick", "--model", urdf, "--characters", "4", "--json", json_path,
                          "--csv", out], capture_output=True, text=True, timeout=120)
    if run.returncode != 0:
        fail("the two-link arm: exit code %d\n%s%s" % (run.returncode, run.stdout, run.stderr))
    with open(json_path) as f:
        doc = json.load(f)
    works = {r["work"] for r in doc["loop"]["runs"]}
    if "humandyn ID (full, double, runtime shape)" not in works:
        fail("the two-link arm's loop runs lack humandyn's: %r" % works)
    if doc["joints"] != 2:
        fail("the two-link arm has %r joints in the JSON" % doc["joints"])
    if doc["crowd"] is not None or doc["work_precision"]:
        fail("the two-link arm has crowd rows or work-precision points, which need the seed's shape")
    with open(os.path.join(out, "bench_work_precision.csv")) as f:
        if len(list(csv.DictReader(f))) != 0:
            fail("the two-link arm's bench_work_precision.csv keeps the earlier run's points")


if __name__ == "__main__":
    main()
