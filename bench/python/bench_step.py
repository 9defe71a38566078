"""Stepping a paper scene from Python against the same steps from C++.

For each scene, alternately (A B A B ...): the command line's `ffdaabb run` steps the scene for
--frames frames after --warmup (C++: its wall time per frame), and this process steps the same
scene through the module (Python: World.step() called once per frame, timed around each call).
Both build the scene the same way and end on the same state hash, which is checked. Reported per
scene: the mean and median over the pairs of each side's mean wall time per frame, the ratio
Python / C++ of each pair (median, mean), and, within the Python runs, the time spent outside
the library: the wall time around step() against the step's own timing (profile total).

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python/bench_step.py \\
        --cli build/release/bin/ffdaabb --out bench/results/<machine>/python/step.json
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

import ffdaabb


def cpp_run(cli: str, scene: str, frames: int, warmup: int) -> tuple[float, str]:
    with tempfile.TemporaryDirectory() as folder:
        stats = os.path.join(folder, "stats.json")
        subprocess.run([cli, "run", "--scene", scene, "--frames", str(frames), "--warmup",
                        str(warmup), "--measure-every", "0", "--quiet", "--stats", stats],
                       check=True)
        with open(stats) as f:
            s = json.load(f)
    # wall_seconds covers warm-up and timed frames alike (the build is not in it).
    return 1000.0 * s["wall_seconds"] / (frames + warmup), s["state_hash"]


def python_run(scene: str, frames: int, warmup: int) -> tuple[float, float, str]:
    world = ffdaabb.World.from_scene(scene)
    inside = 0.0
    start = time.perf_counter()
    for _ in range(frames + warmup):
        world.step()
        inside += world.profile["stage_ms"]["total"]
    wall = time.perf_counter() - start
    return 1000.0 * wall / (frames + warmup), inside / (frames + warmup), f"{world.state_hash:016x}"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cli", required=True, help="the ffdaabb command-line tool")
    parser.add_argument("--scenes", nargs="+", default=["spheres", "teapots", "alphabets", "buddhas"])
    parser.add_argument("--frames", type=int, default=240)
    parser.add_argument("--warmup", type=int, default=60)
    parser.add_argument("--pairs", type=int, default=3)
    parser.add_argument("--out", help="write the results as JSON here")
    args = parser.parse_args()

    results = []
    print(f"{'scene':<10} {'C++ ms/frame':>14} {'Python ms/frame':>16} {'ratio median':>13} "
          f"{'ratio mean':>11} {'outside step':>13}")
    for scene in args.scenes:
        cpp, py, ratios, outside = [], [], [], []
        for _ in range(args.pairs):
            c, c_hash = cpp_run(args.cli, scene, args.frames, args.warmup)
            p, p_inside, p_hash = python_run(scene, args.frames, args.warmup)
            if c_hash != p_hash:
                print(f"{scene}: state hashes differ: C++ {c_hash}, Python {p_hash}",
                      file=sys.stderr)
                return 1
            cpp.append(c)
            py.append(p)
            ratios.append(p / c)
            outside.append(p - p_inside)
        row = {
            "scene": scene, "frames": args.frames, "warmup": args.warmup, "pairs": args.pairs,
            "state_hash": c_hash,
            "cpp_ms_per_frame": {"mean": statistics.mean(cpp), "median": statistics.median(cpp),
                                 "runs": cpp},
            "python_ms_per_frame": {"mean": statistics.mean(py), "median": statistics.median(py),
                                    "runs": py},
            "ratio_python_over_cpp": {"median": statistics.median(ratios),
                                      "mean": statistics.mean(ratios), "runs": ratios},
            "python_ms_outside_step_per_frame": statistics.mean(outside),
        }
        results.append(row)
        print(f"{scene:<10} {statistics.median(cpp):>14.3f} {statistics.median(py):>16.3f} "
              f"{statistics.median(ratios):>13.4f} {statistics.mean(ratios):>11.4f} "
              f"{statistics.mean(outside) * 1000:>10.1f} us")
    if args.out:
        os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
        partial = args.out + ".part"
        with open(partial, "w") as f:
            json.dump({"python": sys.version.split()[0], "numpy": __import__("numpy").__version__,
                       "module": ffdaabb.__version__, "scenes": results}, f, indent=2)
            f.write("\n")
        os.replace(partial, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
