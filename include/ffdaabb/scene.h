// Scenes as data: JSON files that say which objects fall where, with what lattice and material,
// in which world. The paper's four experiments ship as scenes/alphabets.json, spheres.json,
// teapots.json and buddhas.json; the CLI, the benchmarks, the tests and the viewer all load
// them through this one interface.
//
// Format (every field optional unless noted; unknown fields are errors):
//   {
//     "name": "spheres", "description": "...",
//     "world":  { "frame_step": 1/60, "substeps": 2, "gravity": [0,-9.81,0], "floor": true,
//                 "floor_height": 0, "mode": "enhanced", "contact_skin": 0.05,
//                 "solver_iterations": 4, "threads": 1, "sweep_threshold": 64,
//                 "max_separation_speed": 2, "push_out_speed": 0,
//                 "overlap_recovery_speed": 2 },
//     "objects": [ {                              (required, at least one)
//         "mesh": "sphere" | "letters" | any generator name | {"file": "path.obj"},
//         "letters": "ABC...",                     (for "letters": cycled over the count)
//         "count": 100, "size": 1.0,               (size: largest extent, metres)
//         "lattice":  { "cells": 38 | "cell_size": 0.1 | "resolution": 5,
//                       "fill_interior": true, "box_skin": 0.005 },
//         "material": { "model": "shape-matching" | "mass-spring", "region_half_width": 1,
//                       "stiffness": 1, "youngs_modulus": 2e5, "spring_iterations": 20,
//                       "density": 1000, "mass": 0, "damping": 20, "region_damping": false,
//                       "friction": 0.5, "restitution": 0, "contact_rigidity": 0.5 },
//         "motion": "dynamic" | "static" | "kinematic",   (BodyMotion: colliders)
//         "position": [0,0.5,0],                   (its bounds' centre there, not by the layout;
//                                                  count 1)
//         "scale": [1,0.2,1] } ],                  (per axis, after size: a slab from "box")
//     "layout": { "origin": [0,1,0], "columns": [5,5], "spacing": 1.2, "jitter": 0.1,
//                 "random_rotation": true, "velocity": [0,0,0], "velocity_jitter": 0,
//                 "seed": 1 },
//     "pins": [ {                                  (World::pinParticle and the like)
//         "object": 0,                             (required: the body, in the order made)
//         "particle": 3 | "vertex": 12 | "point": [0,2.5,0],  (exactly one; point: where the
//                                                  body is as placed, world coordinates)
//         "target": [0,2.5,0],                     (default: where the pinned point starts)
//         "stiffness": "hard" | 5000,              (N/m)
//         "rigidity": 1, "swing_damping": 0.5, "max_speed": 10 } ],
//     "planes": [ { "normal": [0.3,1,0], "offset": 0 } ]   (World::addPlane, besides the floor)
//   }
// The layout stacks the objects in layers of columns[0] x columns[1] cells of `spacing` metres
// (centred on origin in x and z, rising from origin.y), in the order of `objects`, each cell
// jittered and each object rotated at random (seeded, so a scene is deterministic). Objects with
// a "position" (colliders: stairs, a bowl, a platform) are placed there, unrotated and at rest,
// and take no cell of the layout.
#pragma once

#include "ffdaabb/world.h"

#include <filesystem>
#include <string>
#include <vector>

namespace ffd {

struct SceneObject {
    std::string mesh = "sphere";    ///< generator name, "letters", or "" when meshFile is set
    std::filesystem::path meshFile; ///< a mesh file (a scene's `file` or `model`, resolved)
    std::string letters = "ABCDEFGHIJKLMNOPQRSTUVWXYZ";
    int count = 1;
    float size = 1.0f;   ///< largest extent after normalisation, metres
    BodySettings body;   ///< lattice, material and motion (pose is set by the layout)
    bool placed = false; ///< at `position` (one object, unrotated, at rest), not by the layout
    Vec3 position;
    Vec3 scale{1, 1, 1}; ///< per axis, applied after the size's normalisation
};

struct SceneLayout {
    Vec3 origin{0, 1, 0};
    int columns[2] = {5, 5};
    float spacing = 1.2f;
    float jitter = 0.1f; ///< random offset of each cell, fraction of spacing
    bool randomRotation = true;
    Vec3 velocity;
    float velocityJitter = 0; ///< m/s, random per object
    uint32_t seed = 1;
};

/// A pin of a scene (its "pins"): which body, which of its points, where and how held.
struct ScenePin {
    int object = 0; ///< the body's index in the order the scene makes them
    enum class At : uint8_t { Particle, Vertex, Point } at = At::Point;
    uint32_t index = 0; ///< the particle or vertex
    Vec3 point;         ///< At::Point: world coordinates, where the body is as placed
    bool hasTarget = false;
    Vec3 target;
    PinSettings settings;
};

struct Scene {
    std::string name;
    std::string description;
    std::filesystem::path source; ///< the file it was read from (empty if parsed)
    WorldSettings world;
    std::vector<SceneObject> objects;
    SceneLayout layout;
    std::vector<ScenePin> pins;
    std::vector<Plane> planes; ///< plane colliders (World::addPlane), in order

    int objectCount() const;
};

/// Reads a scene: `nameOrPath` is a file (contains '/' or ends in .json) or the name of a
/// shipped scene (looked up in $FFDAABB_SCENES, then in the `scenes` folder of each data folder:
/// ffdaabb/data.h). Throws InputError naming the file, the field (as a path like
/// objects[0].lattice.cells), the value and what was expected.
Scene loadScene(const std::string& nameOrPath);

/// Parses scene JSON; `source` names it in errors and anchors relative mesh paths.
Scene parseScene(const std::string& json, const std::filesystem::path& source);

/// Names of the scenes found in those folders.
std::vector<std::string> sceneNames();

/// Sets the total object count, scaling each entry's count in proportion (at least 1 each);
/// placed entries (a "position") keep their one object.
void setObjectCount(Scene& scene, int count);

/// What a built scene holds.
struct SceneBuild {
    World world;
    std::vector<BodyId> bodies;
    size_t vertices = 0, triangles = 0, cells = 0, particles = 0, nodes = 0; ///< totals
    double buildMilliseconds = 0;
    std::vector<PinId> pins; ///< the scene's pins, in its order
};

/// The mesh of the index-th object of entry `object` (letters cycle), normalised to its size.
TriangleMesh sceneObjectMesh(const SceneObject& object, int index);

/// Generates (or loads) the meshes, builds the lattices (shared between identical objects)
/// and places every object by the layout.
SceneBuild buildScene(const Scene& scene);

} // namespace ffd
