#!/usr/bin/env python3
"""humandyn id|fd|simulate --scene: on states that hold the legs still, each locked or pruned scene writes exactly
the full model's torques for its output joints (and only those); fed the full model's torques, the
locked scenes' forward dynamics gives back the accelerations of their moving joints, with or without the
locked joints' torque columns; id and fd read only the moving joints' columns when --lock gives the
locked angles; every scene name is accepted, an unknown one and --terms with --scene are usage errors (exit 2); a simulation in the
upper-body scene keeps the legs in their starting pose while servos bend the waist and the legs' servo
references ask them to move. --lock sets the lock angles instead of the first row (id) or the starting
pose (simulate); a joint the scene does not lock, an unknown joint, a bad angle and --lock without
--scene are usage errors.

usage: cli_scene.py PATH/TO/humandyn"""
import csv
import io
import os
import random
import subprocess
import sys
import tempfile

JOINTS = ["r_ankle_pitch", "r_knee_pitch", "r_hip_roll", "r_hip_pitch", "waist_pitch", "waist_yaw",
          "l_shoulder_pitch", "l_shoulder_roll", "l_elbow_pitch", "r_shoulder_pitch", "r_shoulder_roll",
          "r_elbow_pitch", "l_hip_pitch", "l_hip_roll", "l_knee_pitch", "l_ankle_pitch"]
LEGS_AND_WAIST = {0, 1, 2, 3, 4, 5, 12, 13, 14, 15}


def run(exe, *args):
    p = subprocess.run([exe, *args], capture_output=True, text=True)
    return p.returncode, p.stdout, p.stderr


def table(text):
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], [[float(x) for x in r] for r in rows[1:]]


def main():
    exe = sys.argv[1]
    rng = random.Random(5)
    lock = [rng.uniform(-0.8, 0.8) for _ in JOINTS]
    header = ["t"] + ["q_" + j for j in JOINTS] + ["qd_" + j for j in JOINTS] + ["qdd_" + j for j in JOINTS]
    rows = []
    for k in range(20):
        q = [rng.uniform(-2, 2) for _ in JOINTS]
        qd = [rng.uniform(-3, 3) for _ in JOINTS]
        qdd = [rng.uniform(-10, 10) for _ in JOINTS]
        for i in LEGS_AND_WAIST:  # legs and waist held still at their lock angles
            q[i], qd[i], qdd[i] = lock[i], 0.0, 0.0
        rows.append([0.01 * k] + q + qd + qdd)
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        states = os.path.join(tmp, "states.csv")
        with open(states, "w") as f:
            f.write(",".join(header) + "\n")
            for r in rows:
                f.write(",".join(repr(x) for x in r) + "\n")
        rc, out, err = run(exe, "id", "--in", states)
        if rc != 0:
            sys.exit("humandyn id failed: " + err)
        full_header, full = table(out)
        expected_columns = {
            "full": 16, "upper_body": 8, "arms_only": 6, "arm_torques": 6,
        }
        for scene, n in expected_columns.items():
            rc, out, err = run(exe, "id", "--scene", scene, "--in", states)
            if rc != 0:
                failures.append(f"--scene {scene}: exit {rc}: {err}")
                continue
            h, values = table(out)
            if len(h) != n + 1:
                failures.append(f"--scene {scene}: {len(h) - 1} torque columns, expected {n}")
            for c, name in enumerate(h):
                fc = full_header.index(name)
                for r in range(len(rows)):
                    a, b = values[r][c], full[r][fc]
                    if abs(a - b) > 1e-9 * max(1.0, abs(b)):
                        failures.append(f"--scene {scene}: {name} row {r}: {a} vs the full model's {b}")
                        break
        # forward dynamics: the full model's torques for accelerations that hold legs and waist still,
        # through a scene that locks them, give those accelerations back
        with open(os.path.join(tmp, "torques.csv"), "w") as f:
            f.write(",".join(["q_" + j for j in JOINTS] + ["qd_" + j for j in JOINTS] + ["tau_" + j for j in JOINTS]) + "\n")
            for r, taus in zip(rows, full):
                f.write(",".join(repr(x) for x in r[1:33] + taus[1:]) + "\n")
        for scene, method in (("upper_body", "articulated"), ("arms_only", "mass-matrix")):
            rc, out, err = run(exe, "fd", "--scene", scene, "--method", method, "--in", os.path.join(tmp, "torques.csv"))
            if rc != 0:
                failures.append(f"fd --scene {scene}: exit {rc}: {err}")
                continue
            h, values = table(out)
            for c, name in enumerate(h):
                i = JOINTS.index(name[len("qdd_"):])
                for r in range(len(rows)):
                    a, b = values[r][c], rows[r][33 + i]
                    if abs(a - b) > 1e-8 * max(1.0, abs(b)):
                        failures.append(f"fd --scene {scene}: {name} row {r}: {a}, expected {b}")
                        break
            if len(h) != (8 if scene == "upper_body" else 6):
                failures.append(f"fd --scene {scene}: {len(h)} columns")
        # a locked joint's torque is not read: left out (as id --scene leaves it out), the same accelerations
        moving = [i for i in range(16) if i not in LEGS_AND_WAIST]
        with open(os.path.join(tmp, "moving.csv"), "w") as f:
            f.write(",".join(["q_" + j for j in JOINTS] + ["qd_" + j for j in JOINTS] + ["tau_" + JOINTS[i] for i in moving]) + "\n")
            for r, taus in zip(rows, full):
                f.write(",".join(repr(x) for x in r[1:33] + [taus[1 + i] for i in moving]) + "\n")
        with_all = run(exe, "fd", "--scene", "arms_only", "--in", os.path.join(tmp, "torques.csv"))
        without = run(exe, "fd", "--scene", "arms_only", "--in", os.path.join(tmp, "moving.csv"))
        if without[0] != 0 or without[1] != with_all[1]:
            failures.append(f"fd --scene arms_only without the locked joints' torques: exit {without[0]}: {without[2]}")
        # nor its rate, nor (when --lock gives it) its angle: id and fd on the moving joints' columns alone
        locked = [i for i in range(16) if i in LEGS_AND_WAIST]
        lock_all = ",".join(f"{JOINTS[i]}={lock[i]!r}" for i in locked)
        moving_states = os.path.join(tmp, "moving_states.csv")
        with open(moving_states, "w") as f:
            f.write(",".join(p + JOINTS[i] for p in ("q_", "qd_", "qdd_") for i in moving) + "\n")
            for r in rows:
                f.write(",".join(repr(r[1 + 16 * g + i]) for g in range(3) for i in moving) + "\n")
        id_all = run(exe, "id", "--scene", "arms_only", "--in", states)
        id_moving = run(exe, "id", "--scene", "arms_only", "--lock", lock_all, "--in", moving_states)
        if id_moving[0] != 0 or table(id_moving[1])[1] != [r[1:] for r in table(id_all[1])[1]]:
            failures.append(f"id --scene arms_only on the moving joints' columns: exit {id_moving[0]}: {id_moving[2]}")
        id_no_lock = run(exe, "id", "--scene", "arms_only", "--in", moving_states)
        if id_no_lock[0] == 0 or "q_r_ankle_pitch" not in id_no_lock[2]:
            failures.append("id --scene arms_only without --lock nor the locked angles: " + repr(id_no_lock))
        with open(os.path.join(tmp, "moving_torques.csv"), "w") as f:
            f.write(",".join(["q_" + JOINTS[i] for i in moving] + ["qd_" + JOINTS[i] for i in moving] +
                             ["tau_" + JOINTS[i] for i in moving]) + "\n")
            for r, taus in zip(rows, full):
                f.write(",".join(repr(x) for x in [r[1 + i] for i in moving] + [r[17 + i] for i in moving] +
                                 [taus[1 + i] for i in moving]) + "\n")
        fd_moving = run(exe, "fd", "--scene", "arms_only", "--lock", lock_all, "--in",
                        os.path.join(tmp, "moving_torques.csv"))
        if fd_moving[0] != 0 or fd_moving[1] != with_all[1]:
            failures.append(f"fd --scene arms_only on the moving joints' columns: exit {fd_moving[0]}: {fd_moving[2]}")
        # simulate: legs locked in the starting pose, the rest moving
        traj, motion = os.path.join(tmp, "trajectory.csv"), os.path.join(tmp, "motion.csv")
        with open(motion, "w") as f:
            f.write(",".join(["t"] + ["q_" + j for j in JOINTS]) + "\n")
            f.write(",".join(["0"] + ["0"] * 16) + "\n")
            f.write(",".join(["0.2"] + ["0.3"] * 16) + "\n")  # every joint, the legs included, asked to turn
        rc, _, err = run(exe, "simulate", "--scene", "upper_body", "--integrator", "rk4", "--duration", "0.2",
                         "--track", motion, "--out", traj)
        if rc != 0:
            failures.append(f"simulate --scene upper_body: exit {rc}: {err}")
        else:
            with open(traj) as f:
                h, values = table(f.read())
            legs = [h.index(p + JOINTS[i]) for i in (0, 1, 2, 3, 12, 13, 14, 15) for p in ("q_", "qd_")]
            if any(abs(r[c]) > 0 for r in values for c in legs):
                failures.append("simulate --scene upper_body: a locked leg joint moved")
            if max(abs(r[h.index("qd_waist_pitch")]) for r in values) < 1e-3:
                failures.append("simulate --scene upper_body: the upper body did not move")
        # --lock: the same states with the legs' angle columns all zero, the lock angles on the command line
        legs = (0, 1, 2, 3, 12, 13, 14, 15)
        shifted = os.path.join(tmp, "shifted.csv")
        with open(shifted, "w") as f:
            f.write(",".join(header) + "\n")
            for r in rows:
                f.write(",".join("0.0" if c - 1 in legs else repr(x) for c, x in enumerate(r)) + "\n")
        lock_option = ",".join(f"{JOINTS[i]}={lock[i]!r}" for i in legs)
        rc, out, err = run(exe, "id", "--scene", "upper_body", "--lock", lock_option, "--in", shifted)
        if rc != 0:
            failures.append(f"id --scene upper_body --lock: exit {rc}: {err}")
        else:
            h, values = table(out)
            for c, name in enumerate(h):
                fc = full_header.index(name)
                if any(abs(values[r][c] - full[r][fc]) > 1e-9 * max(1.0, abs(full[r][fc])) for r in range(len(rows))):
                    failures.append(f"id --scene upper_body --lock: {name} differs from the full model's")
        rc, _, err = run(exe, "simulate", "--scene", "upper_body", "--lock", "r_knee_pitch=0.5,l_knee_pitch=-0.25",
                         "--duration", "0.05", "--out", traj)
        if rc != 0:
            failures.append(f"simulate --scene upper_body --lock: exit {rc}: {err}")
        else:
            with open(traj) as f:
                h, values = table(f.read())
            for name, angle in (("q_r_knee_pitch", 0.5), ("q_l_knee_pitch", -0.25)):
                if any(r[h.index(name)] != angle for r in values):
                    failures.append(f"simulate --scene upper_body --lock: {name} left {angle}")
        for args in (["--lock", "r_knee_pitch=0.5"],                                     # no --scene
                     ["--scene", "upper_body", "--lock", "waist_pitch=0.1"],              # not locked there
                     ["--scene", "upper_body", "--lock", "r_kne_pitch=0.1"],              # no such joint
                     ["--scene", "upper_body", "--lock", "r_knee_pitch=abc"],             # not a number
                     ["--scene", "upper_body", "--lock", "r_knee_pitch=1,r_knee_pitch=2"]):  # twice
            rc, _, err = run(exe, "id", *args, "--in", states)
            if rc != 2:
                failures.append(f"id {' '.join(args)}: exit {rc}, expected 2 ({err.strip()})")
        for scene in ("no_coriolis", "static_pose"):
            rc, _, err = run(exe, "id", "--scene", scene, "--in", states)
            if rc != 0:
                failures.append(f"--scene {scene}: exit {rc}: {err}")
        for args in (["--scene", "legs_only"], ["--scene", "full", "--terms", "full"]):
            rc, _, err = run(exe, "id", *args, "--in", states)
            if rc != 2:
                failures.append(f"{' '.join(args)}: exit {rc}, expected 2 ({err.strip()})")
    for f in failures:
        print(f)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
