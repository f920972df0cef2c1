#!/usr/bin/env python3
"""The machine code each named scene's inverse dynamics compiles to.

Compiles bench/scene_code_size.cpp once per scene (one scene per object file, so every helper the scene
pulls in is counted once) and sums the sizes of the object's .text sections. Prints a Markdown table;
with --check, exits 1 unless every pruned scene compiles to less code than `full`.

    python3 bench/scene_code_size.py [--cxx g++] [--eigen /usr/include/eigen3] [--check]
"""
import argparse
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
SCENES = [("full", "Full"), ("no_coriolis", "NoCoriolis"), ("static_pose", "StaticPose"),
          ("upper_body", "UpperBody"), ("arms_only", "ArmsOnly"), ("arm_torques", "ArmTorques")]
FLAGS = ["-std=c++20", "-O3", "-DNDEBUG"]


def text_bytes(cxx, eigen, scene_type, out_dir):
    obj = out_dir / f"{scene_type}.o"
    subprocess.run([cxx, *FLAGS, f"-I{ROOT / 'include'}", f"-I{eigen}", f"-DHUMANDYN_SCENE={scene_type}",
                    "-c", str(ROOT / "bench" / "scene_code_size.cpp"), "-o", str(obj)], check=True)
    listing = subprocess.run(["size", "-A", str(obj)], check=True, capture_output=True, text=True).stdout
    return sum(int(line.split()[1]) for line in listing.splitlines()
               if line.startswith(".text"))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cxx", default="g++")
    parser.add_argument("--eigen", default="/usr/include/eigen3")
    parser.add_argument("--check", action="store_true", help="fail unless every pruned scene is smaller than full")
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as tmp:
        sizes = {name: text_bytes(args.cxx, args.eigen, scene_type, pathlib.Path(tmp)) for name, scene_type in SCENES}

    version = subprocess.run([args.cxx, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    print(f"{version}, {' '.join(FLAGS)}: bytes of machine code (.text) of one scene's inverse dynamics\n")
    print("| scene | bytes | of full |")
    print("|---|---:|---:|")
    for name, _ in SCENES:
        print(f"| `{name}` | {sizes[name]:,} | {100 * sizes[name] / sizes['full']:.0f} % |".replace(",", " "))

    larger = [name for name, _ in SCENES if name != "full" and sizes[name] >= sizes["full"]]
    if args.check and larger:
        print(f"\nnot smaller than full: {', '.join(larger)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
