#!/usr/bin/python3
"""The CMU clips through `humandyn motion import` and `humandyn id --ground-reaction` (docs/motion.md, "Real
clips"): per clip, the share of single-support frames with a plausible ground reaction (normal > 0, centre of
pressure inside the sole) and the stance leg's peak sagittal moments (N m/kg, Winter's convention: ankle
plantarflexor, knee extensor, hip extensor positive); the trunk's and the hips' flexion over the clip
("On the CMU clips"); a chart of the walks' moments over stance.

    /usr/bin/python3 tools/motion_report.py BUILD/tools/humandyn ../shared/data/mocap OUT_FOLDER
"""
import csv
import math
import os
import subprocess
import sys

MASS = 70.0
# the right-stance model's joints of the stance leg and the sign that turns a joint torque into Winter's
# convention: minus the anatomical sign (docs/motion.md, anatomical angles, right stance)
LEG = {
    "right": {"ankle": ("r_ankle_pitch", -1), "knee": ("r_knee_pitch", +1), "hip": ("r_hip_pitch", -1)},
    "left": {"ankle": ("l_ankle_pitch", +1), "knee": ("l_knee_pitch", -1), "hip": ("l_hip_pitch", +1)},
}


def run(cli, clip, out):
    stem = os.path.splitext(os.path.basename(clip))[0]
    states, body, tau = (os.path.join(out, stem + s) for s in (".csv", ".json", ".tau.csv"))
    subprocess.run([cli, "motion", "import", clip, "--cmu", "--mass", str(MASS), "--out", states,
                    "--model-out", body], check=True)
    subprocess.run([cli, "id", "--model", body, "--in", states, "--out", tau, "--ground-reaction"], check=True,
                   stderr=subprocess.DEVNULL)
    return list(csv.DictReader(open(tau)))


def main():
    cli, data, out = sys.argv[1:4]
    os.makedirs(out, exist_ok=True)
    curves = {}
    print("| clip | single-support frames | plausible | peak ankle | peak knee | peak hip |")
    print("|---|---|---|---|---|---|")
    for name in ("07_08", "35_02", "02_03", "02_04"):
        rows = run(cli, os.path.join(data, name + ".bvh"), out)
        single = [r for r in rows if r["phase"] in ("right", "left")]
        ok = [r for r in single if r["foot_pulls"] == "0" and r["cop_outside_sole"] == "0"]
        peaks = {}
        for j in ("ankle", "knee", "hip"):
            m = [LEG[r["phase"]][j][1] * float(r["tau_" + LEG[r["phase"]][j][0]]) / MASS for r in single]
            peaks[j] = max(m) if m else float("nan")
            curves.setdefault(name, {})[j] = [(float(r["t"]), v) for r, v in zip(single, m)]
        share = 100.0 * len(ok) / len(single) if single else float("nan")
        print(f"| `{name}` | {len(single)} | {len(ok)} ({share:.0f} %) | {peaks['ankle']:.2f} | "
              f"{peaks['knee']:.2f} | {peaks['hip']:.2f} |")
    # the anatomical angles over each clip (degrees): the trunk's flexion and both hips' flexion
    print()
    print("| clip | trunk flexion (median, range) | right hip flexion | left hip flexion |")
    print("|---|---|---|---|")
    for name in ("07_08", "35_02", "02_03", "02_04"):
        rows = list(csv.DictReader(open(os.path.join(out, name + ".tau.csv"))))
        deg = {c: sorted(math.degrees(float(r[c])) for r in rows)
               for c in ("trunk_flexion", "r_hip_flexion", "l_hip_flexion")}
        t = deg["trunk_flexion"]
        print(f"| `{name}` | {t[len(t) // 2]:.1f} ({t[0]:.1f} to {t[-1]:.1f}) | "
              f"{deg['r_hip_flexion'][0]:.1f} to {deg['r_hip_flexion'][-1]:.1f} | "
              f"{deg['l_hip_flexion'][0]:.1f} to {deg['l_hip_flexion'][-1]:.1f} |")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.5), sharey=True)
    bands = {"ankle": (1.3, 1.6), "knee": (0.5, 1.0), "hip": (0.5, 1.0)}
    for ax, j in zip(axes, ("ankle", "knee", "hip")):
        for name in ("07_08", "35_02"):
            t, m = zip(*curves[name][j])
            ax.plot(t, m, ".", ms=2, label=name)
        ax.axhspan(*bands[j], color="0.85", label="published peak")
        ax.set_title(f"{j} (stance leg)")
        ax.set_xlabel("t (s), single-support frames")
    axes[0].set_ylabel("moment (N m/kg; plantarflexor / extensor +)")
    axes[0].legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, "walk_moments.png"), dpi=100)


if __name__ == "__main__":
    main()
