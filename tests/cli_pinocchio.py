"""`humandyn model --json [--floating]` is enough to rebuild the body in another library: the model is built
in Pinocchio (Python, PyPI `pin`) from the JSON alone, and the joint torques and base wrench that
`humandyn id --floating` writes for a few hundred random states of base and joints equal pinocchio.rnea's
with a free-flyer base; the stance-rooted form's torques equal those of the same model with a fixed base.

usage: cli_pinocchio.py HUMANDYN_BINARY SCRATCH_DIR
Exit 77 (skipped) when Pinocchio cannot be imported."""
import csv
import json
import math
import os
import subprocess
import sys

try:
    import numpy as np
    import pinocchio as pin
except ImportError as e:
    print(f"Pinocchio (PyPI `pin`) not importable by {sys.executable}: {e}; the comparison is skipped "
          "(bash tools/run.sh test installs it in build/venv)")
    sys.exit(77)

TOLERANCE = 1e-9  # N m and N, relative to the largest entry of the row (at least 1)
STATES = 300


def humandyn(binary, *args):
    run = subprocess.run([binary, *args], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(f"humandyn {' '.join(args)} failed ({run.returncode}): {run.stderr}")
    return run.stdout


def pinocchio_model(doc):
    """The model of a `humandyn model --json` document, as its conventions state: joint i a revolute
    about z placed at its parent link frame * mount * Rz(theta), its link's body at Tz(d) Tx(a) Rx(alpha)
    from the joint frame; a free flyer carrying the base link when "base": {"joint": "floating"}, else
    the base frame as Pinocchio's universe (gravity turned into it)."""
    def rot(axis, angle):
        return pin.SE3(pin.AngleAxis(angle, np.array(axis, dtype=float)).matrix(), np.zeros(3))

    def pose(p):
        return pin.SE3(np.array(p.get("R", np.eye(3)), dtype=float), np.array(p.get("p", [0, 0, 0]), dtype=float))

    def inertia(link):
        return pin.Inertia(link.get("mass", 0.0), np.array(link.get("com", [0, 0, 0]), dtype=float),
                           np.array(link.get("inertia", np.zeros((3, 3))), dtype=float))

    base = doc["base"]
    floating = base.get("joint", "fixed") == "floating"
    gravity = np.array(doc.get("gravity", [0, 0, -9.81]), dtype=float)
    m = pin.Model()
    root = 0
    if floating:
        root = m.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "base")
        m.appendBodyToJoint(root, inertia(base["link"]), pin.SE3.Identity())
        m.gravity = pin.Motion(gravity, np.zeros(3))
    else:
        m.gravity = pin.Motion(pose(base["pose"]).rotation.T @ gravity, np.zeros(3))
    link_in_joint = []
    for j in doc["joints"]:
        dh = j["dh"]
        placement = pin.SE3.Identity() if j["parent"] < 0 else link_in_joint[j["parent"]]
        if "mount" in j:
            placement = placement * pose(j["mount"])
        placement = placement * rot([0, 0, 1], dh["theta"])
        parent = root if j["parent"] < 0 else j["parent"] + 1 + (1 if floating else 0)
        jid = m.addJoint(parent, pin.JointModelRZ(), placement, j["name"])
        link = pin.SE3(pin.AngleAxis(dh["alpha"], np.array([1.0, 0, 0])).matrix(), np.array([dh["a"], 0, dh["d"]]))
        link_in_joint.append(link)
        m.appendBodyToJoint(jid, inertia(j["link"]), link)
    return m, floating


def write_csv(path, header, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        for r in rows:
            w.writerow([repr(float(x)) for x in r])


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], [[float(x) for x in r] for r in rows[1:]]


def compare(binary, scratch, floating, rng):
    flag = ["--floating"] if floating else []
    doc = json.loads(humandyn(binary, "model", "--json", *flag))
    model_path = os.path.join(scratch, "floating.json" if floating else "fixed.json")
    with open(model_path, "w") as f:
        json.dump(doc, f)
    model, is_floating = pinocchio_model(doc)
    assert is_floating == floating
    data = model.createData()
    names = [j["name"] for j in doc["joints"]]
    nj = len(names)

    header = ["t"]
    if floating:
        header += ["base_x", "base_y", "base_z", "base_qw", "base_qx", "base_qy", "base_qz", "base_wx", "base_wy",
                   "base_wz", "base_vx", "base_vy", "base_vz", "base_wdx", "base_wdy", "base_wdz", "base_ax",
                   "base_ay", "base_az"]
    header += ["q_" + n for n in names] + ["qd_" + n for n in names] + ["qdd_" + n for n in names]
    rows, expected = [], []
    for k in range(STATES):
        q, qd, qdd = rng.uniform(-math.pi, math.pi, nj), rng.uniform(-3, 3, nj), rng.uniform(-10, 10, nj)
        row = [0.001 * k]
        if floating:
            # the base: a random pose, velocity and acceleration in Pinocchio's local (base-frame) coordinates
            quat = pin.Quaternion(*rng.normal(size=4)).normalized()  # (w, x, y, z)
            R, p = quat.matrix(), rng.uniform(-1, 1, 3)
            w_b, v_b = rng.uniform(-3, 3, 3), rng.uniform(-2, 2, 3)
            wd_b, a_b = rng.uniform(-10, 10, 3), rng.uniform(-10, 10, 3)
            q_pin = np.concatenate([p, [quat.x, quat.y, quat.z, quat.w], q])
            v_pin = np.concatenate([v_b, w_b, qd])
            a_pin = np.concatenate([a_b, wd_b, qdd])
            # the same motion as humandyn's columns state it, world axes: the origin's classical
            # acceleration is R (dv_b/dt + w_b x v_b)
            row += list(p) + [quat.w, quat.x, quat.y, quat.z] + list(R @ w_b) + list(R @ v_b) + list(R @ wd_b) + \
                list(R @ (a_b + np.cross(w_b, v_b)))
            tau = pin.rnea(model, data, q_pin, v_pin, a_pin)
            # Pinocchio's base force and moment (local) in the world, humandyn's order of columns
            expected.append(np.concatenate([tau[6:], R @ tau[0:3], R @ tau[3:6]]))
        else:
            expected.append(pin.rnea(model, data, q, qd, qdd).copy())
        rows.append(row + list(q) + list(qd) + list(qdd))

    states = os.path.join(scratch, "states.csv")
    out = os.path.join(scratch, "torques.csv")
    write_csv(states, header, rows)
    humandyn(binary, "id", "--model", model_path, *flag, "--in", states, "--out", out)
    got_header, got = read_csv(out)
    want_header = ["t"] + ["tau_" + n for n in names]
    if floating:
        want_header += ["base_fx", "base_fy", "base_fz", "base_mx", "base_my", "base_mz"]
    if got_header != want_header:
        sys.exit(f"unexpected header {got_header}")
    worst_tau = worst_base = 0.0
    for g, e in zip(got, expected):
        g = np.array(g[1:])
        scale = max(1.0, float(np.max(np.abs(e))))
        worst_tau = max(worst_tau, float(np.max(np.abs(g[:nj] - e[:nj]))) / scale)
        if floating:
            worst_base = max(worst_base, float(np.max(np.abs(g[nj:] - e[nj:]))) / scale)
    form = "floating (free flyer)" if floating else "fixed"
    print(f"{form}: {len(got)} states, joint torques within {worst_tau:.2e}" +
          (f", base wrench within {worst_base:.2e}" if floating else "") + " of Pinocchio's rnea (relative)")
    return worst_tau <= TOLERANCE and worst_base <= TOLERANCE


def main():
    binary, scratch = sys.argv[1], sys.argv[2]
    os.makedirs(scratch, exist_ok=True)
    rng = np.random.default_rng(2026)
    print(f"Pinocchio {pin.__version__}")
    ok = compare(binary, scratch, True, rng) & compare(binary, scratch, False, rng)
    if not ok:
        sys.exit(f"a difference beyond {TOLERANCE:g}")


if __name__ == "__main__":
    main()
