#!/usr/bin/env python3
"""tools/plot_bench.py on a bench JSON: both charts come out as valid SVG and PNG, the SVG names every
variant and integrator of the JSON, runs with an exact-zero error are drawn (on a floor line), and a JSON
that cannot be read is an error, not an empty chart.

usage: plot_bench_check.py PYTHON PLOT_SCRIPT BENCH.json
"""

import json
import os
import subprocess
import sys
import tempfile

from chart_check import check_png, svg_text


def main(python, script, fixture):
    probe = subprocess.run([python, "-c", "import matplotlib"], capture_output=True, text=True)
    if probe.returncode != 0:
        sys.exit(f"{python} has no matplotlib: install python3-matplotlib (Debian) for the bench's charts")
    with open(fixture, encoding="utf-8") as f:
        bench = json.load(f)
    with tempfile.TemporaryDirectory() as out:
        run = subprocess.run([python, script, fixture, out], capture_output=True, text=True)
        assert run.returncode == 0, f"plot_bench failed ({run.returncode}): {run.stderr}"
        texts = {}
        for stem in ("error_vs_time", "work_precision"):
            check_png(os.path.join(out, stem + ".png"))
            texts[stem] = svg_text(os.path.join(out, stem + ".svg"))
        assert "Error against run time" in texts["error_vs_time"]
        for name in {v["name"] for v in bench["variants"]}:
            assert name in texts["error_vs_time"], f"the legend does not name variant '{name}'"
        assert "Integration work-precision" in texts["work_precision"]
        for integrator in {r["integrator"] for r in bench["work_precision"] if r["ok"]}:
            assert integrator in texts["work_precision"], f"the legend does not name integrator '{integrator}'"
        if any(not r["ok"] for r in bench["work_precision"]):
            assert "diverged, not drawn" in texts["work_precision"], "diverged runs are not listed"

        # runs that end exactly where the reference does (a body at rest without gravity): drawn on the
        # floor line, not called diverged
        exact = dict(bench, work_precision=[dict(r, ok=True, q_error=0.0, ms_per_sim_second=1.0)
                                            for r in bench["work_precision"]])
        exact_json = os.path.join(out, "exact.json")
        with open(exact_json, "w", encoding="utf-8") as f:
            json.dump(exact, f)
        exact_out = os.path.join(out, "exact")
        run = subprocess.run([python, script, exact_json, exact_out], capture_output=True, text=True)
        assert run.returncode == 0, f"plot_bench failed on exact zeros ({run.returncode}): {run.stderr}"
        text = svg_text(os.path.join(exact_out, "work_precision.svg"))
        assert "exact 0" in text and "diverged" not in text, "exact zeros are not drawn on the floor line"
        for integrator in {r["integrator"] for r in exact["work_precision"]}:
            assert integrator in text, f"the legend does not name integrator '{integrator}' at exact zeros"

        # a file that is not there, or not JSON: exit code 1 and the file's name
        for bad in (os.path.join(out, "missing.json"), os.path.join(out, "error_vs_time.png")):
            run = subprocess.run([python, script, bad, out], capture_output=True, text=True)
            assert run.returncode == 1 and bad in run.stderr, f"{bad}: exit {run.returncode}, {run.stderr!r}"
    print("plot_bench: both charts valid SVG and PNG, every variant and integrator named")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
