"""ffdaabb: real-time simulation of many deformable objects, from Python.

Dense triangle meshes are embedded in sparse FFD lattices, the lattices move by shape matching,
and objects collide through the Enhanced FFD-AABB pipeline (Jeon, Choi and Hong, 2012).

    import ffdaabb
    world = ffdaabb.World.from_scene("spheres")      # a shipped scene, or a JSON file
    world.step(120)                                   # two seconds; the GIL is released
    v = world.vertices(world.bodies()[0])             # float32 (V, 3), a view: no copy

    w = ffdaabb.World(substeps=4)                     # WorldSettings fields by keyword
    ball = w.add_body(*ffdaabb.sphere(), position=(0, 2, 0), stiffness=0.5)
    w.step(60)
    print(w.centre_of_mass(ball), w.profile["stage_ms"]["total"])

Arrays: vertices, particles and velocities are float32 Views of the world's memory (see View);
meshes go in and come out as NumPy arrays (Mesh). Errors in input raise InputError, a ValueError
whose message is the one the command line prints. The full reference is in the type stub
(_ffdaabb.pyi) and the README's Python section.
"""

import os as _os

from ._support import BodyContact, Contact, ContactPair, Mesh, RayHit, StaleViewError, View
from ._ffdaabb import (  # noqa: F401  (re-exported)
    BodyId,
    BodySettings,
    InputError,
    LatticeSettings,
    PinId,
    PinSettings,
    PlaneId,
    Ranges,
    World,
    WorldSettings,
    __version__,
    add_data_folder,
    bowl,
    box,
    box_standoff,
    data_folders,
    dragon,
    generate,
    letter,
    load_mesh,
    run,
    save_obj,
    scene_names,
    settings_table,
    sphere,
    stages,
    teapot,
)

# The package's own data (scenes and models) when installed from a wheel, or the build tree's.
_data = _os.path.join(_os.path.dirname(__file__), "data")
if _os.path.isdir(_data):
    add_data_folder(_data)

__all__ = [
    "BodyContact",
    "BodyId",
    "BodySettings",
    "Contact",
    "ContactPair",
    "InputError",
    "LatticeSettings",
    "Mesh",
    "PinId",
    "PinSettings",
    "PlaneId",
    "Ranges",
    "RayHit",
    "StaleViewError",
    "View",
    "World",
    "WorldSettings",
    "__version__",
    "add_data_folder",
    "bowl",
    "box",
    "box_standoff",
    "data_folders",
    "dragon",
    "generate",
    "letter",
    "load_mesh",
    "run",
    "save_obj",
    "scene_names",
    "settings_table",
    "sphere",
    "stages",
    "teapot",
]
