"""Sweep the shape-matching stiffness and measure how a soft ball lands on a soft block.

Each run builds its own World: a block (1.2 x 0.4 x 1.2 m) resting on the floor and a ball
(radius 0.35 m) dropped onto it from 1.8 m, both of the run's stiffness (shape matching's alpha:
the share of the way to the goal shape taken per step). It steps a fixed time and measures

  ball_compression     largest loss of the ball's height (1 - min height extent / rest extent)
  block_compression    the same for the block, which the ball lands on
  max_strain           largest relative change of a lattice edge or diagonal (|d / d0 - 1|)
  ball_squash_at_rest  the ball's loss of height at the end, resting on the block
  rebound_m            how far the ball's centre of mass rose, after the impact's lowest point,
                       above where it finally rests
  settling_time_s      when every body's rms particle speed fell below 0.05 m/s for good
  peak_depth_mm        the deepest interpenetration (winding number) seen in any frame
  final_depth_mm, final_depth_relative, final_inside_vertices, below_floor_mm
                       World.interpenetration() at the end
  state_hash           the world's state hash at the end: equal hashes, identical runs

The runs go to separate processes (concurrent.futures.ProcessPoolExecutor). A World steps on
one thread and is deterministic, so the numbers do not depend on how many processes share the
work: --verify runs the sweep a second time with another number of processes and checks that
every number (and hash) is the same.

Run it as

    python stiffness_sweep.py                            # 0.1, 0.2, ... 1.0, all cores
    python stiffness_sweep.py --values 0.05,0.1,0.2,0.5,1 --jobs 4 --seconds 4
    python stiffness_sweep.py --values 0.1:1:19 --verify # 19 values from 0.1 to 1
    python stiffness_sweep.py --quick --csv results/sweep.csv --plot results/sweep.png

It writes a CSV (--csv) and a plot of the measures against stiffness (--plot).
"""

from __future__ import annotations

import argparse
import concurrent.futures
import csv
import math
import multiprocessing
import os
import sys
import time
from pathlib import Path

import numpy as np

import ffdaabb

SETTLED_SPEED = 0.05  # m/s: rms particle speed below which a body counts as at rest
BALL_RADIUS = 0.35
BALL_DROP_HEIGHT = 1.8
BLOCK_HALF_EXTENTS = (0.6, 0.2, 0.6)
MAX_SECONDS = 60.0

COLUMNS = [
    "stiffness",
    "ball_compression",
    "block_compression",
    "max_strain",
    "ball_squash_at_rest",
    "rebound_m",
    "settling_time_s",
    "peak_depth_mm",
    "final_depth_mm",
    "final_depth_relative",
    "final_inside_vertices",
    "below_floor_mm",
    "frames",
    "state_hash",
]


def lattice_pairs(particles: np.ndarray, cell_size: float) -> tuple[np.ndarray, np.ndarray]:
    """Index pairs of lattice particles that are neighbours (along an edge or a diagonal of a
    cell), and their rest distances.

    The particles of an unrotated body lie on an axis-aligned grid of spacing cell_size: each
    gets integer grid coordinates, and its neighbours are found by looking those up.
    """
    grid = np.rint((particles - particles.min(axis=0)) / cell_size).astype(np.int64)
    size = grid.max(axis=0) + 2
    key = (grid[:, 0] * size[1] + grid[:, 1]) * size[2] + grid[:, 2]
    order = np.argsort(key)
    sorted_keys = key[order]
    pairs = []
    for dx, dy, dz in [(dx, dy, dz) for dx in (-1, 0, 1) for dy in (-1, 0, 1) for dz in (-1, 0, 1)
                       if (dx, dy, dz) > (0, 0, 0)]:
        other = grid + (dx, dy, dz)
        inside = np.all((other >= 0) & (other < size), axis=1)
        other_key = (other[:, 0] * size[1] + other[:, 1]) * size[2] + other[:, 2]
        at = np.minimum(np.searchsorted(sorted_keys, other_key), len(key) - 1)
        found = inside & (sorted_keys[at] == other_key)
        pairs.append(np.stack([np.nonzero(found)[0], order[at[found]]], axis=1))
    index = np.concatenate(pairs)
    rest = np.linalg.norm(particles[index[:, 0]] - particles[index[:, 1]], axis=1)
    return index, rest


def height_extent(vertices: np.ndarray) -> float:
    y = vertices[:, 1]
    return float(y.max() - y.min())


def simulate(stiffness: float, seconds: float, cells: int) -> dict:
    """One run of the sweep: builds its own World, steps it and measures it."""
    world = ffdaabb.World(threads=1)
    lattice = ffdaabb.LatticeSettings(cells=cells)
    block_vertices, block_triangles = ffdaabb.box(BLOCK_HALF_EXTENTS)
    block = world.add_body(block_vertices, block_triangles, stiffness=stiffness, lattice=lattice,
                           position=(0.0, BLOCK_HALF_EXTENTS[1], 0.0))
    sphere_vertices, sphere_triangles = ffdaabb.sphere(3)
    ball = world.add_body(sphere_vertices * BALL_RADIUS, sphere_triangles, stiffness=stiffness,
                          lattice=lattice, position=(0.05, BALL_DROP_HEIGHT, 0.0))
    bodies = [ball, block]

    # Views of the world's memory (no copy): they see every later step.
    vertices = [world.vertices(b) for b in bodies]
    particles = [world.particles(b) for b in bodies]
    velocities = [world.velocities(b) for b in bodies]
    rest_extent = [height_extent(v) for v in vertices]
    pairs = [lattice_pairs(np.array(p, dtype=np.float64), world.info(b)["cell_size"])
             for p, b in zip(particles, bodies)]

    frames = max(1, round(seconds / world.settings.frame_step))
    ball_height = np.empty(frames)
    extent_ratio = np.empty((frames, len(bodies)))
    moving = np.zeros(frames, dtype=bool)
    first_contact = -1
    max_strain = 0.0
    peak_depth = 0.0
    for frame in range(frames):
        world.step()
        ball_height[frame] = world.centre_of_mass(ball)[1]
        for k in range(len(bodies)):
            extent_ratio[frame, k] = height_extent(vertices[k]) / rest_extent[k]
            index, rest = pairs[k]
            p = particles[k]
            length = np.linalg.norm(p[index[:, 0]] - p[index[:, 1]], axis=1)
            max_strain = max(max_strain, float(np.max(np.abs(length / rest - 1.0))))
            speed = math.sqrt(float(np.mean(np.sum(np.square(velocities[k]), axis=1))))
            moving[frame] |= speed >= SETTLED_SPEED
        if first_contact < 0 and world.touching_bodies(ball):
            first_contact = frame
        peak_depth = max(peak_depth, world.interpenetration()["max_depth_m"])

    frame_step = world.settings.frame_step
    rebound = math.nan
    if first_contact >= 0:
        after = ball_height[first_contact:]
        # The impact's lowest point: where the ball's centre first stops going down.
        rising = np.nonzero(np.diff(after) > 0)[0]
        if rising.size:
            rebound = float(after[rising[0]:].max() - ball_height[-1])
    moving_frames = np.nonzero(moving)[0]
    if moving_frames.size == 0:
        settling = 0.0
    elif moving_frames[-1] < frames - 1:
        settling = round((moving_frames[-1] + 1) * frame_step, 6)
    else:
        settling = math.nan  # still moving at the end

    overlap = world.interpenetration()
    return {
        "stiffness": stiffness,
        "ball_compression": 1.0 - float(extent_ratio[:, 0].min()),
        "block_compression": 1.0 - float(extent_ratio[:, 1].min()),
        "max_strain": max_strain,
        "ball_squash_at_rest": 1.0 - float(extent_ratio[-1, 0]),
        "rebound_m": rebound,
        "settling_time_s": settling,
        "peak_depth_mm": 1000.0 * peak_depth,
        "final_depth_mm": 1000.0 * overlap["max_depth_m"],
        "final_depth_relative": overlap["max_depth_relative"],
        "final_inside_vertices": overlap["inside_vertices"],
        "below_floor_mm": 1000.0 * overlap["below_floor_m"],
        "frames": frames,
        "state_hash": f"{world.state_hash:016x}",
    }


def timed_run(stiffness: float, seconds: float, cells: int) -> tuple[dict, float]:
    start = time.perf_counter()
    row = simulate(stiffness, seconds, cells)
    return row, time.perf_counter() - start


def sweep(values: list[float], seconds: float, cells: int, jobs: int) -> tuple[list[dict], float]:
    """Runs every value in `jobs` processes; the rows in the order of `values`, and the time."""
    start = time.perf_counter()
    # "spawn": every worker starts a fresh interpreter, the same on every platform.
    context = multiprocessing.get_context("spawn")
    with concurrent.futures.ProcessPoolExecutor(max_workers=jobs, mp_context=context) as pool:
        futures = [pool.submit(timed_run, k, seconds, cells) for k in values]
        results = [f.result() for f in futures]
    elapsed = time.perf_counter() - start
    for value, (_, run_time) in zip(values, results):
        print(f"  stiffness {value:<6g} {run_time:6.2f} s")
    return [row for row, _ in results], elapsed


def format_value(value: object) -> str:
    """Floats as the shortest text that reads back as the same number: exact in the CSV."""
    return repr(value) if isinstance(value, float) else str(value)


def write_csv(rows: list[dict], path: Path) -> None:
    temporary = path.with_name(path.name + ".tmp")
    with open(temporary, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(COLUMNS)
        for row in rows:
            writer.writerow([format_value(row[c]) for c in COLUMNS])
    os.replace(temporary, path)


def plot(rows: list[dict], seconds: float, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    k = np.array([r["stiffness"] for r in rows])

    def column(name: str) -> np.ndarray:
        return np.array([r[name] for r in rows], dtype=float)

    fig, axes = plt.subplots(2, 2, figsize=(10, 7), dpi=110, sharex=True)
    ax = axes[0, 0]
    ax.plot(k, 100 * column("ball_compression"), "o-", label="ball, largest")
    ax.plot(k, 100 * column("block_compression"), "s-", label="block, largest")
    ax.plot(k, 100 * column("ball_squash_at_rest"), "^--", label="ball, at rest")
    ax.plot(k, 100 * column("max_strain"), "d:", label="max lattice strain")
    ax.set_ylabel("compression / strain (%)")
    ax.set_title("Deformation")
    ax.legend(fontsize="small")

    ax = axes[0, 1]
    ax.plot(k, 100 * column("rebound_m"), "o-", color="tab:green")
    ax.set_ylabel("rebound above rest (cm)")
    ax.set_title("Rebound of the ball")

    ax = axes[1, 0]
    ax.plot(k, column("settling_time_s"), "o-", color="tab:purple")
    ax.set_ylabel("settling time (s)")
    ax.set_title(f"Settling (rms speed < {SETTLED_SPEED:g} m/s; run {seconds:g} s)")

    ax = axes[1, 1]
    ax.plot(k, column("peak_depth_mm"), "o-", color="tab:red", label="deepest, any frame")
    ax.plot(k, column("final_depth_mm"), "s--", color="tab:orange", label="at the end")
    ax.set_ylabel("interpenetration depth (mm)")
    ax.set_title("Interpenetration (winding number)")
    ax.legend(fontsize="small", loc="upper right")
    deepest = float(np.nanmax(column("peak_depth_mm")))
    ax.set_ylim(0.0, max(1.0, 1.25 * deepest))
    if deepest == 0.0:
        ax.text(0.5, 0.5, "no vertex inside another body in any frame", ha="center",
                va="center", transform=ax.transAxes, color="0.4")

    for ax in axes.flat:
        ax.grid(True, alpha=0.3)
        ax.set_ylim(bottom=0.0)
        ax.set_xlim(0.0, 1.05)
    for ax in axes[1]:
        ax.set_xlabel("shape-matching stiffness")
    fig.suptitle("A soft ball dropped onto a soft block, against stiffness")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def values_argument(text: str) -> list[float]:
    """argparse type: "0.1,0.2,0.5" (a list) or "0.1:1:10" (10 values from 0.1 to 1).

    The values come back sorted, each once.
    """
    try:
        if ":" in text:
            parts = text.split(":")
            if len(parts) != 3:
                raise argparse.ArgumentTypeError(f"expected START:STOP:COUNT, got {text!r}")
            count = int(parts[2])
            if not 1 <= count <= 1000:
                raise argparse.ArgumentTypeError(f"expected a count of 1..1000, got {parts[2]}")
            values = [float(v) for v in np.linspace(float(parts[0]), float(parts[1]), count)]
        else:
            values = [float(v) for v in text.replace(" ", ",").split(",") if v]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected numbers like 0.1,0.5,1 or 0.1:1:10, got {text!r}") from None
    if not values:
        raise argparse.ArgumentTypeError("no values given")
    bad = [v for v in values if not 0 < v <= 1]
    if bad:
        raise argparse.ArgumentTypeError(
            f"a stiffness must be 0 < stiffness <= 1, got {', '.join(f'{v:g}' for v in bad)}")
    return sorted({round(v, 12) for v in values})


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description="Sweep shape-matching stiffness over a ball dropped onto a block, in "
                    "parallel processes; writes a CSV and a plot.")
    parser.add_argument("--values", type=values_argument, default=None,
                        help="stiffness values: a list (0.1,0.5,1) or START:STOP:COUNT "
                             "(default: 0.1:1:10; with --quick 0.1,0.4,0.7,1)")
    parser.add_argument("--seconds", type=float, default=3.0,
                        help="simulated time of each run (default: 3)")
    parser.add_argument("--cells", type=int, default=64,
                        help="about this many lattice cells per body (default: 64)")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                        help="processes (default: the number of cores)")
    parser.add_argument("--csv", type=Path, default=Path("stiffness_sweep.csv"),
                        help="the CSV to write (default: stiffness_sweep.csv)")
    parser.add_argument("--plot", type=Path, default=Path("stiffness_sweep.png"),
                        help="the plot to write, PNG (default: stiffness_sweep.png)")
    parser.add_argument("--verify", action="store_true",
                        help="run the sweep again with another number of processes and check "
                             "that every number is the same (exit status 1 if not)")
    parser.add_argument("--quick", action="store_true",
                        help="a short sweep (4 values, at most 3 s each) for tests")
    args = parser.parse_args(argv)
    if args.values is None:
        args.values = [0.1, 0.4, 0.7, 1.0] if args.quick else values_argument("0.1:1:10")
    if args.quick:
        args.seconds = min(args.seconds, 3.0)
    if not 0 < args.seconds <= MAX_SECONDS:
        parser.error(f"--seconds: expected 0 < seconds <= {MAX_SECONDS:g}, got {args.seconds}")
    if not 1 <= args.cells <= 100000:
        parser.error(f"--cells: expected 1..100000, got {args.cells}")
    if args.jobs < 1:
        parser.error(f"--jobs: expected 1 or more, got {args.jobs}")
    for option, path in (("--csv", args.csv), ("--plot", args.plot)):
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
        except OSError as e:
            parser.error(f"{option}: cannot make the folder {str(path.parent)!r}: {e.strerror}")

    jobs = min(args.jobs, len(args.values))
    print(f"{len(args.values)} runs of {args.seconds:g} s in {jobs} processes:")
    rows, elapsed = sweep(args.values, args.seconds, args.cells, jobs)
    print(f"sweep: {elapsed:.2f} s")

    write_csv(rows, args.csv)
    plot(rows, args.seconds, args.plot)

    def settle(t: float) -> str:
        return "moving" if math.isnan(t) else f"{t:.2f}s"

    print(f"{'stiffness':>9} {'ball cmp':>9} {'block cmp':>9} {'strain':>7} {'rebound':>8} "
          f"{'settle':>7} {'peak pen':>9} {'end pen':>8}")
    for r in rows:
        print(f"{r['stiffness']:>9g} {100 * r['ball_compression']:>8.1f}% "
              f"{100 * r['block_compression']:>8.1f}% {100 * r['max_strain']:>6.1f}% "
              f"{100 * r['rebound_m']:>6.1f}cm {settle(r['settling_time_s']):>7} "
              f"{r['peak_depth_mm']:>7.1f}mm {r['final_depth_mm']:>6.1f}mm")
    print(f"CSV written to {args.csv}, plot to {args.plot}")

    if args.verify:
        other = 1 if jobs > 1 else min(2, len(args.values))
        print(f"verifying: the same sweep in {other} process{'es' if other > 1 else ''}:")
        again, _ = sweep(args.values, args.seconds, args.cells, other)
        differ = [(a["stiffness"], c) for a, b in zip(rows, again) for c in COLUMNS
                  if format_value(a[c]) != format_value(b[c])]
        if differ:
            print(f"NOT deterministic: {len(differ)} values differ, first {differ[:5]}")
            return 1
        print(f"deterministic: all {len(rows) * len(COLUMNS)} values and hashes are the same "
              f"with {jobs} and {other} processes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
