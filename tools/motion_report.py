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


def fail(message):
    print("motion_report: " + message, file=sys.stderr)
    sys.exit(1)


def run(cli, clip, out):
    stem = os.path.splitext(os.path.basename(clip))[0]
    states, body, tau = (os.path.join(out, stem + s) for s in (".csv", ".json", ".tau.csv"))
    for command in ([cli, "motion", "import", clip, "--cmu", "--mass", str(MASS), "--out", states, "--model-out", body],
                    [cli, "id", "--model", body, "--in", states, "--out", tau, "--ground-reaction"]):
        done = subprocess.run(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if done.returncode != 0:  # (its own message says what is at fault)
            name = " ".join(command[1:3]) if command[1] == "motion" else command[1]
            fail("%s (exit code %d): %s" % (name, done.returncode, done.stderr.strip()))
    with open(tau) as f:
        return list(csv.DictReader(f))


def main():
    if len(sys.argv) != 4:
        print(__doc__.strip().splitlines()[-1].strip(), file=sys.stderr)
        sys.exit(2)
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
        # (a clip without single support, a body standing on both feet, has no share and no peaks)
        share = f"{100.0 * len(ok) / len(single):.0f} %" if single else "no single support"
        shown = {j: f"{peaks[j]:.2f}" if single else "-" for j in peaks}
        print(f"| `{name}` | {len(single)} | {len(ok)} ({share}) | {shown['ankle']} | {shown['knee']} | {shown['hip']} |")
    # the anatomical angles over each clip (degrees): the trunk's flexion and both hips' flexion
    print()
    print("| clip | trunk flexion (median, range) | right hip flexion | left hip flexion |")
    print("|---|---|---|---|")
    for name in ("07_08", "35_02", "02_03", "02_04"):
        with open(os.path.join(out, name + ".tau.csv")) as f:
            rows = list(csv.DictReader(f))
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
            if curves[name][j]:  # (none for a clip without single support)
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
