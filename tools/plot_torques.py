#!/usr/bin/env python3
"""A clip's joint torque curves, drawn with matplotlib from `humandyn id`'s output:

  torques.svg/.png    each joint's torque (N m) against time, one panel per limb (right leg, left leg,
                      waist, arms), and the ground reaction's vertical force when the file has grf_fz

usage: python3 tools/plot_torques.py TORQUES.csv OUT_DIR [--joints J,J,...] [--title TEXT]

The file has tau_<joint> columns (N m) and an optional t (s; without it, the row number). --joints draws
only those joints. A file that cannot be read, a cell that is not a number, or a joint with no column is
an error naming the file (exit code 1), never an empty chart.
"""

import argparse
import csv
import math
import os
import sys

from chart_files import plt, save, shown

# the panels, by the joint's name: the seed body's limbs; any other joint in "other"
LIMBS = [("right leg", lambda j: j.startswith("r_") and any(k in j for k in ("ankle", "knee", "hip"))),
         ("left leg", lambda j: j.startswith("l_") and any(k in j for k in ("ankle", "knee", "hip"))),
         ("waist", lambda j: j.startswith("waist")),
         ("arms", lambda j: any(k in j for k in ("shoulder", "elbow", "wrist")))]


def read_torques(path):
    """(time or None, {joint: values}, grf_fz or None); SystemExit naming the file, line and column."""
    shown_path = shown(path)
    try:
        with open(path, newline="", encoding="utf-8-sig") as f:
            # each record with the line it starts on; a line of blanks is no row (as humandyn reads CSV)
            records, start = [], 1
            reader = csv.reader(f)
            for record in reader:
                records.append((start, record))
                start = reader.line_num + 1
    except OSError as e:
        sys.exit(f"{shown_path}: cannot read: {e.strerror}")
    except UnicodeDecodeError as e:
        sys.exit(f"{shown_path}: not UTF-8 (byte 0x{e.object[e.start]:02X} at offset {e.start})")
    rows = [(line, r) for line, r in records if any(cell.strip() for cell in r)]
    if not rows:
        sys.exit(f"{shown_path}: line 1: " + ("no header row: the file holds nothing but blank lines (expected a "
                                              "header row of column names)" if records else
                                              "empty file: expected a header row of column names"))
    header = [h.strip() for h in rows[0][1]]
    columns = {name: [] for name in header}
    path = shown_path
    for line, row in rows[1:]:
        if len(row) != len(header):
            sys.exit(f"{path}: line {line}: {len(row)} cells, the header has {len(header)}")
        for column, (name, cell) in enumerate(zip(header, row), start=1):
            try:
                value = float(cell)
            except ValueError:
                sys.exit(f"{path}: line {line}, column {column} '{shown(name)}': '{shown(cell.strip())}' is not a "
                         "number")
            if not math.isfinite(value):
                sys.exit(f"{path}: line {line}, column {column} '{shown(name)}': not a finite number")
            columns[name].append(value)
    torques = {name[4:]: values for name, values in columns.items() if name.startswith("tau_")}
    if not torques:
        sys.exit(f"{path}: no tau_<joint> column")
    return columns.get("t"), torques, columns.get("grf_fz")


def main():
    parser = argparse.ArgumentParser(description="A clip's joint torque curves (humandyn id's output).")
    parser.add_argument("torques")
    parser.add_argument("out_dir")
    parser.add_argument("--joints", help="only these joints, comma-separated")
    parser.add_argument("--title", help="the chart's title (default: the file's name)")
    a = parser.parse_args()

    t, torques, grf_fz = read_torques(a.torques)
    if a.joints:
        wanted = [j for j in a.joints.split(",") if j]
        for j in wanted:
            if j not in torques:
                sys.exit(f"{a.torques}: no column tau_{j} (--joints)")
        torques = {j: torques[j] for j in wanted}
    n = len(next(iter(torques.values())))
    x = t if t is not None else list(range(n))

    panels = []
    for name, belongs in LIMBS:
        joints = [j for j in torques if belongs(j)]
        if joints:
            panels.append((name, joints))
    other = [j for j in torques if not any(j in joints for _, joints in panels)]
    if other:
        panels.append(("other", other))
    if grf_fz is not None:
        panels.append(("ground reaction", None))

    fig, axes = plt.subplots(len(panels), 1, figsize=(8, 2.2 * len(panels) + 0.6), sharex=True, squeeze=False)
    for ax, (name, joints) in zip(axes[:, 0], panels):
        if joints is None:
            ax.plot(x, grf_fz, color="tab:green", label="grf_fz")
            ax.set_ylabel("vertical force (N)")
        else:
            for j in joints:
                ax.plot(x, torques[j], label=j)
            ax.set_ylabel("torque (N m)")
            ax.axhline(0, color="0.6", linewidth=0.6)
        ax.set_title(name, loc="left")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1), fontsize=8, frameon=False)
    axes[-1, 0].set_xlabel("time (s)" if t is not None else "row")
    fig.suptitle(shown(a.title or f"Joint torques: {os.path.basename(a.torques)}"))
    fig.tight_layout()
    os.makedirs(a.out_dir, exist_ok=True)
    save(fig, a.out_dir, "torques", dpi=120)
    print(f"wrote {os.path.join(a.out_dir, 'torques.svg')} and .png ({len(torques)} joints, {n} rows)")


if __name__ == "__main__":
    main()
