"""The World's features from Python: bodies, forces, pins, colliders, sleeping, queries,
snapshots, generators and mesh files."""

import numpy as np
import pytest

import ffdaabb


def test_a_ball_falls_lands_and_falls_asleep():
    w = ffdaabb.World()
    ball = w.add_body(*ffdaabb.sphere(), position=(0, 3, 0), lattice=ffdaabb.LatticeSettings(cells=38))
    w.step(20)
    assert w.linear_velocity(ball)[1] < -2.5  # free fall, about g t
    w.step(280)
    lo, hi = w.bounds(ball)
    assert -0.02 < lo[1] < 0.05 and abs(hi[1] - lo[1] - 2) < 0.1
    assert not w.is_awake(ball) and w.awake_count == 0  # asleep from about frame 270
    assert w.touching_bodies(ball)[0].other is None  # the floor
    w.apply_impulse(ball, (0, 50, 0))
    assert w.is_awake(ball)


def test_settings_read_back_and_apply():
    s = ffdaabb.WorldSettings(substeps=3, gravity=(0, -5, 0), mode="previous")
    w = ffdaabb.World(s, threads=2)
    assert w.settings.substeps == 3 and w.settings.threads == 2 and w.settings.mode == "previous"
    assert list(w.settings.gravity) == [0, -5, 0]
    changed = w.settings
    changed.solver_iterations = 8
    w.settings = changed
    assert w.settings.solver_iterations == 8
    assert ffdaabb.WorldSettings().contact_skin == 0.05  # the float as written, not 0.0500000007
    table = ffdaabb.settings_table()
    assert [r["key"] for r in table["world"]] == ffdaabb.WorldSettings.fields[: len(table["world"])]
    for r in table["material"]:
        assert getattr(ffdaabb.BodySettings(), r["key"]) == pytest.approx(r["default"])
    b = ffdaabb.BodySettings(stiffness=0.5, position=(1, 2, 3))
    assert b == b.copy() and b != ffdaabb.BodySettings()


def test_forces_velocities_and_translation():
    w = ffdaabb.World(floor=False, gravity=(0, 0, 0))
    body = w.add_body(*ffdaabb.sphere(), position=(0, 0, 0))
    mass = w.info(body)["mass"]
    start = w.centre_of_mass(body)
    w.apply_impulse(body, (mass * 2.0, 0, 0))
    assert w.linear_velocity(body) == pytest.approx([2, 0, 0], abs=1e-4)
    w.step(30)
    assert w.centre_of_mass(body) - start == pytest.approx([1, 0, 0], abs=0.01)
    w.set_velocity(body, (0, 0, 0))
    here = w.centre_of_mass(body)
    w.translate(body, (0, 5, 0))
    assert w.centre_of_mass(body) - here == pytest.approx([0, 5, 0], abs=1e-4)
    assert sum(w.particle_mass(body, i) for i in range(len(w.particles(body)))) == pytest.approx(mass, rel=1e-4)


def test_a_hanging_letter_pin_carries_its_weight():
    w = ffdaabb.World()
    j = w.add_body(*ffdaabb.letter("J"), position=(0, 2, 0))
    top = w.vertices(j)[np.argmax(w.vertices(j)[:, 1])]
    pin = w.pin_point(j, top, ffdaabb.PinSettings(swing_damping=2))
    w.step(240)
    info = w.pin(pin)
    assert info["body"] == j and info["lag"] < 0.01
    weight = w.info(j)["mass"] * 9.81
    assert info["force"][1] == pytest.approx(weight, rel=0.05)
    assert w.pins() == [pin] and w.unpin(pin) and not w.is_valid(pin)


def test_static_kinematic_bodies_and_planes():
    w = ffdaabb.World()
    slab = w.add_body(*ffdaabb.box((2, 0.2, 2)), position=(0, 0.2, 0), motion="static")
    paddle = w.add_body(*ffdaabb.box((0.3, 0.3, 0.3)), position=(-3, 0.8, 0), motion="kinematic")
    ball = w.add_body(*ffdaabb.sphere(), position=(0, 2, 0))
    before = np.array(w.particles(slab))
    start = w.centre_of_mass(paddle)
    for i in range(60):
        w.set_kinematic_target(paddle, (-3 + 0.02 * i, 0.8, 0))
        w.step()
    assert np.array_equal(before, w.particles(slab))
    assert w.centre_of_mass(paddle) - start == pytest.approx([0.02 * 59, 0, 0], abs=0.01)
    assert w.bounds(ball)[0][1] > 0.38  # resting on the slab, not in it
    plane = w.add_plane((0.3, 1, 0), 0.5)
    assert len(w.planes()) == 1 and w.planes()[0][1] == 0.5
    assert np.linalg.norm(w.planes()[0][0]) == pytest.approx(1)
    assert w.remove_plane(plane) and not w.planes()


def test_queries_and_contact_events():
    w = ffdaabb.World()
    ball = w.add_body(*ffdaabb.sphere(), position=(0, 1.3, 0))
    hit = w.raycast((0, 10, 0), (0, -1, 0))
    assert hit is not None and hit.body == ball and hit.distance == pytest.approx(7.7, abs=0.02)
    assert hit.normal[1] > 0.9 and sum(hit.barycentric) == pytest.approx(1)
    assert len(w.raycast_all((0, 10, 0), (0, -1, 0))) >= 2
    assert w.raycast((0, 10, 0), (0, -1, 0), ignore=[ball]) is None
    assert w.bodies_overlapping((-0.1, 1.2, -0.1), (0.1, 1.4, 0.1)) == [ball]
    assert not w.body_overlaps(ball, (5, 5, 5), (6, 6, 6))
    began = []
    for _ in range(50):  # it touches the floor at frame 15 and falls asleep (no contacts) at 59
        w.step()
        began += w.contact_events()["begin"]
    assert (ball, None) in began
    pairs = w.contact_pairs()
    assert pairs and pairs[0].body_b is None and pairs[0].contact_count > 0
    contacts = w.contacts()
    assert contacts and all(c.body_a == ball for c in contacts)


def test_snapshots_round_trip_bit_for_bit():
    w = ffdaabb.World.from_scene("teapots", objects=10)
    w.step(40)
    saved = w.save_state()
    assert isinstance(saved, bytes)
    w.step(30)
    expected = w.state_hash
    w.restore_state(saved)
    assert w.frame == 40
    w.step(30)
    assert w.state_hash == expected
    fresh = ffdaabb.World.from_scene("teapots", objects=10, threads=2)
    fresh.restore_state(bytearray(saved))
    fresh.step(30)
    assert fresh.state_hash == expected


def test_generators_and_mesh_files(tmp_path):
    s = ffdaabb.sphere()
    assert s.vertices.shape == (162, 3) and s.triangles.shape == (320, 3)
    assert s.vertices.dtype == np.float32 and s.triangles.dtype == np.uint32
    assert np.allclose(np.linalg.norm(s.vertices, axis=1), 1, atol=1e-5)
    t = ffdaabb.teapot()
    assert abs(len(t.vertices) - 3242) < 100 and len(t.triangles) == 6400
    a = ffdaabb.letter("A")
    assert a.vertices[:, 1].min() == pytest.approx(0, abs=1e-5)
    assert ffdaabb.box((1, 2, 3), 1).vertices.max(axis=0) == pytest.approx([1, 2, 3])
    assert len(ffdaabb.bowl().triangles) > 0 and len(ffdaabb.generate("icosphere:1").vertices) == 42
    d = ffdaabb.dragon(target_triangles=4000)
    assert abs(len(d.triangles) - 4000) < 400
    path = tmp_path / "s.obj"
    ffdaabb.save_obj(str(path), *s)
    back = ffdaabb.load_mesh(str(path))
    # The same points (the reader may order them otherwise) and the same triangles over them.
    def rows(v):
        return v[np.lexsort(v.T[::-1])]

    assert np.allclose(rows(back.vertices), rows(s.vertices), atol=1e-6)
    assert np.allclose(rows(back.vertices[back.triangles].reshape(-1, 9)),
                       rows(s.vertices[s.triangles].reshape(-1, 9)), atol=1e-6)


def test_interpenetration_is_measured_on_the_meshes():
    w = ffdaabb.World(gravity=(0, 0, 0), floor=False, overlap_recovery_speed=0)
    a = w.add_body(*ffdaabb.sphere(), position=(0, 0, 0))
    b = w.add_body(*ffdaabb.sphere(), position=(1.5, 0, 0))
    m = w.interpenetration()
    assert m["inside_vertices"] > 0 and m["body_pairs"] == 1
    deepest = m["deepest_vertex"]
    assert {deepest["body"], deepest["inside"]} == {a, b}
    assert 0 <= deepest["vertex"] < len(w.vertices(deepest["body"]))
    assert m["max_depth_m"] == pytest.approx(0.5, abs=0.06)
    assert m["reference_size_m"] == pytest.approx(2, abs=0.05)
    apart = ffdaabb.World()
    apart.add_body(*ffdaabb.sphere(), position=(0, 2, 0))
    assert apart.interpenetration()["inside_vertices"] == 0
    assert apart.interpenetration()["deepest_vertex"] is None
