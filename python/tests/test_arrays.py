"""Arrays: shapes and dtypes, views of the world's memory without copies, stale views."""

import gc
import pickle

import numpy as np
import pytest

import ffdaabb


@pytest.fixture
def world():
    w = ffdaabb.World()
    for i in range(3):
        w.add_body(*ffdaabb.sphere(), position=(2.5 * i, 1.5, 0))
    return w


def test_shapes_and_dtypes(world):
    body = world.bodies()[0]
    info = world.info(body)
    v, p, u = world.vertices(body), world.particles(body), world.velocities(body)
    assert isinstance(v, np.ndarray) and isinstance(v, ffdaabb.View)
    assert v.shape == (info["vertices"], 3) == (162, 3) and v.dtype == np.float32
    assert p.shape == u.shape == (info["particles"], 3) and p.dtype == u.dtype == np.float32
    t = world.triangles(body)
    assert t.shape == (320, 3) and t.dtype == np.uint32
    assert world.box_nodes(body).shape[1] == 3
    total_v = sum(world.info(b)["vertices"] for b in world.bodies())
    total_p = sum(world.info(b)["particles"] for b in world.bodies())
    assert world.all_vertices().shape == (total_v, 3)
    assert world.all_particles().shape == world.all_velocities().shape == (total_p, 3)
    assert world.all_vertices().dtype == np.float32
    assert ffdaabb.World().all_vertices().shape == (0, 3)


def test_a_view_sees_the_next_step_without_a_copy(world):
    body = world.bodies()[1]
    v, p = world.vertices(body), world.particles(body)
    address = v.__array_interface__["data"][0]
    before = np.array(v)
    world.step(5)
    assert v.__array_interface__["data"][0] == address
    assert not np.array_equal(before, v)  # it fell: the same memory, new values
    assert np.array_equal(np.asarray(v), world.vertices(body))
    assert v[:, 1].max() < before[:, 1].max()
    assert np.shares_memory(p, world.particles(body))
    assert not v.flags.writeable and not p.flags.writeable
    with pytest.raises(ValueError):
        v[0, 0] = 1.0


def test_the_whole_worlds_arrays_hold_each_body_in_order(world):
    world.step(3)
    allv, allp, allu = world.all_vertices(), world.all_particles(), world.all_velocities()
    for body in world.bodies():
        r = world.ranges(body)
        assert np.array_equal(allv[r.vertices], world.vertices(body))
        assert np.array_equal(allp[r.particles], world.particles(body))
        assert np.array_equal(allu[r.particles], world.velocities(body))
        assert np.shares_memory(allv[r.vertices], world.vertices(body))
    assert allv.__array_interface__["data"][0] == world.vertices(world.bodies()[0]).__array_interface__["data"][0]


@pytest.mark.parametrize("change", ["add", "remove", "restore"])
def test_a_view_used_after_the_arrays_move_raises(world, change):
    body = world.bodies()[0]
    saved = world.save_state()
    v, allp = world.vertices(body), world.all_particles()
    row, column = v[3], v[:, 1]  # slices are views too
    kept = np.array(v)  # a copy survives anything
    if change == "add":
        world.add_body(*ffdaabb.sphere(), position=(0, 5, 0))
    elif change == "remove":
        assert world.remove_body(world.bodies()[2])
    else:
        world.restore_state(saved)
    for stale in (v, allp, row, column):
        assert stale.stale
        with pytest.raises(ffdaabb.StaleViewError):
            stale[0]
        with pytest.raises(ffdaabb.StaleViewError):
            stale + 1  # ufuncs
        with pytest.raises(ffdaabb.StaleViewError):
            np.mean(stale)  # NumPy functions
        with pytest.raises(ffdaabb.StaleViewError):
            stale.sum()
        with pytest.raises(ffdaabb.StaleViewError):
            str(stale)
        with pytest.raises(ffdaabb.StaleViewError):
            stale.copy()
        with pytest.raises(ffdaabb.StaleViewError):
            list(stale)
        assert "stale" in repr(stale)
        # Paths that bypass the checks read nothing rather than freed memory.
        assert stale.size == 0 and np.array(stale).size == 0
    assert kept.shape == (162, 3) and np.isfinite(kept).all()
    fresh = world.vertices(body)
    assert not fresh.stale and fresh.shape == (162, 3)


def test_views_work_as_numpy_arrays(world):
    body = world.bodies()[0]
    v = world.vertices(body)
    assert np.allclose(v.mean(axis=0), world.centre_of_mass(body), atol=0.05)
    assert isinstance(v + 1, np.ndarray) and not isinstance(v + 1, ffdaabb.View)
    assert type(np.linalg.norm(v, axis=1)) is np.ndarray
    assert isinstance(v.T, ffdaabb.View) and isinstance(np.transpose(v), ffdaabb.View)
    assert pickle.loads(pickle.dumps(v)).shape == (162, 3)
    assert v.tolist()[0] == pytest.approx(list(v[0]))


def test_a_view_keeps_its_world_alive():
    w = ffdaabb.World()
    body = w.add_body(*ffdaabb.sphere(), position=(0, 2, 0))
    v = w.vertices(body)
    expected = np.array(v)
    del w
    gc.collect()
    assert np.array_equal(v, expected)


def test_input_arrays_of_any_numeric_type_are_taken():
    mesh = ffdaabb.sphere()
    w = ffdaabb.World()
    body = w.add_body(mesh.vertices.astype(np.float64), mesh.triangles.astype(np.int64).tolist())
    assert np.allclose(w.vertices(body), mesh.vertices)
    moved = np.array(w.particles(body), dtype=np.float64) + [0, 1, 0]
    w.set_particles(body, moved)
    assert np.allclose(w.particles(body), moved)
    assert not np.any(w.velocities(body))
