"""The module gives what the command line gives: state hashes, statistics, error messages."""

import json
import subprocess

import pytest

import ffdaabb


def cli_run(cli: str, tmp_path, *args: str) -> dict:
    stats = tmp_path / "stats.json"
    subprocess.run([cli, "run", *args, "--quiet", "--stats", str(stats)], check=True)
    return json.loads(stats.read_text())


@pytest.mark.parametrize(
    "scene,frames,options",
    [
        ("spheres", 90, {}),
        ("teapots", 40, {"objects": 12, "seed": 5}),
        ("alphabets", 30, {"objects": 40, "seed": 3, "threads": 2}),
        ("colliders", 60, {"mode": "previous"}),
    ],
)
def test_the_state_hash_after_n_frames_is_the_command_lines(cli, tmp_path, scene, frames, options):
    flags = [f"--{k}={v}" for k, v in options.items()]
    expected = cli_run(cli, tmp_path, "--scene", scene, "--frames", str(frames), *flags)
    world = ffdaabb.World.from_scene(scene, **options)
    world.step(frames)
    assert f"{world.state_hash:016x}" == expected["state_hash"]
    # And at another thread count.
    other = ffdaabb.World.from_scene(scene, **{**options, "threads": 3})
    other.step(frames)
    assert other.state_hash == world.state_hash


def test_run_gives_the_command_lines_statistics(cli, tmp_path):
    expected = cli_run(cli, tmp_path, "--scene", "spheres", "--frames", "30", "--warmup", "5",
                       "--measure-every", "10")
    stats = ffdaabb.run("spheres", frames=30, warmup=5, measure_every=10)
    assert set(stats) == set(expected)
    assert set(stats["stage_ms"]) == set(expected["stage_ms"]) == set(ffdaabb.stages()) | {"total"}
    for key in ("state_hash", "objects", "vertices", "triangles", "cells", "particles",
                "frames", "warmup_frames", "seed", "mode", "contacts", "floor_contacts",
                "sleeping_bodies_at_end", "finite"):
        assert stats[key] == expected[key], key
    assert stats["interpenetration"] == expected["interpenetration"]


def test_the_profile_has_the_command_lines_names():
    world = ffdaabb.World.from_scene("spheres", objects=20)
    world.step(30)
    p = world.profile
    assert list(p["stage_ms"]) == ffdaabb.stages() + ["total"]
    assert {"object_collision", "total"} <= set(p["table1_ms"])
    assert p["stage_ms"]["total"] > 0 and p["frame"] == 30
    for key in ("candidate_pairs", "potential_pairs", "box_pairs", "contact_box_pairs",
                "contacts", "floor_contacts", "sleeping_bodies", "max_contact_depth"):
        assert key in p
    # Each box pair phase 3 tests was named by a node/box pair, and gives at most eight points.
    assert p["contact_box_pairs"] <= p["box_pairs"] <= p["potential_pairs"]
    assert p["contacts"] <= 8 * p["contact_box_pairs"]


def test_input_errors_carry_the_command_lines_message(cli, tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"objects": [{"mesh": "sphere", "count": -3}]}')
    result = subprocess.run([cli, "run", "--scene", str(bad), "--frames", "1", "--quiet"],
                            capture_output=True, text=True)
    assert result.returncode == 2
    printed = result.stderr.strip()
    assert printed.startswith("ffdaabb: error: ")
    with pytest.raises(ffdaabb.InputError) as error:
        ffdaabb.World.from_scene(bad)
    assert str(error.value) == printed[len("ffdaabb: error: "):]
    assert isinstance(error.value, ValueError)
    assert error.value.source and error.value.problem and str(bad) in str(error.value)
    with pytest.raises(ffdaabb.InputError) as again:
        ffdaabb.run(str(bad), frames=1)
    assert str(again.value) == str(error.value)


def test_box_standoff_is_mesh_infos(cli):
    # The sphere with the paper's 38 cells, as mesh-info builds it: the same figures.
    result = subprocess.run([cli, "mesh-info", "--generate", "sphere", "--json"],
                            capture_output=True, text=True, check=True)
    expected = json.loads(result.stdout)
    got = ffdaabb.box_standoff(*ffdaabb.sphere(), ffdaabb.LatticeSettings(cells=38))
    assert got["cell_size"] == pytest.approx(expected["cell_size"], rel=1e-6)
    assert got["size"] == pytest.approx(expected["size"], rel=1e-6)
    for key in ("directions", "median", "p90", "max"):
        assert got[key] == pytest.approx(expected["box_standoff"][key], rel=1e-6), key
    # A ball's boxes stand off its surface along the lattice's diagonals (known problem 9), by
    # less than a cell's diagonal.
    assert 0 < got["median"] <= got["p90"] <= got["max"] <= 3 ** 0.5 * 1.01 * got["cell_size"]
    assert len(got["worst_direction"]) == 3


def test_box_standoff_refuses_bad_input():
    vertices, triangles = ffdaabb.box([1, 1, 1])
    with pytest.raises(ffdaabb.InputError, match="directions"):
        ffdaabb.box_standoff(vertices, triangles, directions=0)
    with pytest.raises(ffdaabb.InputError, match="triangles"):
        ffdaabb.box_standoff(vertices, [[0, 1, 99]])
    aligned = ffdaabb.box_standoff(vertices, triangles, ffdaabb.LatticeSettings(cell_size=0.5),
                                   directions=100)
    assert aligned["directions"] == 100
    assert aligned["max"] <= 3 ** 0.5 * 0.005 * 0.5 * 1.001  # the skin alone
