#!/usr/bin/env python3
"""`humandyn view`'s page in a real browser (headless Chromium, Debian's `chromium`).

A motion is simulated (`humandyn simulate --track`, the left arm raised while the body stands), its torques
computed (`humandyn id`), a ground reaction column set added by hand (every tenth row's centre of pressure
empty, as `id` writes the rows where the foot pulls), and the page written (`humandyn view`). Then Chromium
  - takes a screenshot: the figure is drawn (pixels of the limbs' colours in the views, not a blank page);
  - dumps the DOM after some virtual time: the frame counter has advanced past the first frame;
  - logs the console to stderr: no uncaught exception and no console message at all, in either run.
The console check is itself checked on a page that throws, so that it cannot pass by seeing nothing.
Then a real walk (CMU 07_08 in SHARED_DATA/mocap, skipped, saying so, when absent) goes through
`motion import --cmu`, `id --ground-reaction --model` the scaled body and `view`: its page draws the figure,
its counter advances and shows the row's phase, and nothing is logged to the console.
Exit 77 (skipped) when chromium is not installed.

usage: view_browser.py HUMANDYN WORK_DIR [SHARED_DATA]
"""
import json
import math
import os
import re
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import zlib


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def run(*args, **kw):
    p = subprocess.run([str(a) for a in args], capture_output=True, text=True, **kw)
    if p.returncode != 0:
        fail(f"{' '.join(map(str, args))}: exit {p.returncode}\n{p.stdout}\n{p.stderr}")
    return p


def png_pixels(path):
    """The RGB(A) pixels of an 8-bit, non-interlaced PNG: (width, height, channels, rows of bytes)."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        fail(f"{path} is not a PNG")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace != 0:
        fail(f"{path}: PNG of depth {depth}, colour type {colour}, interlace {interlace}: not decoded here")
    channels = 3 if colour == 2 else 4
    raw, stride = zlib.decompress(idat), width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - channels] if x >= channels else 0
            b = previous[x]
            c = previous[x - channels] if x >= channels else 0
            if kind == 1:
                line[x] = (line[x] + a) & 255
            elif kind == 2:
                line[x] = (line[x] + b) & 255
            elif kind == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        previous = line
    return width, height, channels, rows


def count_colour(path, rgb, tolerance=40):
    """How many pixels lie within `tolerance` (per channel) of the colour rgb."""
    width, height, channels, rows = png_pixels(path)
    count = 0
    for line in rows:
        for x in range(0, width * channels, channels):
            if all(abs(line[x + k] - rgb[k]) <= tolerance for k in range(3)):
                count += 1
    return count


def console_errors(stderr):
    """Chromium's log lines of the page's console. Chromium logs every console message at one level
    ("INFO:CONSOLE:<line>] "<message>", source: ..."), console.error and uncaught exceptions alike, and the
    page writes nothing to the console: so any such line is an error."""
    return [line for line in stderr.splitlines() if ":CONSOLE" in line or "Uncaught" in line]


def chromium(browser, page, *options):
    """One headless Chromium run on `page`, in a profile of its own and a process group of its own. Headless
    Chromium now and then does not exit after its work on a busy machine (the page done, the process left
    waiting): such a run is killed after 30 s (a run takes a few seconds; the hang, once it happens, lasts) with
    every process it started (they would keep the profile locked) and made again in a fresh profile, up to
    three times in all, each retry said."""
    url = "file://" + os.path.abspath(page)
    timeout = 30
    for attempt in range(3):
        with tempfile.TemporaryDirectory(prefix="humandyn-chromium-") as profile:
            command = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                       "--disable-extensions", "--disable-background-networking", "--disable-component-update",
                       "--no-default-browser-check", f"--user-data-dir={profile}", "--enable-logging=stderr",
                       "--v=0", *options, url]
            p = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                 start_new_session=True)
            try:
                out, err = p.communicate(timeout=timeout)
                return subprocess.CompletedProcess(command, p.returncode, out, err)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                p.communicate()
                print(f"chromium did not exit within {timeout} s on {page} (attempt {attempt + 1} of 3): killed")
    fail(f"chromium did not exit within {timeout} s on {page}, three times")


def screenshot_errors(browser, page, shot, what):
    """A screenshot of `page` into `shot` that must show the figure (the left limbs' blue and the right limbs'
    red in the views); the console errors of the run."""
    p = chromium(browser, page, f"--screenshot={shot}", "--window-size=1000,1000", "--virtual-time-budget=1000",
                 "--hide-scrollbars")
    if not os.path.exists(shot):
        fail(f"no screenshot of {what}: exit {p.returncode}\n{p.stderr[-3000:]}")
    blue, red = count_colour(shot, (42, 111, 219)), count_colour(shot, (217, 83, 79))
    print(f"{what}: screenshot {shot}: {blue} pixels of the left limbs' colour, {red} of the right limbs'")
    if blue < 300 or red < 300:
        fail(f"the screenshot of {what} shows no figure ({blue} left-limb pixels, {red} right-limb pixels)")
    return console_errors(p.stderr)


def main():
    exe, work = sys.argv[1], sys.argv[2]
    browser = shutil.which("chromium")
    if browser is None:
        print("chromium not found: the browser test of `humandyn view` is skipped (apt-get install chromium, as "
              "`bash tools/run.sh test` does)")
        sys.exit(77)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    path = lambda name: os.path.join(work, name)

    # a reference: the left arm raised forward over 0.6 s, the rest standing; tracked by the servo
    joints = [j["name"] for j in json.loads(run(exe, "model", "--json").stdout)["joints"]]
    with open(path("reference.csv"), "w") as f:
        f.write("t," + ",".join("q_" + j for j in joints) + "\n")
        for k in range(61):
            t = k * 0.01
            s = min(1.0, t / 0.6)
            lift = -1.5 * (10 * s**3 - 15 * s**4 + 6 * s**5)
            f.write(f"{t}," + ",".join(str(lift if j == "l_shoulder_pitch" else 0.0) for j in joints) + "\n")
    run(exe, "simulate", "--integrator", "implicit", "--dt", "1/200", "--duration", "1.5", "--track",
        path("reference.csv"), "--kp", "2000", "--out", path("trajectory.csv"))

    # the trajectory's angles for `id` (gravity torques need q only), and a ground reaction beside them
    lines = open(path("trajectory.csv")).read().splitlines()
    header = lines[0].split(",")
    keep = [i for i, name in enumerate(header) if name == "t" or name.startswith("q_")]
    with open(path("states.csv"), "w") as f:
        for line in lines:
            cells = line.split(",")
            f.write(",".join(cells[i] for i in keep) + "\n")
    run(exe, "id", "--terms", "gravity", "--in", path("states.csv"), "--out", path("torques.csv"))
    tau = open(path("torques.csv")).read().splitlines()
    with open(path("torques_grf.csv"), "w") as f:
        f.write(tau[0] + ",grf_fx,grf_fy,grf_fz,cop_x,cop_y\n")
        for k, line in enumerate(tau[1:]):
            cop = ",," if k % 10 == 5 else ",0.03,-0.09"  # the foot pulls: no centre of pressure, no arrow
            f.write(line + f",{20 * math.sin(k / 10)},0,{730 + 20 * math.cos(k / 10)}{cop}\n")

    run(exe, "view", path("trajectory.csv"), "--torques", path("torques_grf.csv"), "--plot",
        "l_shoulder_pitch,l_elbow_pitch", "--out", path("clip.html"))
    frames = len(lines) - 1

    # 1. the screenshot shows the figure
    errors = screenshot_errors(browser, path("clip.html"), path("clip.png"), "the clip")

    # 2. the frame counter advances: after 1 s of virtual time (shorter than the clip) the page shows a later frame
    p = chromium(browser, path("clip.html"), "--dump-dom", "--virtual-time-budget=1000")
    match = re.search(r'data-frame="(\d+)"', p.stdout)
    counter = re.search(r'id="frame">frame (\d+) / (\d+)', p.stdout)
    if not match or not counter:
        fail(f"no frame counter in the dumped DOM (exit {p.returncode}):\n{p.stdout[:2000]}\n{p.stderr[-3000:]}")
    shown, total = int(counter.group(1)), int(counter.group(2))
    print(f"after 1 s of virtual time: frame {shown} of {total}")
    if total != frames:
        fail(f"the page has {total} frames, the trajectory {frames}")
    if shown <= 1:
        fail("the frame counter did not advance")
    errors += console_errors(p.stderr)

    # 3. no console error in either run; and the check sees one where there is one
    if errors:
        fail("console errors:\n" + "\n".join(errors))
    with open(path("throws.html"), "w") as f:
        f.write("<!DOCTYPE html><html><body><script>console.error('checked'); null.x;</script></body></html>")
    p = chromium(browser, path("throws.html"), "--dump-dom")
    if not console_errors(p.stderr):
        fail("the console check sees nothing on a page that throws:\n" + p.stderr[-3000:])
    print("no console error; a page that throws is caught by the same check")

    # 4. a real walk through motion import, id --ground-reaction and view, the files as they are
    shared = sys.argv[3] if len(sys.argv) > 3 else os.environ.get("HUMANDYN_SHARED_DATA", "")
    clip = os.path.join(shared, "mocap", "07_08.bvh")
    if not shared or not os.path.exists(clip):
        print(f"{clip or 'mocap/07_08.bvh'} is absent (HUMANDYN_SHARED_DATA): the real walk is not tested")
    else:
        run(exe, "motion", "import", clip, "--cmu", "--out", path("walk.csv"), "--model-out", path("walk.json"))
        run(exe, "id", "--ground-reaction", "--model", path("walk.json"), "--in", path("walk.csv"), "--out",
            path("walk_tau.csv"))
        run(exe, "view", path("walk.csv"), "--torques", path("walk_tau.csv"), "--model", path("walk.json"), "--out",
            path("walk.html"))
        errors = screenshot_errors(browser, path("walk.html"), path("walk.png"), "the walk")
        p = chromium(browser, path("walk.html"), "--dump-dom", "--virtual-time-budget=1000")
        counter = re.search(r'id="frame">frame (\d+) / (\d+)[^<]*, phase (right|left|double|flight)<', p.stdout)
        if not counter:
            fail(f"no frame counter with a phase in the walk's DOM (exit {p.returncode}):\n{p.stdout[:2000]}\n"
                 f"{p.stderr[-3000:]}")
        rows = len(open(path("walk.csv")).read().splitlines()) - 1
        shown, total = int(counter.group(1)), int(counter.group(2))
        print(f"walk: after 1 s of virtual time: frame {shown} of {total}, phase {counter.group(3)}")
        if total != rows or shown <= 1:
            fail(f"the walk's page shows frame {shown} of {total} ({rows} rows): it must advance over every row")
        errors += console_errors(p.stderr)
        if errors:
            fail("console errors on the walk's page:\n" + "\n".join(errors))
    print("PASS")


if __name__ == "__main__":
    main()
