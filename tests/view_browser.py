#!/usr/bin/env python3
"""`humandyn view`'s page in a real browser: headless Chromium driven over WebDriver (Debian's `chromium`,
`chromium-driver` and `python3-selenium`; the screenshot read with Pillow, `python3-pil`).

A motion is simulated (`humandyn simulate --track`, the left arm raised while the body stands), its torques
computed (`humandyn id`), a ground reaction column set added by hand (every tenth row's centre of pressure
empty, as `id` writes the rows where the foot pulls), and the page written (`humandyn view`). Then the browser
  - opens it playing, pauses it, scrubs to the first frame and takes a screenshot: the figure is drawn in the
    front and the side view (pixels of the left and the right limbs' colours inside each view's canvas);
  - plays it: the frame counter, always equal to the frame shown, passes the middle and starts over;
  - paused, one arrow key steps one frame and the other steps back, with the focus on the page's button or
    on its slider;
  - scrubs through every frame (each shows its number) and screenshots the last;
  - plays a clip at t near 1e15 s, and draws the time plot of one whose times and angles reach 1e308 s and
    1e307 rad;
  - reads the page's console log: no uncaught exception and no console message at all.
The console check is itself checked on a page that throws, so that it cannot pass by seeing nothing.
Then a real walk (CMU 07_08 in SHARED_DATA/mocap, skipped, saying so, when absent) goes through
`motion import --cmu`, `id --ground-reaction --model` the scaled body and `view`: its page draws the figure,
its counter plays through and shows the row's phase, every frame is drawn, and nothing is logged to the
console. Every wait is for a condition on the page, with a deadline, never for a fixed time; the browser is
ended with every process that names its profile, on a failure or SIGTERM too.
Exit 77 (skipped) when the browser, its driver or the Python packages are not installed.

usage: view_browser.py HUMANDYN WORK_DIR [SHARED_DATA]
"""
import contextlib
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile

try:
    from PIL import Image
    from selenium import webdriver
    from selenium.common.exceptions import TimeoutException, WebDriverException
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.remote.remote_connection import RemoteConnection
    from selenium.webdriver.support.ui import WebDriverWait
except ImportError as missing:
    print(f"{missing}: the browser test of `humandyn view` is skipped (apt-get install python3-selenium "
          "python3-pil, as `bash tools/run.sh test` does)")
    sys.exit(77)

DEADLINE = 60  # seconds any one wait on the page may take (a wait ends as soon as its condition holds)


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def run(*args, **kw):
    p = subprocess.run([str(a) for a in args], capture_output=True, text=True, **kw)
    if p.returncode != 0:
        fail(f"{' '.join(map(str, args))}: exit {p.returncode}\n{p.stdout}\n{p.stderr}")
    return p


def count_colour(png, box, rgb, tolerance=40):
    """How many pixels of the PNG file inside the box (left, top, right, bottom in pixels) lie within
    `tolerance` (per channel) of the colour rgb."""
    with Image.open(png) as image:
        pixels = image.convert("RGB").crop(box).getdata()
    return sum(1 for p in pixels if all(abs(p[k] - rgb[k]) <= tolerance for k in range(3)))


@contextlib.contextmanager
def browser(chromium, chromedriver):
    """Headless Chromium under its WebDriver, in a profile of its own, with the console log recorded. On the way
    out (a failure, an exception, SIGTERM from ctest's timeout) every process whose command line names the
    profile is killed, so that a browser that does not end when asked cannot hold the profile or outlive
    the test."""
    signal.signal(signal.SIGTERM, lambda *_: fail("terminated"))
    RemoteConnection.set_timeout(DEADLINE + 30)  # no WebDriver command waits longer than a deadline and a margin
    with tempfile.TemporaryDirectory(prefix="humandyn-chromium-", ignore_cleanup_errors=True) as profile:
        options = webdriver.ChromeOptions()
        options.binary_location = chromium
        for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-extensions",
                     "--disable-background-networking", "--disable-component-update", "--no-default-browser-check",
                     "--disable-breakpad", "--window-size=1000,1000", "--hide-scrollbars",
                     f"--user-data-dir={profile}"):
            options.add_argument(flag)
        options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
        driver = None
        try:
            try:
                driver = webdriver.Chrome(service=Service(executable_path=chromedriver), options=options)
            except WebDriverException as e:
                versions = [subprocess.run([tool, "--version"], capture_output=True, text=True).stdout.strip()
                            or f"{tool} without a version" for tool in (chromium, chromedriver)]
                fail(f"the browser did not start under its driver ({' and '.join(versions)}; a driver serves only "
                     f"its own browser version): {e.msg}")
            driver.set_page_load_timeout(DEADLINE)
            driver.set_script_timeout(DEADLINE)
            yield driver
        finally:
            try:
                if driver is not None:
                    driver.quit()
            finally:
                for pid in os.listdir("/proc"):
                    try:
                        with open(f"/proc/{pid}/cmdline", "rb") as f:
                            if profile.encode() in f.read():
                                os.kill(int(pid), signal.SIGKILL)
                    except (OSError, ValueError):
                        pass


def console(driver):
    """The console messages and uncaught exceptions logged since the last call. The page writes nothing to the
    console, so any entry is an error."""
    return [f"{e['level']}: {e['message']}" for e in driver.get_log("browser")]


def wait_for(driver, condition, what):
    try:
        return WebDriverWait(driver, DEADLINE, poll_frequency=0.05).until(lambda d: condition(d))
    except TimeoutException:
        fail(f"{what}: not within {DEADLINE} s")


def shown_frame(driver):
    """The frame the page shows (1-based, the body's data-frame) and the counter's text, read in one script so
    that the playing clip cannot move between the two."""
    frame, text = driver.execute_script(
        "return [document.body.dataset.frame, document.getElementById('frame').textContent]")
    return int(frame) if frame else 0, text


def play_button(driver):
    return driver.find_element(By.ID, "play").text


def scrub(driver, frame):
    """Moves the slider to `frame` (1-based) as a user's drag does (its value, then its input event)."""
    driver.execute_script("const s = document.getElementById('scrub'); s.value = String(arguments[0]);"
                          "s.dispatchEvent(new Event('input'));", frame - 1)


def open_page(driver, page):
    """Opens the page, which plays from its first frame; pauses it and scrubs back to the first frame, so that
    the screenshot that follows sees the same frame on every run."""
    driver.get("file://" + os.path.abspath(page))
    wait_for(driver, lambda d: shown_frame(d)[0] >= 1, f"the first frame of {page}")
    if play_button(driver) != "pause":
        fail(f"{page} does not play when opened: its button reads {play_button(driver)!r}")
    driver.find_element(By.ID, "play").click()
    if play_button(driver) != "play":
        fail(f"{page}: paused, its button reads {play_button(driver)!r}")
    scrub(driver, 1)
    if shown_frame(driver)[0] != 1:
        fail(f"scrubbed to the start, {page} shows {shown_frame(driver)[1]!r}")


def screenshot(driver, shot, what):
    """A screenshot of the open page into `shot` that must show the figure in both views: the left limbs'
    blue and the right limbs' red, counted inside the front and the side view's canvases only."""
    if not driver.save_screenshot(shot):
        fail(f"no screenshot of {what}")
    boxes = driver.execute_script(
        "const k = window.devicePixelRatio; return ['front', 'side'].map((id) => {"
        "  const r = document.getElementById(id).getBoundingClientRect();"
        "  return [r.left, r.top, r.right, r.bottom].map((x) => Math.round(x * k)); });")
    for name, box in zip(("front", "side"), boxes):
        blue, red = count_colour(shot, box, (42, 111, 219)), count_colour(shot, box, (217, 83, 79))
        print(f"{what}: screenshot {shot}, {name} view: {blue} pixels of the left limbs' colour, {red} of the "
              "right limbs'")
        if blue < 50 or red < 50:
            fail(f"the {name} view of {what} shows no figure ({blue} left-limb pixels, {red} right-limb pixels)")


def every_frame(driver, frames, what):
    """Scrubs the paused page through every frame in one script: each must show its own number; then no
    console entry may have been logged."""
    wrong = driver.execute_script(
        "const s = document.getElementById('scrub'), wrong = [];"
        "for (let f = 0; f < arguments[0]; ++f) {"
        "  s.value = String(f); s.dispatchEvent(new Event('input'));"
        "  if (document.body.dataset.frame !== String(f + 1)) wrong.push(f + 1); }"
        "return wrong;", frames)
    if wrong:
        fail(f"{what}: scrubbed to frames {wrong[:10]}, the page shows others")
    errors = console(driver)
    if errors:
        fail(f"console errors on {what}:\n" + "\n".join(errors))
    print(f"{what}: every one of the {frames} frames drawn, no console entry")


def plays_through(driver, frames, what):
    """Plays the paused clip from its first frame: the counter must pass the middle of the clip and then start
    over (the clip loops); returns the counter's text at the middle. Paused again on the way out."""
    driver.find_element(By.ID, "play").click()
    seen = {}

    def wrapped(d):
        shown, text = shown_frame(d)
        if not re.match(rf"frame {shown} / {frames}\b", text):
            fail(f"{what}: the counter reads {text!r}, the page shows frame {shown} of {frames}")
        if shown > frames // 2:
            seen.setdefault("middle", text)
        return "middle" in seen and shown < frames // 4

    wait_for(driver, wrapped, f"{what} playing past its middle and starting over")
    driver.find_element(By.ID, "play").click()
    return seen["middle"]


def arrow_keys(driver, frames, target, what):
    """Paused, one arrow key sent to `target` (an element id) steps one frame and the other steps back."""
    paused, _ = shown_frame(driver)
    element = driver.find_element(By.ID, target)
    driver.execute_script("arguments[0].focus();", element)
    step, back = (Keys.ARROW_LEFT, Keys.ARROW_RIGHT) if paused == frames else (Keys.ARROW_RIGHT, Keys.ARROW_LEFT)
    expected = paused - 1 if paused == frames else paused + 1
    element.send_keys(step)
    stepped, text = shown_frame(driver)
    if stepped != expected or not text.startswith(f"frame {expected} / "):
        fail(f"{what}, paused at frame {paused}: one arrow key on #{target} shows frame {stepped} ({text!r}), "
             f"not {expected}")
    element.send_keys(back)
    if shown_frame(driver)[0] != paused:
        fail(f"{what}: the opposite arrow key on #{target} does not go back to frame {paused}: "
             f"{shown_frame(driver)[1]!r}")
    print(f"{what}: paused at frame {paused}, an arrow key on #{target} shows frame {expected} and back")


def main():
    exe, work = sys.argv[1], sys.argv[2]
    chromium, chromedriver = shutil.which("chromium"), shutil.which("chromedriver")
    if chromium is None or chromedriver is None:
        print("chromium or chromedriver not found: the browser test of `humandyn view` is skipped (apt-get install "
              "chromium chromium-driver, as `bash tools/run.sh test` does)")
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

    shared = sys.argv[3] if len(sys.argv) > 3 else os.environ.get("HUMANDYN_SHARED_DATA", "")
    clip = os.path.join(shared, "mocap", "07_08.bvh")

    with browser(chromium, chromedriver) as driver:
        # 1. the screenshot of the first frame shows the figure in both views
        open_page(driver, path("clip.html"))
        screenshot(driver, path("clip.png"), "the clip")
        legend = driver.find_element(By.ID, "legend").text
        if "ground reaction at the centre of pressure (the clip's largest vertical one 1 m long)" not in legend:
            fail(f"the legend does not give the ground reaction's scale as drawn: {legend!r}")

        # 2. played, the counter passes the middle of the trajectory's frames and starts over
        text = plays_through(driver, frames, "the clip")
        print(f"the clip plays: {text}, then starts over")

        # 3. paused, the arrow keys step one frame each way, whether the page or the slider has the focus
        arrow_keys(driver, frames, "play", "the clip")
        arrow_keys(driver, frames, "scrub", "the clip")

        # 4. every frame drawn without a console entry, the last one's screenshot too; and the console check
        # sees an error and an exception where there are some
        every_frame(driver, frames, "the clip")
        screenshot(driver, path("clip_last.png"), "the clip's last frame")
        with open(path("throws.html"), "w") as f:
            f.write("<!DOCTYPE html><html><body><script>console.error('checked'); null.x;</script></body></html>")
        driver.get("file://" + path("throws.html"))
        seen = []
        wait_for(driver, lambda d: seen.extend(console(d)) or len(seen) >= 2,
                 "the console check seeing the error and the exception of a page that throws")
        if not any("checked" in e for e in seen) or not any("Uncaught TypeError" in e for e in seen):
            fail("the console check did not see the page's error and exception:\n" + "\n".join(seen))
        print("a page that throws is caught by the same check:", *seen, sep="\n  ")

        # 5. times and angles at the far end of a double's range: a clip at t near 1e15 s (doubles 0.125 s
        # apart there, more than a screen refresh's step) still plays, and a plot spanning t = -1e308 to
        # 1e308 s and angles of +-1e307 rad (whose differences, and whose degrees, overflow) is drawn
        still = ",".join("0" for _ in joints[1:])
        with open(path("late.csv"), "w") as f:
            f.write("t," + ",".join("q_" + j for j in joints) + "\n")
            f.writelines(f"{1e15 + 0.5 * k!r},{0.1 * k},{still}\n" for k in range(10))
        run(exe, "view", path("late.csv"), "--out", path("late.html"))
        open_page(driver, path("late.html"))
        print(f"a clip at t = 1e15 s plays: {plays_through(driver, 10, 'the clip at t = 1e15 s')}, then starts over")
        with open(path("far.csv"), "w") as f:
            f.write("t," + ",".join("q_" + j for j in joints) + "\n")
            f.writelines(f"{t!r},{q!r},{still}\n" for t, q in ((-1e308, -1e307), (0.0, 0.0), (1e308, 1e307)))
        run(exe, "view", path("far.csv"), "--plot", joints[0], "--out", path("far.html"))
        open_page(driver, path("far.html"))
        curve = driver.execute_script(
            "const c = document.getElementById('plot'), d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;"
            "let n = 0; for (let i = 0; i < d.length; i += 4) if (d[i] == 31 && d[i + 1] == 119 && d[i + 2] == 180) ++n;"
            "return n;")
        if curve < 100:
            fail(f"the time plot of t = -1e308 to 1e308 s, +-1e307 rad draws {curve} pixels of its curve")
        print(f"the time plot of t = -1e308 to 1e308 s and +-1e307 rad is drawn ({curve} pixels of its curve)")

        # 6. a real walk through motion import, id --ground-reaction and view, the files as they are
        if not shared or not os.path.exists(clip):
            print(f"{clip or 'mocap/07_08.bvh'} is absent (HUMANDYN_SHARED_DATA): the real walk is not tested")
        else:
            run(exe, "motion", "import", clip, "--cmu", "--out", path("walk.csv"), "--model-out", path("walk.json"))
            run(exe, "id", "--ground-reaction", "--model", path("walk.json"), "--in", path("walk.csv"), "--out",
                path("walk_tau.csv"))
            run(exe, "view", path("walk.csv"), "--torques", path("walk_tau.csv"), "--model", path("walk.json"),
                "--out", path("walk.html"))
            rows = len(open(path("walk.csv")).read().splitlines()) - 1
            open_page(driver, path("walk.html"))
            screenshot(driver, path("walk.png"), "the walk")
            text = plays_through(driver, rows, "the walk")
            if not re.match(r"frame \d+ / \d+, t = [^,]* s(, on the left foot)?, phase (right|left|double|flight)$",
                            text):
                fail(f"no frame counter with the row's phase on the walk's page: {text!r}")
            print(f"the walk plays: {text}, then starts over")
            every_frame(driver, rows, "the walk")
    print("PASS")


if __name__ == "__main__":
    main()
