// The World: bodies, stepping (without the GIL), views of its memory, forces, pins, colliders,
// sleeping, queries, snapshots and the profile.
#include "bindings.h"

#include "ffdaabb/error.h"
#include "ffdaabb/queries.h"
#include "ffdaabb/scene.h"
#include "interpenetration.h"
#include "runner.h"

#include <Python.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace ffd::python {

namespace {

// The World wrapper of a Python World object, checked idle (no step() in another thread).
PyWorld& idle(const py::object& self) {
    PyWorld& w = self.cast<PyWorld&>();
    w.checkIdle();
    return w;
}

py::object handleOrNone(BodyId id) {
    return id.isNull() ? py::none() : py::cast(id);
}

template <class Id>
void bindHandle(py::module_& m, const char* name, const char* doc) {
    py::class_<Id>(m, name, doc)
        .def_readonly("index", &Id::index, "slot index")
        .def_readonly("generation", &Id::generation, "the slot's generation when it was made")
        .def("__eq__",
             [](const Id& a, const py::object& b) {
                 return py::isinstance<Id>(b) && a == b.cast<Id>();
             })
        .def("__hash__",
             [](const Id& a) { return py::hash(py::make_tuple(a.index, a.generation)); })
        .def("__repr__", [name](const Id& a) {
            return std::string(name) + "(index=" + std::to_string(a.index) +
                   ", generation=" + std::to_string(a.generation) + ")";
        });
}

std::vector<Vec3> pointsFrom(const py::handle& source, const char* argument, size_t expected) {
    auto a = rows3(source, argument);
    if (size_t(a.shape(0)) != expected)
        badArgument(argument, "expected " + std::to_string(expected) +
                                  " rows (one per particle), got " + std::to_string(a.shape(0)));
    return points(a);
}

py::dict profileDict(const World& world) {
    const Profile& p = world.profile();
    py::dict stages, columns;
    for (const StageInfo& s : stageTable()) stages[s.key] = p.ms(s.stage);
    stages["total"] = p.total;
    for (const TableColumnInfo& c : tableColumns()) columns[c.key] = p.ms(c.column);
    columns["total"] = p.total;
    py::dict d;
    d["frame"] = world.frame();
    d["stage_ms"] = stages;
    d["table1_ms"] = columns;
    d["candidate_pairs"] = p.candidatePairs;
    d["potential_pairs"] = p.potentialPairs;
    d["box_pairs"] = p.boxPairs;
    d["contact_box_pairs"] = p.contactBoxPairs;
    d["contacts"] = p.contacts;
    d["floor_contacts"] = p.floorContacts;
    d["overlap_pairs"] = p.overlapPairs;
    d["whole_pairs"] = p.wholePairs;
    d["sleeping_bodies"] = p.sleepingBodies;
    d["max_contact_depth"] = p.maxContactDepth;
    return d;
}

py::object rayHit(const RayHit& h) {
    return support().attr("RayHit")(h.body, h.triangle, h.barycentric, h.distance, h.point,
                                    h.normal);
}

Aabb boxFrom(Vec3 lo, Vec3 hi) {
    return Aabb{lo, hi};
}

py::dict pinDict(const PinInfo& p) {
    py::dict d;
    d["body"] = p.body;
    d["target"] = p.target;
    d["point"] = p.point;
    d["followed"] = p.followed;
    d["force"] = p.force;
    d["lag"] = p.lag;
    d["settings"] = p.settings;
    return d;
}

// Steps n frames without the GIL; between frames, takes it back briefly to let Ctrl-C through.
void stepFrames(PyWorld& w, int n) {
    if (n < 0) badArgument("n", "value " + std::to_string(n) + " is out of range (expected >= 0)");
    w.beginStep();
    struct Done {
        PyWorld& w;
        ~Done() { w.stepping = false; }
    } done{w};
    for (int i = 0; i < n; ++i) {
        {
            py::gil_scoped_release released;
            w.world.step();
        }
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    }
}

} // namespace

void bindWorld(py::module_& m) {
    bindHandle<BodyId>(m, "BodyId", "A handle to a body (World.add_body); stale once removed.");
    bindHandle<PinId>(m, "PinId", "A handle to a pin (World.pin_*); stale once unpinned.");
    bindHandle<PlaneId>(m, "PlaneId", "A handle to a plane collider (World.add_plane).");

    py::class_<World::Ranges>(m, "Ranges",
                              "Where a body's entries lie in World.all_vertices() and "
                              "all_particles() / all_velocities().")
        .def_readonly("first_vertex", &World::Ranges::firstVertex)
        .def_readonly("vertex_count", &World::Ranges::vertexCount)
        .def_readonly("first_particle", &World::Ranges::firstParticle)
        .def_readonly("particle_count", &World::Ranges::particleCount)
        .def_property_readonly(
            "vertices",
            [](const World::Ranges& r) {
                return py::slice(r.firstVertex, r.firstVertex + r.vertexCount, 1);
            },
            "the body's rows of all_vertices(), as a slice")
        .def_property_readonly(
            "particles",
            [](const World::Ranges& r) {
                return py::slice(r.firstParticle, r.firstParticle + r.particleCount, 1);
            },
            "the body's rows of all_particles() and all_velocities(), as a slice")
        .def("__repr__", [](const World::Ranges& r) {
            return "Ranges(first_vertex=" + std::to_string(r.firstVertex) +
                   ", vertex_count=" + std::to_string(r.vertexCount) +
                   ", first_particle=" + std::to_string(r.firstParticle) +
                   ", particle_count=" + std::to_string(r.particleCount) + ")";
        });

    py::class_<PyWorld> cls(m, "World", "A simulation world (see the module's documentation).");
    cls.def(py::init([](std::optional<WorldSettings> settings, const py::kwargs& kw) {
                const WorldSettings ws =
                    withKeywords(settings.value_or(WorldSettings{}), kw, "World");
                validate(ws);
                return std::make_unique<PyWorld>(World(ws));
            }),
            py::arg("settings") = py::none(),
            "A world of these settings (WorldSettings), with any field overridden by keyword: "
            "World(substeps=4, threads=0).");
    cls.def_static(
        "from_scene",
        [](const py::object& sceneName, std::optional<int> objects, std::optional<long long> seed,
           std::optional<std::string> mode, std::optional<int> threads) {
            cli::SceneOverrides o{objects, mode, threads, seed};
            const std::string scene = pathText(sceneName);
            SceneBuild build = [&] {
                py::gil_scoped_release released;
                return buildScene(sceneFor(scene, o));
            }();
            return std::make_unique<PyWorld>(std::move(build.world));
        },
        py::arg("scene"), py::arg("objects") = py::none(), py::arg("seed") = py::none(),
        py::arg("mode") = py::none(), py::arg("threads") = py::none(),
        "A world built from a scene: a shipped scene's name (ffdaabb.scene_names()) or a JSON "
        "file's path, with the command line's overrides (--objects, --seed, --mode, "
        "--threads). Its bodies are world.bodies(), in the scene's order; its pins "
        "world.pins().");

    cls.def_property(
        "settings", [](const py::object& self) { return idle(self).world.settings(); },
        [](const py::object& self, const WorldSettings& s) { idle(self).world.setSettings(s); },
        "The world's settings (a copy: assign a changed copy back, it takes effect at the next "
        "step()).");
    cls.def(
        "add_body",
        [](const py::object& self, const py::object& vertices, const py::object& triangles,
           std::optional<BodySettings> settings, const py::kwargs& kw) {
            PyWorld& w = idle(self);
            const BodySettings s = withKeywords(settings.value_or(BodySettings{}), kw, "add_body");
            const TriangleMesh mesh = meshFromArrays(vertices, triangles);
            const BodyId id = [&] {
                py::gil_scoped_release released;
                return w.world.addBody(mesh, s);
            }();
            w.relayout();
            return id;
        },
        py::arg("vertices"), py::arg("triangles"), py::arg("settings") = py::none(),
        "Adds a body made from a mesh (vertices (V, 3), triangles (T, 3), or a Mesh unpacked: "
        "add_body(*mesh)) with these BodySettings, any field overridden by keyword "
        "(position=(0, 2, 0)). Views taken before become stale.");
    cls.def(
        "remove_body",
        [](const py::object& self, BodyId id) {
            PyWorld& w = idle(self);
            const bool removed = w.world.removeBody(id);
            if (removed) w.relayout();
            return removed;
        },
        py::arg("body"),
        "Removes a body; False for a stale handle. Views taken before become stale.");
    cls.def(
        "is_valid", [](const py::object& self, BodyId id) { return idle(self).world.isValid(id); },
        py::arg("body"));
    cls.def(
        "is_valid", [](const py::object& self, PinId id) { return idle(self).world.isValid(id); },
        py::arg("pin"));
    cls.def(
        "is_valid", [](const py::object& self, PlaneId id) { return idle(self).world.isValid(id); },
        py::arg("plane"), "Whether a body, pin or plane handle names something alive.");
    cls.def_property_readonly(
        "body_count", [](const py::object& self) { return idle(self).world.bodyCount(); },
        "The number of bodies (len(world)).");
    cls.def("__len__", [](const py::object& self) { return idle(self).world.bodyCount(); });
    cls.def(
        "bodies", [](const py::object& self) { return idle(self).world.bodies(); },
        "Handles of all bodies, in the order they were added.");

    cls.def(
        "step", [](const py::object& self, int n) { stepFrames(self.cast<PyWorld&>(), n); },
        py::arg("n") = 1,
        "Advances n frames (settings.frame_step each). Releases the GIL while it steps: other "
        "Python threads run meanwhile (but may not call this World).");

    // Views.
    cls.def(
        "vertices",
        [](const py::object& self, BodyId id) {
            PyWorld& w = idle(self);
            const auto s = w.world.vertices(id);
            return view(self, w, &s.data()->x, s.size());
        },
        py::arg("body"),
        "The body's deformed mesh vertices: a read-only float32 View (V, 3) of the world's "
        "memory, no copy; it sees later steps.");
    cls.def(
        "particles",
        [](const py::object& self, BodyId id) {
            PyWorld& w = idle(self);
            const auto s = w.world.particles(id);
            return view(self, w, &s.data()->x, s.size());
        },
        py::arg("body"), "The body's lattice particle positions: a View (P, 3), no copy.");
    cls.def(
        "velocities",
        [](const py::object& self, BodyId id) {
            PyWorld& w = idle(self);
            const auto s = w.world.velocities(id);
            return view(self, w, &s.data()->x, s.size());
        },
        py::arg("body"), "The body's lattice particle velocities: a View (P, 3), no copy.");
    cls.def(
        "triangles",
        [](const py::object& self, BodyId id) {
            PyWorld& w = idle(self);
            const auto s = w.world.triangles(id);
            return view(self, w, s.data()->data(), s.size());
        },
        py::arg("body"), "The body's triangles: a uint32 View (T, 3), shared by its model.");
    cls.def(
        "box_nodes",
        [](const py::object& self, BodyId id) {
            PyWorld& w = idle(self);
            const auto s = w.world.boxNodes(id);
            return view(self, w, &s.data()->x, s.size());
        },
        py::arg("body"), "The body's FFD-AABB box nodes (8 per cell box): a View (B*8, 3).");
    cls.def(
        "all_vertices",
        [](const py::object& self) {
            PyWorld& w = idle(self);
            const auto s = w.world.allVertices();
            return view(self, w, s.empty() ? nullptr : &s.data()->x, s.size());
        },
        "Every body's vertices in one View, body after body (ranges(body).vertices).");
    cls.def(
        "all_particles",
        [](const py::object& self) {
            PyWorld& w = idle(self);
            const auto s = w.world.allParticles();
            return view(self, w, s.empty() ? nullptr : &s.data()->x, s.size());
        },
        "Every body's particles in one View, body after body (ranges(body).particles).");
    cls.def(
        "all_velocities",
        [](const py::object& self) {
            PyWorld& w = idle(self);
            const auto s = w.world.allVelocities();
            return view(self, w, s.empty() ? nullptr : &s.data()->x, s.size());
        },
        "Every body's particle velocities in one View, body after body.");
    cls.def(
        "ranges", [](const py::object& self, BodyId id) { return idle(self).world.ranges(id); },
        py::arg("body"), "Where the body's rows lie in the all_* arrays.");

    // State of a body.
    cls.def(
        "centre_of_mass",
        [](const py::object& self, BodyId id) { return idle(self).world.centreOfMass(id); },
        py::arg("body"),
        "The mass-weighted centre of the body's lattice particles (its centre of mass as the "
        "dynamics sees it: the lattice covers the mesh's cells, so it may differ from the mesh's "
        "own centre by part of a cell).");
    cls.def(
        "linear_velocity",
        [](const py::object& self, BodyId id) { return idle(self).world.linearVelocity(id); },
        py::arg("body"), "The mass-weighted mean velocity of the body's particles, m/s.");
    cls.def(
        "bounds",
        [](const py::object& self, BodyId id) {
            const Aabb b = idle(self).world.bounds(id);
            return py::make_tuple(b.lo, b.hi);
        },
        py::arg("body"),
        "The body's bounds as (lo, hi): those of its box nodes, which contain its deformed mesh.");
    cls.def(
        "info",
        [](const py::object& self, BodyId id) {
            const BodyInfo i = idle(self).world.info(id);
            py::dict d;
            d["vertices"] = i.vertices;
            d["triangles"] = i.triangles;
            d["cells"] = i.cells;
            d["surface_cells"] = i.surfaceCells;
            d["particles"] = i.particles;
            d["cell_size"] = i.cellSize;
            d["mass"] = i.mass;
            return d;
        },
        py::arg("body"),
        "The body's model: vertices, triangles, cells, particles, cell size, mass.");
    cls.def(
        "body_settings",
        [](const py::object& self, BodyId id) { return idle(self).world.settings(id); },
        py::arg("body"), "The BodySettings the body was made with (a copy).");
    cls.def(
        "particle_mass",
        [](const py::object& self, BodyId id, uint32_t p) {
            return idle(self).world.particleMass(id, p);
        },
        py::arg("body"), py::arg("particle"),
        "The mass of one lattice particle (its share of the body's mass), kg.");

    // Forces and placing.
    cls.def(
        "apply_force",
        [](const py::object& self, BodyId id, Vec3 f) { idle(self).world.applyForce(id, f); },
        py::arg("body"), py::arg("force"), "A force (N) applied during the next step().");
    cls.def(
        "apply_impulse",
        [](const py::object& self, BodyId id, Vec3 j) { idle(self).world.applyImpulse(id, j); },
        py::arg("body"), py::arg("impulse"), "An instantaneous change of momentum, N s.");
    cls.def(
        "apply_particle_force",
        [](const py::object& self, BodyId id, uint32_t p, Vec3 f) {
            idle(self).world.applyParticleForce(id, p, f);
        },
        py::arg("body"), py::arg("particle"), py::arg("force"),
        "A force (N) on one particle during the next step() (for dragging a point).");
    cls.def(
        "translate",
        [](const py::object& self, BodyId id, Vec3 offset) {
            idle(self).world.translate(id, offset);
        },
        py::arg("body"), py::arg("offset"),
        "Moves every particle of the body by `offset` (a teleport: velocities unchanged).");
    cls.def(
        "set_velocity",
        [](const py::object& self, BodyId id, Vec3 v) { idle(self).world.setVelocity(id, v); },
        py::arg("body"), py::arg("velocity"),
        "Sets every particle of the body to this velocity, m/s.");
    cls.def(
        "set_particles",
        [](const py::object& self, BodyId id, const py::object& positions, bool resetVelocity) {
            PyWorld& w = idle(self);
            const std::vector<Vec3> p =
                pointsFrom(positions, "positions", w.world.particles(id).size());
            w.world.setParticles(id, p, resetVelocity);
        },
        py::arg("body"), py::arg("positions"), py::arg("reset_velocity") = true,
        "Overwrites the body's particle positions ((P, 3)); velocities zeroed unless "
        "reset_velocity is False.");
    cls.def(
        "update_mesh", [](const py::object& self, BodyId id) { idle(self).world.updateMesh(id); },
        py::arg("body"),
        "Recomputes the body's vertices and box nodes now (after set_particles, or with "
        "mesh_update off).");
    cls.def(
        "set_mode",
        [](const py::object& self, const std::string& mode) {
            CollisionMode cm;
            if (!parseCollisionMode(mode, cm))
                throw InputError("mode", "unknown mode \"" + mode +
                                             "\" (expected enhanced, previous, brute or none)");
            idle(self).world.setMode(cm);
        },
        py::arg("mode"), "Changes the collision pipeline: enhanced, previous, brute or none.");

    // Pins.
    auto pinArgs = [](std::optional<PinSettings> s) { return s.value_or(PinSettings{}); };
    cls.def(
        "pin_particle",
        [pinArgs](const py::object& self, BodyId id, uint32_t particle, Vec3 target,
                  std::optional<PinSettings> s) {
            return idle(self).world.pinParticle(id, particle, target, pinArgs(s));
        },
        py::arg("body"), py::arg("particle"), py::arg("target"), py::arg("settings") = py::none(),
        "Pins a lattice particle at `target` (hard, or soft with settings.stiffness); returns its "
        "PinId.");
    cls.def(
        "pin_vertex",
        [pinArgs](const py::object& self, BodyId id, uint32_t vertex, Vec3 target,
                  std::optional<PinSettings> s) {
            return idle(self).world.pinVertex(id, vertex, target, pinArgs(s));
        },
        py::arg("body"), py::arg("vertex"), py::arg("target"), py::arg("settings") = py::none(),
        "Pins a mesh vertex at `target`.");
    cls.def(
        "pin_rest_point",
        [pinArgs](const py::object& self, BodyId id, Vec3 rest, Vec3 target,
                  std::optional<PinSettings> s) {
            return idle(self).world.pinRestPoint(id, rest, target, pinArgs(s));
        },
        py::arg("body"), py::arg("rest_point"), py::arg("target"), py::arg("settings") = py::none(),
        "Pins the point of the rest mesh `rest_point` (the mesh's own coordinates, as add_body was "
        "given) at `target`.");
    cls.def(
        "pin_point",
        [pinArgs](const py::object& self, BodyId id, Vec3 point, std::optional<PinSettings> s) {
            return idle(self).world.pinPoint(id, point, pinArgs(s));
        },
        py::arg("body"), py::arg("point"), py::arg("settings") = py::none(),
        "Pins the body's point now at `point` where it is.");
    cls.def(
        "set_pin_target",
        [](const py::object& self, PinId pin, Vec3 target) {
            idle(self).world.setPinTarget(pin, target);
        },
        py::arg("pin"), py::arg("target"),
        "Moves the pin's target over the next step() (in equal parts per substep).");
    cls.def(
        "set_pin_settings",
        [](const py::object& self, PinId pin, const PinSettings& s) {
            idle(self).world.setPinSettings(pin, s);
        },
        py::arg("pin"), py::arg("settings"), "Changes how the pin holds (PinSettings).");
    cls.def(
        "unpin", [](const py::object& self, PinId pin) { return idle(self).world.unpin(pin); },
        py::arg("pin"), "Removes a pin; False for a stale handle.");
    cls.def(
        "pin", [](const py::object& self, PinId pin) { return pinDict(idle(self).world.pin(pin)); },
        py::arg("pin"),
        "The pin now: a dict of body, target, point, followed, force (N), lag (m), settings.");
    cls.def(
        "pins", [](const py::object& self) { return idle(self).world.pins(); },
        "Handles of all pins, in the order they were made (the order they are projected).");

    // Colliders.
    cls.def(
        "set_kinematic_target",
        [](const py::object& self, BodyId id, Vec3 position, Quat rotation) {
            idle(self).world.setKinematicTarget(id, position, rotation);
        },
        py::arg("body"), py::arg("position"), py::arg("rotation") = Quat{},
        "Moves a kinematic body to this pose over the next step().");
    cls.def(
        "set_kinematic_particles",
        [](const py::object& self, BodyId id, const py::object& targets) {
            PyWorld& w = idle(self);
            const std::vector<Vec3> p =
                pointsFrom(targets, "targets", w.world.particles(id).size());
            w.world.setKinematicParticles(id, p);
        },
        py::arg("body"), py::arg("targets"),
        "Moves a kinematic body's particles to these targets ((P, 3)) over the next step(): a "
        "kinematic body that deforms.");
    cls.def(
        "add_plane",
        [](const py::object& self, Vec3 normal, float offset) {
            return idle(self).world.addPlane(normal, offset);
        },
        py::arg("normal"), py::arg("offset"),
        "A static plane collider: the half-space dot(normal, p) < offset is solid.");
    cls.def(
        "remove_plane",
        [](const py::object& self, PlaneId id) { return idle(self).world.removePlane(id); },
        py::arg("plane"), "Removes a plane; False for a stale handle.");
    cls.def(
        "planes",
        [](const py::object& self) {
            py::list out;
            for (const Plane& p : idle(self).world.planes())
                out.append(py::make_tuple(p.normal, p.offset));
            return out;
        },
        "The planes as (normal, offset), in the order added.");

    // Sleeping.
    cls.def(
        "is_awake", [](const py::object& self, BodyId id) { return idle(self).world.isAwake(id); },
        py::arg("body"), "Whether the body is awake (static and kinematic bodies always are).");
    cls.def(
        "set_awake",
        [](const py::object& self, BodyId id, bool awake) { idle(self).world.setAwake(id, awake); },
        py::arg("body"), py::arg("awake"),
        "Wakes the body and the bodies it fell asleep with (True), or puts it alone to sleep now "
        "(False).");
    cls.def_property_readonly(
        "awake_count", [](const py::object& self) { return idle(self).world.awakeCount(); },
        "Dynamic bodies awake now.");

    // Contacts and queries.
    cls.def(
        "contacts",
        [](const py::object& self) {
            std::vector<ContactInfo> cs;
            idle(self).world.contacts(cs);
            py::object make = support().attr("Contact");
            py::list out;
            for (const ContactInfo& c : cs)
                out.append(
                    make(c.bodyA, handleOrNone(c.bodyB), c.point, c.normal, c.depth, c.impulse));
            return out;
        },
        "The last substep's contacts (Contact tuples; body_b None for the floor).");
    cls.def(
        "raycast",
        [](const py::object& self, Vec3 origin, Vec3 direction, float maxDistance,
           const std::vector<BodyId>& ignore) -> py::object {
            const auto hit = raycast(idle(self).world, origin, direction, maxDistance, ignore);
            return hit ? rayHit(*hit) : py::none();
        },
        py::arg("origin"), py::arg("direction"),
        py::arg("max_distance") = std::numeric_limits<float>::infinity(),
        py::arg("ignore") = std::vector<BodyId>{},
        "The closest RayHit on any deformed mesh, or None.");
    cls.def(
        "raycast_all",
        [](const py::object& self, Vec3 origin, Vec3 direction, float maxDistance) {
            std::vector<RayHit> hits;
            raycastAll(idle(self).world, origin, direction, maxDistance, hits);
            py::list out;
            for (const RayHit& h : hits) out.append(rayHit(h));
            return out;
        },
        py::arg("origin"), py::arg("direction"),
        py::arg("max_distance") = std::numeric_limits<float>::infinity(),
        "Every RayHit along the ray, nearest first.");
    cls.def(
        "body_overlaps",
        [](const py::object& self, BodyId id, Vec3 lo, Vec3 hi) {
            return bodyOverlaps(idle(self).world, id, boxFrom(lo, hi));
        },
        py::arg("body"), py::arg("lo"), py::arg("hi"),
        "Whether the body's deformed mesh meets the box [lo, hi].");
    cls.def(
        "bodies_overlapping",
        [](const py::object& self, Vec3 lo, Vec3 hi) {
            std::vector<BodyId> out;
            bodiesOverlapping(idle(self).world, boxFrom(lo, hi), out);
            return out;
        },
        py::arg("lo"), py::arg("hi"), "The bodies whose deformed meshes meet the box.");
    cls.def(
        "contact_pairs",
        [](const py::object& self) {
            py::object make = support().attr("ContactPair");
            py::list out;
            for (const ContactPair& p : contactPairs(idle(self).world))
                out.append(make(p.bodyA, handleOrNone(p.bodyB), p.normalImpulse, p.impulse,
                                p.contactCount));
            return out;
        },
        "Every pair that had contacts in the last step (ContactPair; body_b None: the floor).");
    cls.def(
        "touching_bodies",
        [](const py::object& self, BodyId id) {
            std::vector<BodyContact> cs;
            touchingBodies(idle(self).world, id, cs);
            py::object make = support().attr("BodyContact");
            py::list out;
            for (const BodyContact& c : cs)
                out.append(make(handleOrNone(c.other), c.normalImpulse, c.impulse, c.contactCount));
            return out;
        },
        py::arg("body"),
        "The body's partners in the last step (BodyContact; other None: the floor).");
    cls.def(
        "contact_events",
        [](const py::object& self) {
            const ContactEvents e = contactEvents(idle(self).world);
            auto list = [](std::span<const ContactEvent> events) {
                py::list out;
                for (const ContactEvent& c : events)
                    out.append(py::make_tuple(c.bodyA, handleOrNone(c.bodyB)));
                return out;
            };
            py::dict d;
            d["begin"] = list(e.begin);
            d["end"] = list(e.end);
            return d;
        },
        "The last step's events: {'begin': [(a, b)], 'end': [(a, b)]} (b None: the floor).");

    // Snapshots, hashes, profile.
    cls.def(
        "save_state",
        [](const py::object& self) {
            const std::vector<uint8_t> bytes = idle(self).world.saveState();
            return py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size());
        },
        "The world's whole dynamic state as bytes (restore_state takes them back).");
    cls.def(
        "restore_state",
        [](const py::object& self, const py::buffer& state) {
            PyWorld& w = idle(self);
            const py::buffer_info info = state.request();
            if (info.ndim != 1 || info.itemsize != 1)
                badArgument("state", "expected bytes from World.save_state()");
            w.world.restoreState({static_cast<const uint8_t*>(info.ptr), size_t(info.size)});
            w.relayout();
        },
        py::arg("state"),
        "Restores a state from save_state() (this world's scene); views taken before become "
        "stale. InputError naming what differs for another scene or damaged bytes.");
    cls.def_property_readonly(
        "state_hash", [](const py::object& self) { return idle(self).world.stateHash(); },
        "FNV-1a hash of every particle's position and velocity (the command line prints it "
        "as 16 hex digits: f'{world.state_hash:016x}').");
    cls.def_property_readonly(
        "frame", [](const py::object& self) { return idle(self).world.frame(); },
        "Frames stepped so far (a restored state's frame after restore_state).");
    cls.def(
        "kinetic_energy", [](const py::object& self) { return idle(self).world.kineticEnergy(); },
        "J");
    cls.def_property_readonly(
        "profile", [](const py::object& self) { return profileDict(idle(self).world); },
        "The last frame's stage timings and counters, under the command line's JSON names: "
        "stage_ms, table1_ms (each with 'total'), candidate_pairs, potential_pairs, box_pairs, "
        "contact_box_pairs, contacts, floor_contacts, overlap_pairs, whole_pairs, "
        "sleeping_bodies, max_contact_depth.");
    cls.def(
        "interpenetration",
        [](const py::object& self, std::optional<float> referenceSize) {
            PyWorld& w = idle(self);
            std::vector<bench::MeshView> views;
            bench::InterpenetrationSettings measure;
            float largest = 0;
            const std::vector<BodyId> ids = w.world.bodies();
            for (BodyId id : ids) {
                views.push_back({w.world.vertices(id), w.world.triangles(id)});
                const Aabb b = w.world.bounds(id);
                const Vec3 e = b.hi - b.lo;
                largest = std::max(largest, std::max(e.x, std::max(e.y, e.z)));
            }
            if (referenceSize && !(*referenceSize > 0))
                badArgument("reference_size", "expected a size > 0 in metres");
            measure.referenceSize = referenceSize.value_or(largest > 0 ? largest : 1.0f);
            measure.floorHeight = w.world.settings().floorHeight;
            bench::Interpenetration p;
            {
                py::gil_scoped_release released;
                p = bench::measureInterpenetration(views, measure);
            }
            py::dict d;
            d["reference_size_m"] = measure.referenceSize;
            d["max_depth_relative"] = p.maxDepthRelative;
            d["max_depth_m"] = p.maxDepth;
            d["inside_vertices"] = p.insideVertices;
            d["deep_vertices"] = p.deepVertices;
            d["body_pairs"] = p.bodyPairs;
            d["below_floor_m"] = p.belowFloor;
            if (p.deepestBody < 0) {
                d["deepest_vertex"] = py::none();
            } else {
                py::dict deepest;
                deepest["body"] = ids[size_t(p.deepestBody)];
                deepest["vertex"] = p.deepestVertex;
                deepest["inside"] = ids[size_t(p.deepestInside)];
                d["deepest_vertex"] = deepest;
            }
            return d;
        },
        py::arg("reference_size") = py::none(),
        "The meshes' interpenetration now, by winding number (the measure `ffdaabb run` "
        "reports): the deepest vertex inside another body (metres, and relative to "
        "reference_size: default the largest body's extent), which vertex that is "
        "(deepest_vertex: body, vertex index, the body it is inside; None when none is "
        "inside), the vertices inside, those deeper than 1 %, the body pairs, and how far below "
        "the floor.");
}

} // namespace ffd::python
