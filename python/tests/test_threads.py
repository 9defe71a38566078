"""step() releases the GIL; a World takes one call at a time."""

import threading
import time

import pytest

import ffdaabb


def test_another_python_thread_runs_while_step_runs():
    world = ffdaabb.World.from_scene("alphabets", objects=60)
    settings = world.settings
    settings.substeps = 40  # one frame: a long single call into the library
    world.settings = settings
    world.step(1)
    stamps: list[float] = []
    stop = threading.Event()

    def count() -> None:
        while not stop.is_set():
            stamps.append(time.perf_counter())

    thread = threading.Thread(target=count)
    thread.start()
    try:
        time.sleep(0.01)
        start = time.perf_counter()
        world.step(1)
        end = time.perf_counter()
    finally:
        stop.set()
        thread.join()
    assert end - start > 0.02, "the frame is too short to tell"
    margin = 0.002
    inside = [t for t in stamps if start + margin < t < end - margin]
    # With the GIL held through the frame, the other thread could not run at all inside it.
    assert len(inside) > 100, f"{len(inside)} iterations of the other thread during step()"


def test_a_second_call_while_step_runs_raises():
    world = ffdaabb.World.from_scene("spheres")
    errors: list[str] = []
    done = threading.Event()

    def step() -> None:
        try:
            world.step(120)
        finally:
            done.set()

    thread = threading.Thread(target=step)
    thread.start()
    while not done.is_set():
        try:
            world.frame
        except RuntimeError as e:
            errors.append(str(e))
        time.sleep(0.0005)
    thread.join()
    assert errors, "no call was made while step() ran"
    assert "step() is running in another thread" in errors[0]
    assert world.frame == 120  # the step itself was not disturbed


def test_worlds_in_different_threads_step_at_once_and_alike():
    hashes = {}

    def run(name: int) -> None:
        w = ffdaabb.World.from_scene("spheres", objects=30)
        w.step(60)
        hashes[name] = w.state_hash

    threads = [threading.Thread(target=run, args=(i,)) for i in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(set(hashes.values())) == 1


def test_step_takes_a_count():
    world = ffdaabb.World.from_scene("spheres", objects=5)
    world.step()
    world.step(0)
    world.step(9)
    assert world.frame == 10
    with pytest.raises(ValueError, match="n: value -1"):
        world.step(-1)
