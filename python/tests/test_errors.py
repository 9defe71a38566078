"""Every class of error: bad input raises InputError (a ValueError) naming what is wrong; wrong
types and keywords raise TypeError; stale views StaleViewError; busy worlds RuntimeError."""

import numpy as np
import pytest

import ffdaabb


@pytest.fixture
def world():
    w = ffdaabb.World()
    w.add_body(*ffdaabb.sphere(), position=(0, 2, 0))
    return w


def test_settings_out_of_range_name_the_field():
    with pytest.raises(ffdaabb.InputError, match=r"substeps: value 0 is out of range \(expected 1..1000\)"):
        ffdaabb.WorldSettings(substeps=0)
    s = ffdaabb.BodySettings()
    with pytest.raises(ValueError, match="restitution"):
        s.restitution = 2
    assert s.restitution == 0  # unchanged
    with pytest.raises(ValueError, match=r"mode: unknown value \"fast\" \(expected enhanced"):
        ffdaabb.WorldSettings(mode="fast")
    with pytest.raises(ValueError, match="motion"):
        ffdaabb.BodySettings(motion="flying")
    with pytest.raises(ValueError, match="stiffness"):
        ffdaabb.PinSettings(stiffness=-1)
    with pytest.raises(ValueError, match="threads"):
        ffdaabb.World(threads=-1)


def test_unknown_keywords_and_wrong_types_raise_type_error(world):
    with pytest.raises(TypeError, match="unexpected keyword argument 'substep'"):
        ffdaabb.World(substep=3)
    with pytest.raises(TypeError, match="unexpected keyword argument 'colour'"):
        world.add_body(*ffdaabb.sphere(), colour=1)
    with pytest.raises(TypeError):
        world.apply_force(world.bodies()[0], (1, 2))  # not 3 numbers
    with pytest.raises(TypeError):
        world.step("ten")


def test_bad_meshes_and_arrays_name_the_argument(world):
    v, t = ffdaabb.sphere()
    with pytest.raises(ValueError, match=r"vertices: expected an array of shape \(N, 3\), got shape \(162, 2\)"):
        world.add_body(v[:, :2], t)
    with pytest.raises(ValueError, match="triangles: expected an integer array"):
        world.add_body(v, t[:, :2])
    with pytest.raises(ValueError, match="triangles: expected integers"):
        world.add_body(v, t.astype(np.float32))
    with pytest.raises(ValueError, match="index -1 at triangle 0"):
        world.add_body(v, np.vstack([[-1, 0, 1], t]))
    bad = t.copy()
    bad[5, 1] = 999
    with pytest.raises(ffdaabb.InputError, match="index 999 at triangle 5"):
        world.add_body(v, bad)
    nan = v.copy()
    nan[7] = np.nan
    with pytest.raises(ffdaabb.InputError):
        world.add_body(nan, t)
    body = world.bodies()[0]
    with pytest.raises(ValueError, match=r"positions: expected \d+ rows"):
        world.set_particles(body, np.zeros((3, 3)))


def test_generator_arguments_take_the_cores_ranges():
    # The same ranges as the core and the scene files ("teapot:N", "icosphere:N"), and messages
    # naming the Python argument.
    assert len(ffdaabb.teapot(100).triangles) == 32 * 2 * 100 * 100
    assert len(ffdaabb.generate("teapot:100").triangles) == 32 * 2 * 100 * 100
    with pytest.raises(ffdaabb.InputError, match=r"quads_per_patch: value 257 is out of range \(expected 1..256\)"):
        ffdaabb.teapot(257)
    with pytest.raises(ffdaabb.InputError, match=r"quads_per_patch: value 0 is out of range"):
        ffdaabb.teapot(0)
    with pytest.raises(ffdaabb.InputError, match=r"subdivisions: value 9 is out of range \(expected 0..8\)"):
        ffdaabb.sphere(9)
    with pytest.raises(ffdaabb.InputError, match=r"subdivisions: value -1 is out of range"):
        ffdaabb.sphere(-1)


def test_stale_handles_are_input_errors(world):
    body = world.bodies()[0]
    assert world.remove_body(body) and not world.remove_body(body)
    assert not world.is_valid(body)
    for call in (world.vertices, world.particles, world.centre_of_mass, world.info):
        with pytest.raises(ffdaabb.InputError):
            call(body)
    with pytest.raises(ffdaabb.InputError):
        world.apply_force(body, (0, 1, 0))


def test_scenes_files_and_states(world, tmp_path):
    with pytest.raises(ffdaabb.InputError, match="no such scene"):
        ffdaabb.World.from_scene("nowhere")
    with pytest.raises(ffdaabb.InputError, match=r"objects: value 0 is out of range"):
        ffdaabb.World.from_scene("spheres", objects=0)
    with pytest.raises(ffdaabb.InputError, match="mode"):
        ffdaabb.run("spheres", frames=1, mode="quick")
    with pytest.raises(ffdaabb.InputError, match="frames"):
        ffdaabb.run("spheres", frames=0)
    missing = tmp_path / "missing.obj"
    with pytest.raises(ffdaabb.InputError) as error:
        ffdaabb.load_mesh(missing)
    assert error.value.source == str(missing)
    with pytest.raises(ffdaabb.InputError, match="state"):
        world.restore_state(b"not a state")
    other = ffdaabb.World.from_scene("spheres", objects=3)
    with pytest.raises(ffdaabb.InputError, match="scene"):
        world.restore_state(other.save_state())
    with pytest.raises(ffdaabb.InputError):
        ffdaabb.letter("a")
    with pytest.raises(ffdaabb.InputError, match="capital"):
        ffdaabb.letter("AB")
    with pytest.raises(ffdaabb.InputError):
        ffdaabb.generate("cube")
    with pytest.raises(ffdaabb.InputError, match="triangles"):
        ffdaabb.save_obj(str(tmp_path / "x.obj"), np.zeros((3, 3)), [[0, 1, 5]])
    assert not (tmp_path / "x.obj").exists()
    with pytest.raises(ffdaabb.InputError):
        ffdaabb.save_obj(str(tmp_path / "no" / "x.obj"), *ffdaabb.sphere())
    with pytest.raises(ffdaabb.InputError, match="direction"):
        world.raycast((0, 0, 0), (0, 0, 0))
    with pytest.raises(ffdaabb.InputError):
        world.add_plane((0, 0, 0), 1)


def test_stale_views_raise_their_own_error(world):
    v = world.vertices(world.bodies()[0])
    world.add_body(*ffdaabb.sphere(), position=(3, 2, 0))
    with pytest.raises(ffdaabb.StaleViewError, match="take it again"):
        v[0]
    assert issubclass(ffdaabb.StaleViewError, ReferenceError)
