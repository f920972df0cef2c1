#!/usr/bin/env python3
"""tools/plot_torques.py on a small torque file (the columns `humandyn id` writes, and a ground reaction):
the chart comes out as valid SVG and PNG naming every joint and limb drawn; --joints draws only those;
a bad file is an error naming the file, line and column, not an empty chart.

usage: plot_torques_check.py PYTHON PLOT_SCRIPT WORK_DIR
"""

import math
import os
import shutil
import subprocess
import sys

from chart_check import check_png, svg_text


def main(python, script, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    joints = ["r_ankle_pitch", "r_knee_pitch", "waist_pitch", "l_shoulder_pitch", "l_knee_pitch"]
    torques = os.path.join(work, "tau.csv")
    with open(torques, "w") as f:
        f.write("t," + ",".join("tau_" + j for j in joints) + ",grf_fz\n")
        for k in range(50):
            f.write(f"{k / 100}," + ",".join(str(round(10 * (i + 1) * math.sin(k / 8 + i), 6)) for i in range(5)) +
                    f",{700 + 30 * math.cos(k / 8)}\n")

    out = os.path.join(work, "all")
    run = subprocess.run([python, script, torques, out], capture_output=True, text=True)
    assert run.returncode == 0, f"plot_torques failed ({run.returncode}): {run.stderr}"
    check_png(os.path.join(out, "torques.png"))
    text = svg_text(os.path.join(out, "torques.svg"))
    for name in joints + ["right leg", "left leg", "waist", "arms", "ground reaction", "time (s)"]:
        assert name in text, f"the chart does not name '{name}'"

    out = os.path.join(work, "knees")
    run = subprocess.run([python, script, torques, out, "--joints", "r_knee_pitch,l_knee_pitch"],
                         capture_output=True, text=True)
    assert run.returncode == 0, f"plot_torques --joints failed ({run.returncode}): {run.stderr}"
    text = svg_text(os.path.join(out, "torques.svg"))
    assert "r_knee_pitch" in text and "l_knee_pitch" in text and "waist_pitch" not in text, "--joints not obeyed"

    # a file name with a control character and a byte that is not UTF-8: the title shows them, as humandyn's
    # messages do, and the SVG stays XML
    odd = os.path.join(os.fsencode(work), b"t\x01a\xffu.csv")
    shutil.copyfile(torques, odd)
    out = os.path.join(work, "odd")
    run = subprocess.run([python.encode(), script.encode(), odd, out.encode()], capture_output=True)
    assert run.returncode == 0, f"plot_torques on an odd file name failed ({run.returncode}): {run.stderr!r}"
    assert "Joint torques: t<U+0001>a<0xFF>u.csv" in svg_text(os.path.join(out, "torques.svg"))

    # errors: a missing file, a cell that is not a number (its line counted over blank lines), a file of
    # blank lines, an unknown --joints name
    bad = os.path.join(work, "bad.csv")
    with open(bad, "w") as f:
        f.write("t,tau_r_knee_pitch\n\n0,1\n0.01,abc\n")
    blank = os.path.join(work, "blank.csv")
    with open(blank, "w") as f:
        f.write("\n  \n")
    for args, want in (([os.path.join(work, "missing.csv")], "missing.csv: cannot read"),
                       ([bad], "bad.csv: line 4, column 2 'tau_r_knee_pitch': 'abc' is not a number"),
                       ([blank], "blank.csv: line 1: no header row: the file holds nothing but blank lines"),
                       ([torques, "--joints", "r_knee"], "no column tau_r_knee")):
        run = subprocess.run([python, script, args[0], os.path.join(work, "x")] + args[1:],
                             capture_output=True, text=True)
        assert run.returncode == 1 and want in run.stderr, f"{args}: exit {run.returncode}, {run.stderr!r}"
    print("plot_torques: valid SVG and PNG naming every joint and limb; --joints obeyed; bad input named")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(*sys.argv[1:])
