// The simulation world: deformable bodies (meshes embedded in FFD lattices), their lattice
// dynamics, a floor, and collisions through the Enhanced FFD-AABB pipeline.
//
//   ffd::World world;                                  // default settings: 1/60 s frames
//   ffd::BodySettings s;  s.position = {0, 2, 0};
//   ffd::BodyId ball = world.addBody(ffd::icosphere(2), s);
//   for (int i = 0; i < 60; ++i) world.step();         // one frame per call
//   std::span<const ffd::Vec3> v = world.vertices(ball); // deformed mesh, no copy
//
// A World is not thread-safe for concurrent calls; step() itself may use worker threads
// (WorldSettings::threads) and gives bit-identical results for any thread count.
#pragma once

#include "ffdaabb/lattice.h"
#include "ffdaabb/math.h"
#include "ffdaabb/mesh.h"
#include "ffdaabb/profile.h"
#include "ffdaabb/tasks.h"

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

namespace ffd {

/// Which collision pipeline runs between objects (the floor is handled in every mode).
enum class CollisionMode : uint8_t {
    Enhanced, ///< bounding spheres -> spatial hash -> box pairs (Jeon, Choi, Hong 2012)
    Previous, ///< the same without phase 1: the paper's baseline (Jung, Hong, Choi 2011)
    Brute,    ///< every node near every box of every other object names the box pairs (oracle)
    None,     ///< objects pass through each other
};

/// The lattice dynamics of a body.
enum class DynamicsModel : uint8_t {
    ShapeMatching, ///< lattice shape matching (FastLSM)
    MassSpring,    ///< springs along lattice edges and diagonals (implicit Euler)
};

/// How a body moves (docs/ARCHITECTURE.md, "Colliders"). A static or kinematic body is a
/// regular body (a mesh in a lattice) that collides through the same pipeline as any other, as a
/// body of infinite mass: contacts never move it, the dynamics never step it, it never sleeps,
/// it makes no contacts with the floor, the planes or other static and kinematic bodies, and
/// forces, impulses and velocities given to it are ignored.
enum class BodyMotion : uint8_t {
    Dynamic,   ///< moved by the dynamics and the contacts
    Static,    ///< never moves (unless placed: translate, setParticles)
    Kinematic, ///< moved by the user (World::setKinematicTarget) over each step
};

const char* toString(CollisionMode mode);
const char* toString(DynamicsModel model);
const char* toString(BodyMotion motion);
/// Parses "dynamic", "static", "kinematic"; returns false for anything else.
bool parseBodyMotion(std::string_view text, BodyMotion& out);
/// Parses "enhanced", "previous", "brute", "none"; returns false for anything else.
bool parseCollisionMode(std::string_view text, CollisionMode& out);
bool parseDynamicsModel(std::string_view text, DynamicsModel& out);

/// A handle to a body: slot index + generation, so a handle to a removed body is detected.
struct BodyId {
    uint32_t index = UINT32_MAX;
    uint32_t generation = 0;

    bool isNull() const { return index == UINT32_MAX; }
    friend bool operator==(const BodyId&, const BodyId&) = default;
};

/// How a body is made and what it is made of. The lattice, the dynamics model and the region
/// half-width decide the shared (immutable) part; everything else is per body.
struct BodySettings {
    LatticeSettings lattice;
    DynamicsModel model = DynamicsModel::ShapeMatching;
    int regionHalfWidth = 1;    ///< shape matching region half-width w, 1..4 (larger = stiffer)
    float stiffness = 1.0f;     ///< shape matching alpha, (0, 1]
    float youngsModulus = 2e5f; ///< mass-spring: Pa, springs get k = E * rest length
    int springIterations = 20;  ///< mass-spring: conjugate-gradient iterations at most
    float density = 1000.0f;    ///< kg/m^3, used when mass is 0
    float mass = 0.0f;          ///< kg; 0 = density * volume (mesh volume, or lattice volume)
    float damping = 20.0f;      ///< 1/s, rate at which non-rigid motion is removed
    bool regionDamping = false; ///< shape matching: damp relative to each region's rigid motion
                                ///< (local wobble only) instead of the whole body's
    float friction = 0.5f;      ///< Coulomb coefficient
    float restitution = 0.0f;   ///< normal restitution, [0, 1]
    /// Share of an impact's approach speed removed through the body's rigid motion at once
    /// (0: only the contact particles are stopped and the body absorbs the impact by
    /// deforming; 1: the whole body stops like a rigid one). Contacts use the pair's mean.
    float contactRigidity = 0.5f;
    /// May fall asleep when it and every body it touches have been at rest for a while
    /// (WorldSettings::sleepSpeed); false for a body the user drives every frame.
    bool allowSleep = true;
    /// Dynamic, or a collider of infinite mass: Static or Kinematic (BodyMotion).
    BodyMotion motion = BodyMotion::Dynamic;
    Vec3 position;        ///< the mesh's origin is placed here
    Quat rotation;        ///< and the mesh rotated about it
    Vec3 velocity;        ///< initial velocity of the centre of mass, m/s
    Vec3 angularVelocity; ///< initial angular velocity about the centre of mass, rad/s
};

/// A static plane collider (World::addPlane): the half-space dot(normal, p) < offset is solid.
struct Plane {
    Vec3 normal{0, 1, 0}; ///< unit (addPlane normalises it), pointing out of the solid side
    float offset = 0;     ///< m: the plane is dot(normal, p) = offset
};

/// A handle to a plane: slot index + generation, like BodyId.
struct PlaneId {
    uint32_t index = UINT32_MAX;
    uint32_t generation = 0;

    bool isNull() const { return index == UINT32_MAX; }
    friend bool operator==(const PlaneId&, const PlaneId&) = default;
};

/// World-wide settings.
struct WorldSettings {
    float frameStep = 1.0f / 60.0f; ///< seconds of simulated time per step() call
    int substeps = 2;               ///< dynamics + collision passes per frame
    Vec3 gravity{0.0f, -9.81f, 0.0f};
    bool floor = true; ///< an infinite plane y = floorHeight, normal +y
    float floorHeight = 0.0f;
    CollisionMode mode = CollisionMode::Enhanced;
    float contactSkin = 0.05f; ///< contact margin as a fraction of the cell size
    int solverIterations = 4;  ///< Gauss-Seidel iterations over contacts per substep
    /// Worker threads of the world's own (0 = all cores): every stage of the step runs on them,
    /// with bit-identical results for any count (World::setTaskSystem: a job system instead).
    int threads = 1;
    bool meshUpdate = true;  ///< update embedded mesh vertices at the end of each frame
    int sweepThreshold = 64; ///< bodies above which sphere pairs use sort-and-sweep
    /// Bound (m/s) on how fast the rigid impact phase may push two bodies' rigid motions apart
    /// at a contact; 0: no bound. Particle velocity at a contact can be deformation (a dent being
    /// restored, a light body squeezed, bodies created overlapping): without the bound the phase
    /// turns it into rigid motion and throws such bodies from piles at tens of m/s. Lower bounds
    /// let boxes settle deeper into each other (more contacts: in the bench the spheres' frame
    /// costs 17 % more at 0.25 than at 1 m/s); higher ones let more throws and energy through
    /// (docs/ALGORITHM.md, section 5, "Separation bound").
    float maxSeparationSpeed = 0.25f;
    /// Push-out bound (m/s); 0: none, overlap is projected out at once. When set (about 1),
    /// overlap deeper than the contact skin is pushed out by at most the skin plus this speed
    /// times the substep per substep, by moving positions, without adding velocity: bodies
    /// created overlapping or in the floor leave at a few m/s instead of tens. Costs the
    /// alphabets scene about a third more time per frame (docs/ALGORITHM.md, "Push-out").
    float pushOutSpeed = 0.0f;
    /// Recovery speed (m/s) of bodies placed overlapping: a body added, translated or set inside
    /// another body or below the floor is pushed out of it by at most this speed, by moving
    /// positions, without adding velocity; bodies placed one inside the other (a centre of
    /// mass in the other's lattice cells) move apart as rigid wholes until their centres are a
    /// cell clear of each other. Only pairs that overlapped when placed are affected, until
    /// they are apart; 0: overlap is projected out at once (docs/ALGORITHM.md, "Overlap
    /// recovery").
    float overlapRecoverySpeed = 2.45f;
    /// Bound (m/s) on how fast the overlap recovery may move a body's centre, its velocity
    /// counted; 0: no bound. The recovery moves bodies by positions, on top of their velocity,
    /// and a body amid a heap has two pushes (a whole pair's and a recovering pair's), each up to
    /// overlapRecoverySpeed: without the bound, 200 bodies created at one spot moved their
    /// centres at over 6 m/s. A move is shortened so that the body's centre goes no faster than
    /// this, or than its velocity alone where that is faster (docs/ALGORITHM.md, "Overlap
    /// recovery").
    float overlapRecoveryMaxSpeed = 4.5f;
    /// Contacts on the bodies' rigid modes (experimental; 0: off). After the position update,
    /// before the particle-level projection, Gauss-Seidel sweeps move the bodies of each
    /// violated contact as rigid wholes, by up to this share of the violation their rigid
    /// motions made in the move, with static friction at the same level; velocities follow.
    /// A load then reaches the whole body in the substep it arrives instead of through the
    /// next substeps' shape matching: bodies stacked on dynamic bodies rest instead of
    /// buzzing, and a body is carried by friction as a rigid one would be. Not yet the
    /// default: it changes how balls roll and land (docs/LIMITS.md, known problem 5).
    float rigidProjection = 0.0f;
    /// Contacts with the floor and the plane colliders at the meshes' vertices (1) instead of
    /// the cell boxes' corners (0, the paper's). On its boxes' corners a ball stands on a flat
    /// patch, its lowest box's face, and slides down a slope instead of rolling; at the
    /// vertices the contacts move over the body's surface as it turns. Each box near the plane
    /// gives at most four vertices (the deepest, the one farthest from it, and the two spanning
    /// the largest triangles with them), plus every other vertex whose motion over the substep
    /// would take it more than a fifth of the contact skin below the plane. Experimental: not
    /// yet the default (docs/ALGORITHM.md, section 5, "Floor contacts at the vertices").
    int vertexFloorContacts = 0;
    /// Sleeping. A body whose particles' root-mean-square speed (its kinetic energy below
    /// M s^2 / 2) and whose particles' root-mean-square motion over each frame stay below this
    /// speed s (m/s) for sleepTime seconds falls asleep, together with every body it touches,
    /// once they all have been that quiet as long. A sleeping body does not move and costs
    /// nothing in the dynamics, node update, narrow phase and mesh update; awake bodies collide
    /// with it as with a body of infinite mass. It wakes, with the bodies it fell asleep with,
    /// when an awake body may reach it within the frame, when a force, impulse, velocity or
    /// pose is given to it or to a body it touches, when a body it touches is removed, and by
    /// World::setAwake. 0: bodies never sleep.
    float sleepSpeed = 0.05f;
    float sleepTime = 0.5f; ///< seconds a body and its neighbours must be quiet to fall asleep
};

/// Rest-pose statistics of a body's shared model.
struct BodyInfo {
    size_t vertices = 0, triangles = 0, cells = 0, surfaceCells = 0, particles = 0;
    float cellSize = 0;
    float mass = 0;
};

/// A contact of the last substep, as the collision pipeline found it and the response
/// resolved it (World::contacts).
struct ContactInfo {
    BodyId bodyA;      ///< the body whose embedded point is in contact
    BodyId bodyB;      ///< the other body; null for the floor
    Vec3 point;        ///< A's point at the end of the step, m
    Vec3 normal;       ///< unit, the direction A was pushed relative to B
    float depth = 0;   ///< penetration when found (0: found within the contact skin), m
    float impulse = 0; ///< normal impulse the response applied over the substep, N s
};

/// A handle to a pin (World::pinParticle and the like): slot index + generation, like BodyId,
/// so a handle to a pin that was removed (unpin, or its body removed) is detected.
struct PinId {
    uint32_t index = UINT32_MAX;
    uint32_t generation = 0;

    bool isNull() const { return index == UINT32_MAX; }
    friend bool operator==(const PinId&, const PinId&) = default;
};

/// How a pin holds its point (docs/ALGORITHM.md, "Pins").
struct PinSettings {
    /// Spring stiffness, N/m; 0: hard (the point is put on its target every substep, exactly up
    /// to what the contacts projected after it move it). A soft pin is an implicit spring
    /// (compliance 1/stiffness, XPBD), so its behaviour does not depend on the substep: a body
    /// of mass m hangs m g / stiffness below its target.
    float stiffness = 0.0f;
    /// Share, [0, 1], of each correction made through the body's rigid motion (translation and
    /// rotation of all its particles about its centre of mass) before the rest is made through
    /// the point's cell's 8 particles. 1: the body follows the pin as a whole and deforms only
    /// by its own dynamics (no tearing when dragged fast); 0: the pin pulls the point's cell
    /// alone and the body's stiffness drags the rest after it (a soft body sags and stretches
    /// under the pin).
    float rigidity = 1.0f;
    /// Rate (1/s) at which the body's motion relative to the pin's target is damped: its
    /// rotation about the target (a pendulum's friction at its pivot) and, for a soft pin, its
    /// bounce on the spring. 0: it swings on, losing only what the projection loses.
    float swingDamping = 0.5f;
    /// Speed (m/s) at which the pin follows its target at most; 0: at any speed. A target moved
    /// faster, or made to jump, is followed at this speed: the point lags behind it instead of
    /// whipping the body around (docs/LIMITS.md, "Pins", for the strain it bounds).
    float maxSpeed = 10.0f;
};

/// A pin as it is now (World::pin).
struct PinInfo {
    BodyId body;
    Vec3 target;   ///< where the pin holds its point, as last set, m
    Vec3 point;    ///< the pinned point of the body now, m
    Vec3 followed; ///< where the pin held its point in the last substep (maxSpeed), m
    Vec3 force;    ///< mean force the pin exerted on the body over the last step, N
    float lag = 0; ///< |point - target|, m
    PinSettings settings;
};

namespace detail {
struct WorldAccess;
}

class World {
public:
    explicit World(const WorldSettings& settings = {});
    ~World();
    World(World&&) noexcept;
    World& operator=(World&&) noexcept;
    World(const World&) = delete;
    World& operator=(const World&) = delete;

    /// Adds a body made from `mesh` (validated; InputError on a bad mesh or setting). Bodies
    /// made from an identical mesh with identical lattice/model settings share one lattice,
    /// embedding and region set. Spans obtained before are invalidated.
    BodyId addBody(const TriangleMesh& mesh, const BodySettings& settings = {});
    /// Removes a body; false for a stale or null handle. Spans obtained before are invalidated.
    bool removeBody(BodyId body);
    bool isValid(BodyId body) const;
    size_t bodyCount() const;
    /// Handles of all bodies in the order they were added.
    std::vector<BodyId> bodies() const;

    /// Advances one frame (settings().frameStep) in settings().substeps substeps.
    void step();

    /// Deformed mesh vertices (#V, metres), as of the end of the last step (or the initial pose).
    std::span<const Vec3> vertices(BodyId body) const;
    /// Triangles of the body's mesh (#T), shared with every body of the same model.
    std::span<const std::array<uint32_t, 3>> triangles(BodyId body) const;
    /// Lattice particle positions and velocities (#P).
    std::span<const Vec3> particles(BodyId body) const;
    std::span<const Vec3> velocities(BodyId body) const;
    /// Every body's entries in one array, body after body in World::bodies() order (the arrays
    /// the per-body spans above are ranges of): deformed vertices, particle positions and
    /// velocities. Invalidated like them when bodies come or go or a state is restored.
    std::span<const Vec3> allVertices() const;
    std::span<const Vec3> allParticles() const;
    std::span<const Vec3> allVelocities() const;
    /// Where a body's entries lie in allVertices() and in allParticles() / allVelocities().
    struct Ranges {
        uint32_t firstVertex = 0, vertexCount = 0;
        uint32_t firstParticle = 0, particleCount = 0;
    };
    Ranges ranges(BodyId body) const;
    /// FFD-AABB boundary nodes (#B * 8) as of the last node update.
    std::span<const Vec3> boxNodes(BodyId body) const;
    /// The body's lattice (rest pose, cell boxes, embedding).
    const Lattice& lattice(BodyId body) const;
    /// Bounds of the body's box nodes (contain the whole deformed mesh).
    Aabb bounds(BodyId body) const;
    /// Bounding sphere of the last sphere test (enhanced mode), centre and radius.
    void boundingSphere(BodyId body, Vec3& outCentre, float& outRadius) const;
    /// Mass-weighted centre and linear velocity of the body's particles.
    Vec3 centreOfMass(BodyId body) const;
    Vec3 linearVelocity(BodyId body) const;
    BodyInfo info(BodyId body) const;
    const BodySettings& settings(BodyId body) const;

    /// A force applied during the next step() (uniform acceleration force/mass), newtons.
    void applyForce(BodyId body, Vec3 force);
    /// An instantaneous change of momentum, spread over the particles by mass, N s.
    void applyImpulse(BodyId body, Vec3 impulse);
    /// A force on one particle during the next step() (for picking and dragging), newtons.
    void applyParticleForce(BodyId body, uint32_t particle, Vec3 force);
    /// Moves every particle by `offset` (a teleport: velocities are kept; vertices follow at once).
    void translate(BodyId body, Vec3 offset);
    void setVelocity(BodyId body, Vec3 velocity);
    /// Overwrites particle positions (and zeroes velocities when `resetVelocity`); #P entries.
    void setParticles(BodyId body, std::span<const Vec3> positions, bool resetVelocity = true);
    /// Recomputes vertices (and nodes) now, e.g. after setParticles or with meshUpdate off.
    void updateMesh(BodyId body);

    const WorldSettings& settings() const;
    /// Changes settings; takes effect at the next step(). InputError on invalid values.
    void setSettings(const WorldSettings& settings);
    void setMode(CollisionMode mode);
    /// Runs the step's parallel loops on `tasks` (a game engine's job system; ThreadPool)
    /// instead of the world's own threads, whatever settings().threads says; null: back to the
    /// world's own. The results are bit-identical either way (ffdaabb/tasks.h).
    void setTaskSystem(std::shared_ptr<TaskSystem> tasks);
    const std::shared_ptr<TaskSystem>& taskSystem() const;

    /// Pins (docs/ALGORITHM.md, "Pins"): an embedded point of a body held at a target, hard or
    /// with a stiffness, projected every substep after the position update and before the
    /// contacts. The point is a lattice particle, a mesh vertex, a point of the rest mesh or a
    /// point of the body where it is now, each as the trilinear blend of its cell's particles.
    /// InputError for a stale body, an index out of range, a non-finite vector or a setting
    /// out of range. A body's pins go when it is removed.
    PinId pinParticle(BodyId body, uint32_t particle, Vec3 target, const PinSettings& s = {});
    PinId pinVertex(BodyId body, uint32_t vertex, Vec3 target, const PinSettings& s = {});
    /// `restPoint` in the mesh's own coordinates (those addBody was given), held at `target`.
    PinId pinRestPoint(BodyId body, Vec3 restPoint, Vec3 target, const PinSettings& s = {});
    /// The body's point now at `point` (the nearest point of its lattice when outside it), held
    /// where it is.
    PinId pinPoint(BodyId body, Vec3 point, const PinSettings& s = {});
    /// Moves the pin's target: over the next step() the target goes from where it was to here
    /// in equal parts per substep. InputError for a stale pin or a non-finite target.
    void setPinTarget(PinId pin, Vec3 target);
    /// Changes how the pin holds (InputError for a stale pin or a setting out of range).
    void setPinSettings(PinId pin, const PinSettings& s);
    /// Removes a pin; false for a stale or null handle.
    bool unpin(PinId pin);
    bool isValid(PinId pin) const;
    /// The pin now (InputError for a stale pin).
    PinInfo pin(PinId pin) const;
    /// Handles of all pins, in the order they were made (the order they are projected).
    std::vector<PinId> pins() const;

    /// Object contacts, then floor contacts, of the last substep of the last step() (empty before
    /// the first step and in CollisionMode::None for objects), in an order set by the bodies'
    /// places alone (the solver's zones, then each point's node and box), the same for every
    /// collision mode and thread count. Clears `out`.
    void contacts(std::vector<ContactInfo>& out) const;
    /// Mass of one lattice particle, kg (its share of the body's mass).
    float particleMass(BodyId body, uint32_t particle) const;

    /// Colliders (docs/ARCHITECTURE.md, "Colliders"). Static and kinematic bodies are bodies
    /// with BodySettings::motion set. A kinematic body moves only where this sends it: over the
    /// next step() its particles go in a straight line, at constant velocity, from where they
    /// are to the pose (`position`, `rotation`: as BodySettings places the mesh), so contacts
    /// and friction see its motion (a moving platform carries what rests on it, a paddle
    /// pushes); after the step its velocities are 0 again. Bodies it may reach wake.
    /// InputError for a stale body, a body that is not kinematic or a non-finite pose.
    void setKinematicTarget(BodyId body, Vec3 position, Quat rotation = {});
    /// The same with every particle's target given (#P entries): a kinematic body that deforms.
    void setKinematicParticles(BodyId body, std::span<const Vec3> targets);
    /// Adds a static plane of any orientation (normal normalised; InputError for a zero or
    /// non-finite normal or offset). Its contacts are made like the floor's, after them.
    /// Sleeping bodies wake (as they do when the floor changes).
    PlaneId addPlane(Vec3 normal, float offset);
    /// Removes a plane; false for a stale or null handle. Sleeping bodies wake.
    bool removePlane(PlaneId plane);
    bool isValid(PlaneId plane) const;
    /// The planes, in the order they were added.
    std::vector<Plane> planes() const;

    /// Whether the body is awake (WorldSettings::sleepSpeed).
    bool isAwake(BodyId body) const;
    /// Wakes the body and every body it fell asleep with (true), or puts the body alone to
    /// sleep now (false; its velocities become zero). A body with allowSleep false stays awake.
    void setAwake(BodyId body, bool awake);
    /// Dynamic bodies awake now (static and kinematic bodies never sleep, and isAwake says
    /// true for them, but they are not counted here).
    size_t awakeCount() const;

    const Profile& profile() const;
    /// Frames stepped so far.
    uint64_t frame() const;
    /// FNV-1a hash of every body's particle positions and velocities, in body order.
    uint64_t stateHash() const;
    /// Total kinetic energy (J) of all particles.
    double kineticEnergy() const;

    /// Snapshots: the world's whole dynamic state as bytes (docs/ARCHITECTURE.md, "Snapshots"):
    /// every particle's position, velocity and pending force, the shape-matching warm starts,
    /// box nodes and bounds, mesh vertices, each body's pending force and initial pose, the
    /// frame counter, the body handles (slots, generations, free slots) and what the collision
    /// pipeline carries from one substep to the next (box-pair claims, the overlap recovery's
    /// pairs, which bodies were placed since the last step). Not the profile, nor the last
    /// step's contacts. The bytes name the build and the scene they come from.
    ///
    ///   std::vector<uint8_t> saved = world.saveState();   // at frame 100
    ///   ...                                                // rebuild the scene, or step on
    ///   world.restoreState(saved);                         // frame 100 again, bit for bit
    std::vector<uint8_t> saveState() const;
    /// Restores a state from saveState() into this world (to rewind) or into a world built
    /// from the same scene: the same world settings (threads aside) and the same bodies in the
    /// same order, each from the same mesh with the same lattice, model and material settings.
    /// Stepping on then gives, bit for bit, the states the saved world reached, at any thread
    /// count. Body handles become the saved world's (world.bodies() lists them); spans obtained
    /// before are invalidated; contacts() is empty and profile() zero until the next step.
    /// Throws InputError, naming what differs, for bytes that are not a state, truncated or
    /// corrupted, of another format version or build, or of another scene; the world is then
    /// left unchanged.
    void restoreState(std::span<const uint8_t> state);

private:
    friend struct detail::WorldAccess; // the library's tools and tests (src/world/world_data.h)
    struct State;
    std::unique_ptr<State> state_;
};

/// A numeric setting: one table behind validate(), the scene reader, the command line's flags
/// and help (`ffdaabb settings`) and the documentation's table of settings, so that all of them
/// accept, name and describe the same values.
struct SettingRange {
    const char* field;    ///< the C++ member: "frameStep" (validate names "world.frameStep")
    const char* key;      ///< the scene file's key: "frame_step" (in "world" or "material")
    double min, max;      ///< inclusive
    const char* expected; ///< the range in words, as errors say it: "seconds, 0 < frame_step <= 1"
    bool integer;         ///< an int setting (else float)
    const char* unit;     ///< "s", "m", "m/s", "kg", ...; "" for a count or a ratio
    const char* doc;      ///< what it sets, one line
};

/// The setting's value in a default-constructed WorldSettings or BodySettings.
double settingDefault(const SettingRange& setting);

/// The numeric WorldSettings, in declaration order.
std::span<const SettingRange> worldSettingRanges();
/// The numeric BodySettings (a scene's "material"), in declaration order.
std::span<const SettingRange> bodySettingRanges();
/// The range of a setting by its C++ member or scene key, among world then body settings; null
/// when none has that name.
const SettingRange* findSettingRange(std::string_view name);

/// Throws InputError (naming the field) when a setting is out of range.
void validate(const WorldSettings& settings);
void validate(const BodySettings& settings);
void validate(const PinSettings& settings);

} // namespace ffd
