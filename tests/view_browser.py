#!/usr/bin/env python3
"""`humandyn view`'s page in a real browser: headless Chromium driven over WebDriver (Debian's `chromium`,
`chromium-driver` and `python3-selenium`; the screenshot read with Pillow, `python3-pil`).

A motion is simulated (`humandyn simulate --track`, the left arm raised while the body stands), its torques
computed (`humandyn id`), a ground reaction column set added by hand (every tenth row's centre of pressure
empty, as `id` writes the rows where the foot pulls), and the page written (`humandyn view`). Then the browser
  - takes a screenshot of the first frame: the figure is drawn (pixels of the limbs' colours in the views, not
    a blank page);
  - plays the clip: the frame counter advances past the first frame;
  - pauses the clip and steps it one frame with the arrow key: the counter follows;
  - reads the page's console log: no uncaught exception and no console message at all.
The console check is itself checked on a page that throws, so that it cannot pass by seeing nothing.
Then a real walk (CMU 07_08 in SHARED_DATA/mocap, skipped, saying so, when absent) goes through
`motion import --cmu`, `id --ground-reaction --model` the scaled body and `view`: its page draws the figure,
its counter advances and shows the row's phase, and nothing is logged to the console.
Every wait is for a condition on the page, with a deadline, never for a fixed time; the browser is ended
with every process it started, whatever happens.
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
    from selenium.common.exceptions import TimeoutException
    from selenium.webdriver.chrome.service import Service
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.support.ui import WebDriverWait
except ImportError as missing:
    print(f"{missing}: the browser test of `humandyn view` is skipped (apt-get install python3-selenium "
          "python3-pil, as `bash tools/run.sh test` does)")
    sys.exit(77)

DEADLINE = 120  # seconds any one wait on the page may take (a wait ends as soon as its condition holds)


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def run(*args, **kw):
    p = subprocess.run([str(a) for a in args], capture_output=True, text=True, **kw)
    if p.returncode != 0:
        fail(f"{' '.join(map(str, args))}: exit {p.returncode}\n{p.stdout}\n{p.stderr}")
    return p


def count_colour(png, rgb, tolerance=40):
    """How many pixels of the PNG file lie within `tolerance` (per channel) of the colour rgb."""
    with Image.open(png) as image:
        pixels = image.convert("RGB").getdata()
    return sum(1 for p in pixels if all(abs(p[k] - rgb[k]) <= tolerance for k in range(3)))


@contextlib.contextmanager
def browser(chromium, chromedriver):
    """Headless Chromium under its WebDriver, in a profile of its own, with the console log recorded. On the way
    out every process whose command line names the profile is killed, so that a browser that does not end
    when asked cannot hold the profile or outlive the test."""
    with tempfile.TemporaryDirectory(prefix="humandyn-chromium-") as profile:
        options = webdriver.ChromeOptions()
        options.binary_location = chromium
        for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-extensions",
                     "--disable-background-networking", "--disable-component-update", "--no-default-browser-check",
                     "--window-size=1000,1000", "--hide-scrollbars", f"--user-data-dir={profile}"):
            options.add_argument(flag)
        options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
        driver = webdriver.Chrome(service=Service(executable_path=chromedriver), options=options)
        try:
            driver.set_page_load_timeout(DEADLINE)
            yield driver
        finally:
            try:
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


def open_page(driver, page):
    """Opens the page once it shows a frame; pauses it and scrubs back to the first frame (as a user would with
    the slider), so that the screenshot that follows sees the same frame on every run."""
    driver.get("file://" + os.path.abspath(page))
    wait_for(driver, lambda d: shown_frame(d)[0] >= 1, f"the first frame of {page}")
    driver.find_element(By.ID, "play").click()
    driver.execute_script("const s = document.getElementById('scrub'); s.value = '0';"
                          "s.dispatchEvent(new Event('input'));")
    if shown_frame(driver)[0] != 1:
        fail(f"scrubbed to the start, {page} shows {shown_frame(driver)[1]!r}")


def screenshot(driver, shot, what):
    """A screenshot of the open page into `shot` that must show the figure (the left limbs' blue and the right
    limbs' red in the views)."""
    if not driver.save_screenshot(shot):
        fail(f"no screenshot of {what}")
    blue, red = count_colour(shot, (42, 111, 219)), count_colour(shot, (217, 83, 79))
    print(f"{what}: screenshot {shot}: {blue} pixels of the left limbs' colour, {red} of the right limbs'")
    if blue < 300 or red < 300:
        fail(f"the screenshot of {what} shows no figure ({blue} left-limb pixels, {red} right-limb pixels)")


def advancing_counter(driver, what):
    """Plays the paused clip from its first frame and waits until it shows a later one; returns (frame, counter
    text)."""
    driver.find_element(By.ID, "play").click()
    wait_for(driver, lambda d: shown_frame(d)[0] > 1, f"the frame counter of {what} advancing")
    return shown_frame(driver)


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
        # 1. the screenshot shows the figure
        open_page(driver, path("clip.html"))
        screenshot(driver, path("clip.png"), "the clip")

        # 2. played, the frame counter advances, over the trajectory's frames
        shown, text = advancing_counter(driver, "the clip")
        counter = re.match(r"frame (\d+) / (\d+)", text)
        if not counter or int(counter.group(1)) != shown:
            fail(f"the counter reads {text!r}, the page shows frame {shown}")
        print(f"the clip plays: {text}")
        if int(counter.group(2)) != frames:
            fail(f"the page has {counter.group(2)} frames, the trajectory {frames}")

        # 3. paused, the arrow keys step one frame each way
        driver.find_element(By.ID, "play").click()
        paused, _ = shown_frame(driver)
        body = driver.find_element(By.TAG_NAME, "body")
        step = Keys.ARROW_LEFT if paused == frames else Keys.ARROW_RIGHT
        expected = paused - 1 if paused == frames else paused + 1
        body.send_keys(step)
        stepped, text = shown_frame(driver)
        if stepped != expected or not text.startswith(f"frame {expected} / "):
            fail(f"paused at frame {paused}, one arrow key shows frame {stepped} ({text!r}), not {expected}")
        body.send_keys(Keys.ARROW_RIGHT if step == Keys.ARROW_LEFT else Keys.ARROW_LEFT)
        if shown_frame(driver)[0] != paused:
            fail(f"the opposite arrow key does not go back to frame {paused}: {shown_frame(driver)[1]!r}")
        print(f"paused at frame {paused}; the arrow keys show frame {expected} and back")

        # 4. no console error; and the check sees one where there is one
        errors = console(driver)
        if errors:
            fail("console errors:\n" + "\n".join(errors))
        with open(path("throws.html"), "w") as f:
            f.write("<!DOCTYPE html><html><body><script>console.error('checked'); null.x;</script></body></html>")
        driver.get("file://" + path("throws.html"))
        seen = []
        wait_for(driver, lambda d: seen.extend(console(d)) or len(seen) >= 2,
                 "the console check seeing the error and the exception of a page that throws")
        print("no console error; a page that throws is caught by the same check:", *seen, sep="\n  ")

        # 5. a real walk through motion import, id --ground-reaction and view, the files as they are
        if not shared or not os.path.exists(clip):
            print(f"{clip or 'mocap/07_08.bvh'} is absent (HUMANDYN_SHARED_DATA): the real walk is not tested")
        else:
            run(exe, "motion", "import", clip, "--cmu", "--out", path("walk.csv"), "--model-out", path("walk.json"))
            run(exe, "id", "--ground-reaction", "--model", path("walk.json"), "--in", path("walk.csv"), "--out",
                path("walk_tau.csv"))
            run(exe, "view", path("walk.csv"), "--torques", path("walk_tau.csv"), "--model", path("walk.json"),
                "--out", path("walk.html"))
            open_page(driver, path("walk.html"))
            screenshot(driver, path("walk.png"), "the walk")
            shown, text = advancing_counter(driver, "the walk")
            counter = re.match(r"frame (\d+) / (\d+)[^,]*(?:, [^,]*)*, phase (right|left|double|flight)$", text)
            if not counter:
                fail(f"no frame counter with a phase on the walk's page: {text!r}")
            rows = len(open(path("walk.csv")).read().splitlines()) - 1
            total = int(counter.group(2))
            print(f"the walk plays: {text}")
            if total != rows:
                fail(f"the walk's page has {total} frames, the clip {rows} rows")
            errors = console(driver)
            if errors:
                fail("console errors on the walk's page:\n" + "\n".join(errors))
    print("PASS")


if __name__ == "__main__":
    main()
