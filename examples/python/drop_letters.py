"""Drop the letters of a word onto the floor and onto each other, and plot their heights.

Each letter of the word (default "FFDAABB") is an extruded capital made soft by shape matching.
The letters start lying flat, fanned out along x so that each one overlaps the one before it,
and at staggered heights: the first lands on the floor, each later one partly on the letters
already down, so that they end in a sloping pile. Every frame the script records each letter's
centre-of-mass height, then plots the heights against time (matplotlib, Agg backend: no display
needed) and prints the final heights and how fast the world stepped.

Run it as

    python drop_letters.py                       # FFDAABB, 3 s, drop_letters.png
    python drop_letters.py --word SOFT --seconds 5 --stiffness 0.2 --out soft.png
    python drop_letters.py --quick --out results/drop.png

The frames per second printed count only World.step(), not the recording or the plot.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

import ffdaabb

MAX_SECONDS = 600.0


def quaternion_multiply(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The Hamilton product a * b of two quaternions (w, x, y, z): rotate by b, then by a."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return np.array([
        aw * bw - ax * bx - ay * by - az * bz,
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
    ])


def axis_angle(axis: tuple[float, float, float], degrees: float) -> np.ndarray:
    """The unit quaternion (w, x, y, z) of a rotation by `degrees` about `axis`."""
    half = math.radians(degrees) / 2.0
    direction = np.asarray(axis, dtype=float)
    direction /= np.linalg.norm(direction)
    return np.concatenate(([math.cos(half)], math.sin(half) * direction))


def word_argument(text: str) -> str:
    """argparse type: a word of the letters A-Z (lower case is accepted and raised)."""
    word = text.strip().upper()
    if not word:
        raise argparse.ArgumentTypeError("the word is empty")
    bad = sorted({c for c in word if not ("A" <= c <= "Z")})
    if bad:
        raise argparse.ArgumentTypeError(
            f"only the letters A-Z can be dropped, not {', '.join(repr(c) for c in bad)}")
    if len(word) > 26:
        raise argparse.ArgumentTypeError(f"at most 26 letters, got {len(word)}")
    return word


def number(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None


def seconds_argument(text: str) -> float:
    value = number(text)
    if not 0 < value <= MAX_SECONDS:
        raise argparse.ArgumentTypeError(f"expected 0 < seconds <= {MAX_SECONDS:g}, got {text}")
    return value


def stiffness_argument(text: str) -> float:
    value = number(text)
    if not 0 < value <= 1:
        raise argparse.ArgumentTypeError(f"expected 0 < stiffness <= 1, got {text}")
    return value


def build_world(word: str, stiffness: float, threads: int,
                pitch: float = 0.55, gap: float = 0.4) -> tuple[ffdaabb.World, list]:
    """A world with the word's letters lying flat, fanned out along x at staggered heights.

    Letter i lies `pitch` metres to the right of letter i - 1 and `gap` metres higher (more
    than its 0.25 m thickness, so that no two letters start overlapping).
    """
    world = ffdaabb.World(threads=threads)
    flat = axis_angle((1.0, 0.0, 0.0), -90.0)  # the letter's face up, its top towards -z
    bodies = []
    for i, capital in enumerate(word):
        yaw = axis_angle((0.0, 1.0, 0.0), 12.0 if i % 2 else -12.0)
        rotation = quaternion_multiply(yaw, flat)
        body = world.add_body(
            *ffdaabb.letter(capital),
            position=(i * pitch, 0.25 + gap * i, 0.5),
            rotation=tuple(float(q) for q in rotation),
            stiffness=stiffness,
        )
        bodies.append(body)
    return world, bodies


def simulate(world: ffdaabb.World, bodies: list, frames: int) -> tuple[np.ndarray, float]:
    """Steps `frames` frames; returns the heights (frames + 1, bodies) and the stepping time."""
    heights = np.empty((frames + 1, len(bodies)))
    heights[0] = [world.centre_of_mass(b)[1] for b in bodies]
    stepping = 0.0
    for frame in range(1, frames + 1):
        start = time.perf_counter()
        world.step()
        stepping += time.perf_counter() - start
        heights[frame] = [world.centre_of_mass(b)[1] for b in bodies]
    return heights, stepping


def plot(word: str, times: np.ndarray, heights: np.ndarray, stiffness: float, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4.5), dpi=120)
    colours = plt.get_cmap("viridis")(np.linspace(0.0, 0.9, len(word)))
    for i, capital in enumerate(word):
        ax.plot(times, heights[:, i], color=colours[i], label=f"{capital} ({i + 1})")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("centre-of-mass height (m)")
    ax.set_title(f'Letters of "{word}" dropped onto the floor (stiffness {stiffness:g})')
    ax.set_xlim(times[0], times[-1])
    ax.set_ylim(bottom=0.0)
    ax.grid(True, alpha=0.3)
    ax.legend(ncol=2 if len(word) > 8 else 1, fontsize="small", loc="upper right")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description="Drop a word's letters onto the floor and plot their heights against time.")
    parser.add_argument("--word", type=word_argument, default="FFDAABB",
                        help="the letters to drop, A-Z (default: FFDAABB)")
    parser.add_argument("--seconds", type=seconds_argument, default=3.0,
                        help="simulated time (default: 3)")
    parser.add_argument("--stiffness", type=stiffness_argument, default=0.5,
                        help="shape-matching stiffness of the letters, 0 < s <= 1 (default: 0.5)")
    parser.add_argument("--threads", type=int, default=1,
                        help="the world's worker threads, 0: all cores (default: 1)")
    parser.add_argument("--out", type=Path, default=Path("drop_letters.png"),
                        help="the plot to write, PNG (default: drop_letters.png)")
    parser.add_argument("--quick", action="store_true",
                        help="a short run (1.5 s simulated) for tests")
    args = parser.parse_args(argv)
    if args.threads < 0:
        parser.error(f"--threads: expected 0 (all cores) or more, got {args.threads}")
    try:
        args.out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        parser.error(f"--out: cannot make the folder {str(args.out.parent)!r}: {e.strerror}")

    seconds = min(args.seconds, 1.5) if args.quick else args.seconds
    world, bodies = build_world(args.word, args.stiffness, args.threads)
    frames = max(1, round(seconds / world.settings.frame_step))
    heights, stepping = simulate(world, bodies, frames)
    times = np.arange(frames + 1) * world.settings.frame_step

    plot(args.word, times, heights, args.stiffness, args.out)

    overlap = world.interpenetration()
    print(f"{len(bodies)} letters, {sum(world.info(b)['particles'] for b in bodies)} lattice "
          f"particles, {frames} frames ({times[-1]:.2f} s simulated)")
    print("final centre-of-mass heights (m):")
    for i, capital in enumerate(args.word):
        print(f"  {capital} ({i + 1}): {heights[-1, i]:.3f}  (dropped from {heights[0, i]:.3f})")
    print(f"stepping: {stepping:.3f} s, {frames / stepping:.0f} frames per second "
          f"({1000 * stepping / frames:.2f} ms a frame)")
    print(f"deepest interpenetration at the end: {overlap['max_depth_m'] * 1000:.1f} mm "
          f"({overlap['inside_vertices']} vertices inside another letter)")
    print(f"plot written to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
