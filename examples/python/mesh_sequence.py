"""Write a simulation out as a sequence of OBJ files, one per frame, for a renderer.

The script builds a shipped scene (default: "spheres" with 10 objects), steps it, and every
--every frames writes every body's deformed mesh into one OBJ file: frame_0000.obj,
frame_0001.obj, ... in the --out folder, each body an `o body_<i>` object (i: its place in
World.bodies()). The vertices are read through World.vertices(), a view of the world's memory
(no copy), taken once: the views see every later step. The OBJ text is made by NumPy and string
formatting, not a loop over vertices; the faces, which do not change, are formatted once.
Every file is written under a temporary name and then renamed (os.replace), so that a reader
never sees a half-written file and an interrupted run leaves none behind.

Run it as

    python mesh_sequence.py                          # 120 frames of "spheres", mesh_sequence/
    python mesh_sequence.py --scene teapots --objects 4 --frames 300 --every 5 --out teapots
    python mesh_sequence.py --quick --out results/sequence

Frame files hold the state after 0, every, 2 x every, ... frames (frame_0000.obj is the start).
Files of an earlier run with more frames are not removed: use an empty folder for each run.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

import ffdaabb


def face_text(triangles: np.ndarray, offset: int) -> str:
    """The `f` lines of a body's triangles, with OBJ's 1-based indices after `offset` vertices."""
    indices = np.asarray(triangles, dtype=np.int64) + (offset + 1)
    return ("f %d %d %d\n" * len(indices)) % tuple(indices.ravel().tolist())


def vertex_text(vertices: np.ndarray) -> str:
    """The `v` lines of a (V, 3) array, micrometre precision."""
    return ("v %.6f %.6f %.6f\n" * len(vertices)) % tuple(vertices.ravel().tolist())


def write_atomically(path: Path, text: str) -> None:
    """Writes `text` to `path` through a temporary name: the file is whole, or not there."""
    temporary = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        with open(temporary, "w", encoding="ascii", newline="\n") as f:
            f.write(text)
        os.replace(temporary, path)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise


class ObjWriter:
    """Formats a world's bodies as one OBJ text per frame.

    The views of the vertices and the face lines are made once: bodies must not be added or
    removed while it is used (the views would become stale, and World raises an error).
    """

    def __init__(self, world: ffdaabb.World, header: str) -> None:
        self.header = header
        self.vertices: list[np.ndarray] = []
        self.parts: list[tuple[str, str]] = []
        offset = 0
        for i, body in enumerate(world.bodies()):
            vertices = world.vertices(body)  # a view: sees every later step, no copy
            self.vertices.append(vertices)
            self.parts.append((f"o body_{i}\n", face_text(world.triangles(body), offset)))
            offset += len(vertices)
        self.vertex_count = offset
        self.triangle_count = sum(len(world.triangles(b)) for b in world.bodies())

    def text(self, frame: int) -> str:
        pieces = [f"# {self.header}, frame {frame}\n"]
        for vertices, (name, faces) in zip(self.vertices, self.parts):
            pieces += [name, vertex_text(vertices), faces]
        return "".join(pieces)


def positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected 1 or more, got {value}")
    return value


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description="Step a scene and write every body's mesh, one OBJ file per frame.")
    parser.add_argument("--scene", default="spheres",
                        help=f"a shipped scene ({', '.join(ffdaabb.scene_names())}) or a scene "
                             "JSON file (default: spheres)")
    parser.add_argument("--objects", type=positive_int, default=10,
                        help="objects in the scene (default: 10)")
    parser.add_argument("--seed", type=int, default=None,
                        help="the scene's random seed (default: the scene's own)")
    parser.add_argument("--frames", type=positive_int, default=120,
                        help="frames to step (default: 120, 2 s)")
    parser.add_argument("--every", type=positive_int, default=1,
                        help="write a file every this many frames (default: 1)")
    parser.add_argument("--out", type=Path, default=Path("mesh_sequence"),
                        help="the folder to write into, made if needed (default: mesh_sequence)")
    parser.add_argument("--quick", action="store_true",
                        help="a short run (30 frames, a file every 3) for tests")
    args = parser.parse_args(argv)
    if args.quick:
        args.frames = min(args.frames, 30)
        args.every = max(args.every, 3)
    if args.frames > 100000:
        parser.error(f"--frames: expected at most 100000, got {args.frames}")

    try:
        world = ffdaabb.World.from_scene(args.scene, objects=args.objects, seed=args.seed)
    except ffdaabb.InputError as e:
        parser.error(f"--scene: {e}")
    try:
        args.out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        parser.error(f"--out: cannot make the folder {str(args.out)!r}: {e.strerror}")

    writer = ObjWriter(world, f"{args.scene}, {world.body_count} bodies")
    digits = max(4, len(str(args.frames // args.every)))
    written: list[Path] = []
    writing = formatting = stepping = 0.0

    def write(frame: int) -> None:
        nonlocal writing, formatting
        start = time.perf_counter()
        text = writer.text(frame)
        formatted = time.perf_counter()
        path = args.out / f"frame_{len(written):0{digits}d}.obj"
        write_atomically(path, text)
        written.append(path)
        formatting += formatted - start
        writing += time.perf_counter() - start

    write(0)
    for frame in range(1, args.frames + 1):
        start = time.perf_counter()
        world.step()
        stepping += time.perf_counter() - start
        if frame % args.every == 0:
            write(frame)

    size = sum(p.stat().st_size for p in written)
    count = len(written)
    print(f"{world.body_count} bodies, {writer.vertex_count} vertices and "
          f"{writer.triangle_count} triangles a file")
    print(f"wrote {count} files ({size / 1e6:.1f} MB) to {args.out}: "
          f"{written[0].name} .. {written[-1].name}")
    print(f"writing: {1000 * writing / count:.2f} ms a file "
          f"({1000 * formatting / count:.2f} ms formatting the text)")
    print(f"stepping: {1000 * stepping / args.frames:.2f} ms a frame ({args.frames} frames)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
