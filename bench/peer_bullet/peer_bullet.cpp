// ffdaabb_peer_bullet: the peer benchmark. Runs one of our scenes (by default the paper's 100
// spheres) in Bullet's soft-body world (btSoftRigidDynamicsWorld) with cluster (CL_SS) and
// vertex-face (VF_SS) soft-soft collisions, and in our World, single-threaded, in one process:
// milliseconds per frame (mean and median over the same frames, from frame 0 and after the
// warm-up) and one interpenetration measure (bench/common) for all of them.
//
// The layout, meshes and masses come from ffd::buildScene, so Bullet gets exactly our posed
// 162-vertex spheres, our masses and initial velocities. What Bullet's material is made of,
// and why, is in BulletMaterial below.
#include "interpenetration.h"
#include "sample_stats.h"

#include "ffdaabb/error.h"
#include "ffdaabb/scene.h"
#include "ffdaabb/world.h"

#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <LinearMath/btThreads.h>
#include <btBulletDynamicsCommon.h>

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace ffd::bench {
namespace {

using Clock = std::chrono::steady_clock;

// --- what both engines start from -----------------------------------------------------------

/// One body as buildScene placed it.
struct BodyStart {
    std::vector<Vec3> vertices; ///< #V, posed (world), metres
    std::span<const std::array<uint32_t, 3>> triangles;
    float mass = 0; ///< kg, ours (density * mesh volume)
    Vec3 velocity, angularVelocity;
};

/// The scene, built once: our world (not yet stepped) and every body's start.
struct SceneStart {
    Scene scene;
    SceneBuild build;
    std::vector<BodyStart> bodies;
    float referenceSize = 1; ///< the largest object size (the sphere diameter), metres
};

SceneStart startScene(const std::string& name, int objects, int threads) {
    SceneStart s;
    s.scene = loadScene(name);
    if (objects > 0) setObjectCount(s.scene, objects);
    s.scene.world.threads = threads;
    s.build = buildScene(s.scene);
    float largest = 0;
    for (const SceneObject& o : s.scene.objects) largest = std::max(largest, o.size);
    s.referenceSize = largest > 0 ? largest : 1.0f;
    for (BodyId id : s.build.bodies) {
        const World& w = s.build.world;
        const std::span<const Vec3> v = w.vertices(id);
        s.bodies.push_back({std::vector<Vec3>(v.begin(), v.end()), w.triangles(id), w.info(id).mass,
                            w.settings(id).velocity, w.settings(id).angularVelocity});
    }
    return s;
}

// --- Bullet -----------------------------------------------------------------------------------

enum class BulletCollisions { Clusters, VertexFace };

const char* toString(BulletCollisions c) {
    return c == BulletCollisions::Clusters ? "CL_SS" : "VF_SS";
}

/// Bullet's soft-body set-up for the scene's 1 m, ~506 kg spheres, each the 162-vertex surface
/// alone (Bullet's legacy soft bodies have no interior). Starting points are Bullet's SoftDemo
/// (Init_Pressure, Init_Volume, Init_ClusterCollide2); every change is measured on the
/// 100-sphere scene (300 frames, bench/peer_bullet/README.md has the sweep):
/// - The shell holds the shape: edge links at kLST 0.9 plus distance-2 bending links, solved
///   with 4 position iterations, keep every sphere within 1 % of its volume and the flattest
///   at 94-98 % of its height (ours: 0.3 % and 98 %). Fewer iterations let it cave in:
///   at 2, VF_SS spheres lose 8 % of their volume; at Bullet's default 1, CL_SS spheres turn
///   inside out.
/// - No pressure or volume term (kPR = kVC = 0). Pressure strong enough to carry the pile on
///   its own (kPR ~ 1e5) is not momentum-neutral on this mesh: a lone sphere bounces off
///   nothing in mid-air and rests 10 cm above the floor. SoftDemo's kPR 2500, or kVC up to
///   1e6, move the volume and height figures by 0.02 at most, so they would only add cost.
/// - Margins: Bullet's default 0.25 m would hold 1 m balls half a metre apart. VF_SS catches a
///   node only within the margin of a face, so falling spheres pass into each other at small
///   margins (max depth 0.36 m at 0.02, 0.15 m at 0.03, none at 0.05); clusters (CL_SS) keep
///   them apart at 0.02 already. Each mode gets the smallest of those that holds, and the
///   measured gap between neighbours shows what the margin costs.
/// - kKHR 1 (node vs static floor hardness): the default 0.1 lets nodes sink 3.5 cm into it.
/// - kDP 0.001 as SoftDemo's pressure ball: kDP damps every velocity, free fall included.
/// - kDF 0.5 like our friction; the floor's friction is 1 since Bullet multiplies the two.
/// - 16 clusters (k-means, as Init_ClusterCollide2): 8 and 32 give the same figures (and cost
///   a little less and more); one cluster per triangle (k = 0) blows up.
struct BulletMaterial {
    float pressure = 0.0f;            // kPR
    float volumeStiffness = 0.0f;     // kVC, with setPose(true, false) for the rest volume
    float poseMatching = 0.0f;        // kMT, with setPose(false, true)
    float linearStiffness = 0.9f;     // kLST of the edge and bending links
    int bendingDistance = 2;          // generateBendingConstraints(2)
    float damping = 0.001f;           // kDP
    float friction = 0.5f;            // kDF
    float kineticHardness = 1.0f;     // kKHR
    int positionIterations = 4;       // piterations
    float clusterMargin = 0.02f;      // collision margin with CL_SS, metres
    float vertexFaceMargin = 0.05f;   // collision margin with VF_SS, metres
    int clusters = 16;                // CL_SS: generateClusters(k)
    float softSoftHardness = 1.0f;    // kSSHR_CL, as Init_ClusterCollide2
    float softSoftSplit = 0.0f;       // kSS_SPLT_CL, as Init_ClusterCollide2
    float groundHalfThickness = 1.0f; // the floor box: y in [-2, 0]
    float groundHalfWidth = 100.0f;
};

/// A Bullet soft-rigid world holding one soft body per scene body and a static floor.
class BulletScene {
public:
    BulletScene(const SceneStart& start, BulletCollisions collisions, const BulletMaterial& mat,
                int substeps)
        : substeps_(substeps), frameStep_(start.scene.world.frameStep) {
        config_ = std::make_unique<btSoftBodyRigidBodyCollisionConfiguration>();
        dispatcher_ = std::make_unique<btCollisionDispatcher>(config_.get());
        broadphase_ = std::make_unique<btDbvtBroadphase>();
        solver_ = std::make_unique<btSequentialImpulseConstraintSolver>();
        // A null soft-body solver makes the world own a btDefaultSoftBodySolver (the CPU one).
        world_ = std::make_unique<btSoftRigidDynamicsWorld>(dispatcher_.get(), broadphase_.get(),
                                                            solver_.get(), config_.get(), nullptr);
        const Vec3 g = start.scene.world.gravity;
        world_->setGravity(btVector3(g.x, g.y, g.z));
        btSoftBodyWorldInfo& info = world_->getWorldInfo();
        info.m_gravity = btVector3(g.x, g.y, g.z);
        info.m_sparsesdf.Initialize();

        // The floor is a static box, not a btStaticPlaneShape: Bullet's soft-rigid contacts
        // (SDF_RS through btSparseSdf, CL_RS through GJK) only work against convex shapes; a
        // plane gives a zero distance everywhere to the SDF and is cast to convex by CL_RS.
        const float h = mat.groundHalfThickness, w = mat.groundHalfWidth;
        groundShape_ = std::make_unique<btBoxShape>(btVector3(w, h, w));
        btTransform at;
        at.setIdentity();
        at.setOrigin(btVector3(0, start.scene.world.floorHeight - h, 0));
        groundMotion_ = std::make_unique<btDefaultMotionState>(at);
        ground_ = std::make_unique<btRigidBody>(
            btRigidBody::btRigidBodyConstructionInfo(0, groundMotion_.get(), groundShape_.get()));
        // Soft-rigid friction is kDF x the rigid body's friction: 1 keeps it at kDF.
        ground_->setFriction(1.0f);
        world_->addRigidBody(ground_.get());

        for (const BodyStart& b : start.bodies) addBody(b, collisions, mat);
        vertices_.resize(bodies_.size());
        for (size_t i = 0; i < bodies_.size(); ++i)
            vertices_[i].resize(size_t(bodies_[i]->m_nodes.size()));
        readBack();
    }

    ~BulletScene() {
        for (btSoftBody* b : bodies_) {
            world_->removeSoftBody(b);
            delete b;
        }
        world_->removeRigidBody(ground_.get());
    }
    BulletScene(const BulletScene&) = delete;
    BulletScene& operator=(const BulletScene&) = delete;

    /// One frame as a Bullet user steps it: fixed substeps of frameStep / substeps (exactly
    /// half of 1/60 in float, so the accumulator never drifts into 1 or 3 substeps), then the
    /// sparse SDF's garbage collection as SoftDemo does each frame. Returns the substeps taken.
    int step() {
        const btScalar fixed = btScalar(frameStep_) / btScalar(substeps_);
        const int taken = world_->stepSimulation(btScalar(frameStep_), substeps_ + 1, fixed);
        world_->getWorldInfo().m_sparsesdf.GarbageCollect();
        return taken;
    }

    void readBack() {
        for (size_t i = 0; i < bodies_.size(); ++i) {
            const btSoftBody::tNodeArray& nodes = bodies_[i]->m_nodes;
            for (int k = 0; k < nodes.size(); ++k) {
                const btVector3& x = nodes[k].m_x;
                vertices_[i][size_t(k)] = {float(x.x()), float(x.y()), float(x.z())};
            }
        }
    }

    const std::vector<std::vector<Vec3>>& vertices() const { return vertices_; }
    int activeBodies() const {
        return int(std::count_if(bodies_.begin(), bodies_.end(),
                                 [](const btSoftBody* b) { return b->isActive(); }));
    }
    size_t links() const { return size_t(bodies_.empty() ? 0 : bodies_[0]->m_links.size()); }
    size_t clusters() const { return size_t(bodies_.empty() ? 0 : bodies_[0]->m_clusters.size()); }

private:
    void addBody(const BodyStart& b, BulletCollisions collisions, const BulletMaterial& mat) {
        std::vector<btScalar> xyz;
        for (const Vec3& v : b.vertices) xyz.insert(xyz.end(), {v.x, v.y, v.z});
        std::vector<int> indices;
        for (const auto& t : b.triangles)
            indices.insert(indices.end(), {int(t[0]), int(t[1]), int(t[2])});
        // Node i is vertex i and face j is triangle j, so our triangles index Bullet's nodes.
        btSoftBody* psb = btSoftBodyHelpers::CreateFromTriMesh(
            world_->getWorldInfo(), xyz.data(), indices.data(), int(b.triangles.size()));
        psb->m_materials[0]->m_kLST = mat.linearStiffness;
        psb->generateBendingConstraints(mat.bendingDistance, psb->m_materials[0]);
        psb->randomizeConstraints();
        psb->m_cfg.kPR = mat.pressure;
        psb->m_cfg.kVC = mat.volumeStiffness;
        psb->m_cfg.kMT = mat.poseMatching;
        psb->m_cfg.kKHR = mat.kineticHardness;
        psb->m_cfg.kDP = mat.damping;
        psb->m_cfg.kDF = mat.friction;
        psb->m_cfg.piterations = mat.positionIterations;
        psb->getCollisionShape()->setMargin(
            collisions == BulletCollisions::Clusters ? mat.clusterMargin : mat.vertexFaceMargin);
        psb->setTotalMass(b.mass, true); // node masses by surface area, as SoftDemo
        if (mat.volumeStiffness > 0 || mat.poseMatching > 0)
            psb->setPose(mat.volumeStiffness > 0, mat.poseMatching > 0);
        if (collisions == BulletCollisions::Clusters) {
            psb->m_cfg.collisions = btSoftBody::fCollision::CL_SS | btSoftBody::fCollision::CL_RS;
            psb->m_cfg.kSSHR_CL = mat.softSoftHardness;
            psb->m_cfg.kSS_SPLT_CL = mat.softSoftSplit;
            psb->generateClusters(mat.clusters);
        } else {
            psb->m_cfg.collisions = btSoftBody::fCollision::VF_SS | btSoftBody::fCollision::SDF_RS;
        }
        // Initial motion: the centre's velocity plus the spin about the centre of mass.
        btVector3 com(0, 0, 0);
        btScalar total = 0;
        for (int k = 0; k < psb->m_nodes.size(); ++k) {
            const btScalar m = psb->getMass(k);
            com += psb->m_nodes[k].m_x * m;
            total += m;
        }
        com /= total;
        const btVector3 v(b.velocity.x, b.velocity.y, b.velocity.z);
        const btVector3 w(b.angularVelocity.x, b.angularVelocity.y, b.angularVelocity.z);
        for (int k = 0; k < psb->m_nodes.size(); ++k)
            psb->m_nodes[k].m_v = v + w.cross(psb->m_nodes[k].m_x - com);
        world_->addSoftBody(psb);
        bodies_.push_back(psb);
    }

    int substeps_;
    float frameStep_;
    // Declaration order is destruction order reversed: the world goes before its parts.
    std::unique_ptr<btSoftBodyRigidBodyCollisionConfiguration> config_;
    std::unique_ptr<btCollisionDispatcher> dispatcher_;
    std::unique_ptr<btDbvtBroadphase> broadphase_;
    std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
    std::unique_ptr<btBoxShape> groundShape_;
    std::unique_ptr<btDefaultMotionState> groundMotion_;
    std::unique_ptr<btRigidBody> ground_;
    std::unique_ptr<btSoftRigidDynamicsWorld> world_;
    std::vector<btSoftBody*> bodies_;
    std::vector<std::vector<Vec3>> vertices_;
};

// --- one run, either engine -------------------------------------------------------------------

/// Milliseconds per frame over a run of frames (bench/common/sample_stats.h: the true median).
struct FrameStats {
    int frames = 0;
    double mean = 0, median = 0, p90 = 0, min = 0, max = 0;
};

FrameStats statsOf(std::span<const double> ms) {
    FrameStats s;
    if (ms.empty()) return s;
    const std::vector<double> v(ms.begin(), ms.end());
    s.frames = int(v.size());
    s.mean = mean(v);
    s.median = median(v);
    s.p90 = quantile(v, 0.9);
    s.min = *std::min_element(v.begin(), v.end());
    s.max = *std::max_element(v.begin(), v.end());
    return s;
}

/// a / b, or 0 when b is not positive (a skipped run).
double ratio(double a, double b) {
    return b > 0 ? a / b : 0.0;
}

/// Shape figures of the final state: is a ball still a ball?
struct ShapeFigures {
    double meanCentreY = 0;     ///< mean of the bodies' vertex centroids' y, metres
    double minHeightRatio = 0;  ///< smallest (vertical extent / reference size) over bodies
    double meanVolumeRatio = 0; ///< mean enclosed volume / volume at the start
    double minVolumeRatio = 0;
};

double enclosedVolume(std::span<const Vec3> v, std::span<const std::array<uint32_t, 3>> t) {
    double sum = 0;
    for (const auto& f : t) {
        const Vec3 a = v[f[0]], b = v[f[1]], c = v[f[2]];
        sum += double(dot(a, cross(b, c)));
    }
    return sum / 6.0;
}

struct RunResult {
    std::string engine;
    std::string collisions; ///< "enhanced" for ours, CL_SS / VF_SS for Bullet
    double buildMs = 0;
    int warmup = 0;
    std::vector<double> frameMs; ///< every frame's time, from frame 0 (warm-up included)
    FrameStats fromStart;        ///< over every frame, from frame 0
    FrameStats afterWarmup;      ///< over the frames after the first `warmup`
    Interpenetration final;
    Interpenetration sampled;  ///< worst over the samples (every sampleEvery frames, and final)
    double measureSeconds = 0; ///< spent measuring (untimed)
    int samples = 0;
    bool finiteEveryFrame = true;
    int firstNonFiniteFrame = -1;
    double substepsPerFrame = 0;
    ShapeFigures shape;
    int activeBodies = -1; ///< Bullet: bodies still awake at the end
    double wallSeconds = 0;
};

struct RunSettings {
    // Every frame by default: impacts in the first second leave transient overlaps a few
    // frames long that sampling every 10 frames misses (VF_SS: 2.5 cm deep, unseen at 10).
    // Measuring is outside the timed region; it moved the medians by less than the noise.
    int frames = 600, warmup = 60, sampleEvery = 1;
    bool trace = false; ///< print the lowest and mean vertex height every frame
    InterpenetrationSettings measure;
};

/// Steps `stepFrame` (one frame including reading the vertices back) warmup + frames times,
/// timing every frame (summed from frame 0 and after the warm-up), measuring every sampleEvery
/// frames (from the first, warm-up included: the falling layers meet in the first second) and
/// after the last.
template <typename StepFrame, typename Vertices>
void runFrames(RunResult& r, const RunSettings& rs, const SceneStart& start, StepFrame&& stepFrame,
               Vertices&& vertices) {
    const auto wallStart = Clock::now();
    auto measure = [&]() {
        const auto m0 = Clock::now();
        const auto& all = vertices();
        std::vector<MeshView> views;
        for (size_t i = 0; i < all.size(); ++i)
            views.push_back({all[i], start.bodies[i].triangles});
        const Interpenetration p = measureInterpenetration(views, rs.measure);
        r.measureSeconds += std::chrono::duration<double>(Clock::now() - m0).count();
        return p;
    };
    auto allFinite = [&]() {
        for (const auto& body : vertices())
            for (const Vec3& v : body)
                if (!isFinite(v)) return false;
        return true;
    };
    long substeps = 0;
    for (int f = 0; f < rs.warmup + rs.frames; ++f) {
        const auto t0 = Clock::now();
        const int taken = stepFrame();
        const auto t1 = Clock::now();
        substeps += taken;
        if (rs.trace) {
            double lowest = 1e30, centre = 0;
            size_t count = 0;
            for (const auto& body : vertices())
                for (const Vec3& v : body)
                    lowest = std::min(lowest, double(v.y)), centre += v.y, ++count;
            const Interpenetration p = measure();
            fmt::print("trace {} {} frame {} lowest_y {:.4f} mean_y {:.4f} near {} min_gap "
                       "{:.4f} max_depth {:.4f}\n",
                       r.engine, r.collisions, f, lowest,
                       centre / double(std::max<size_t>(1, count)), p.nearBodies, p.minGap,
                       p.maxDepth);
        }
        r.frameMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        if (r.finiteEveryFrame && !allFinite()) {
            r.finiteEveryFrame = false;
            r.firstNonFiniteFrame = f;
        }
        if (rs.sampleEvery > 0 && (f + 1) % rs.sampleEvery == 0 && f + 1 != rs.warmup + rs.frames) {
            keepWorst(r.sampled, measure());
            ++r.samples;
        }
    }
    r.final = measure();
    keepWorst(r.sampled, r.final);
    ++r.samples;
    r.warmup = rs.warmup;
    r.fromStart = statsOf(r.frameMs);
    r.afterWarmup = statsOf(std::span<const double>(r.frameMs).subspan(size_t(rs.warmup)));
    r.substepsPerFrame = double(substeps) / double(std::max(1, rs.warmup + rs.frames));

    ShapeFigures& s = r.shape;
    const auto& all = vertices();
    s.minHeightRatio = 1e30;
    s.minVolumeRatio = 1e30;
    for (size_t i = 0; i < all.size(); ++i) {
        Aabb box;
        Vec3 centroid;
        for (const Vec3& v : all[i]) box.add(v), centroid += v;
        centroid = centroid / float(std::max<size_t>(1, all[i].size()));
        s.meanCentreY += double(centroid.y);
        s.minHeightRatio =
            std::min(s.minHeightRatio, double(box.extent().y) / double(rs.measure.referenceSize));
        const double v0 = enclosedVolume(start.bodies[i].vertices, start.bodies[i].triangles);
        const double ratio = enclosedVolume(all[i], start.bodies[i].triangles) / v0;
        s.meanVolumeRatio += ratio;
        s.minVolumeRatio = std::min(s.minVolumeRatio, ratio);
    }
    const double n = double(std::max<size_t>(1, all.size()));
    s.meanCentreY /= n;
    s.meanVolumeRatio /= n;
    r.wallSeconds = std::chrono::duration<double>(Clock::now() - wallStart).count();
}

RunResult runOurs(SceneStart& start, const RunSettings& rs) {
    RunResult r;
    r.engine = "ffdaabb";
    r.collisions = toString(start.scene.world.mode);
    r.buildMs = start.build.buildMilliseconds;
    World& world = start.build.world;
    const std::vector<BodyId>& ids = start.build.bodies;
    std::vector<std::vector<Vec3>> buffers(ids.size());
    for (size_t i = 0; i < ids.size(); ++i) buffers[i].resize(world.vertices(ids[i]).size());
    auto readBack = [&]() {
        for (size_t i = 0; i < ids.size(); ++i) {
            const std::span<const Vec3> v = world.vertices(ids[i]);
            std::copy(v.begin(), v.end(), buffers[i].begin());
        }
    };
    readBack();
    runFrames(
        r, rs, start,
        [&]() {
            world.step();
            readBack(); // the same copy out as Bullet's, so both pay for handing vertices over
            return world.settings().substeps;
        },
        [&]() -> const std::vector<std::vector<Vec3>>& { return buffers; });
    return r;
}

RunResult runBullet(const SceneStart& start, const RunSettings& rs, BulletCollisions collisions,
                    const BulletMaterial& mat, int substeps, size_t& outLinks,
                    size_t& outClusters) {
    RunResult r;
    r.engine = "bullet";
    r.collisions = toString(collisions);
    const auto t0 = Clock::now();
    BulletScene scene(start, collisions, mat, substeps);
    r.buildMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    outLinks = scene.links();
    outClusters = scene.clusters();
    runFrames(
        r, rs, start,
        [&]() {
            const int taken = scene.step();
            scene.readBack();
            return taken;
        },
        [&]() -> const std::vector<std::vector<Vec3>>& { return scene.vertices(); });
    r.activeBodies = scene.activeBodies();
    return r;
}

// --- report -----------------------------------------------------------------------------------

nlohmann::json toJson(const Interpenetration& p) {
    return {{"body_pairs", p.bodyPairs},
            {"inside_vertices", p.insideVertices},
            {"deep_vertices", p.deepVertices},
            {"max_depth_m", p.maxDepth},
            {"mean_depth_m", p.meanDepth},
            {"max_depth_relative", p.maxDepthRelative},
            {"lowest_y_m", p.lowestY},
            {"below_floor_m", p.belowFloor},
            {"below_floor_vertices", p.belowFloorVertices},
            {"near_bodies", p.nearBodies},
            {"median_gap_m", p.medianGap},
            {"mean_gap_m", p.meanGap},
            {"min_gap_m", p.minGap},
            {"finite", p.finite}};
}

nlohmann::json toJson(const FrameStats& s) {
    return {{"frames", s.frames}, {"mean", s.mean}, {"median", s.median},
            {"p90", s.p90},       {"min", s.min},   {"max", s.max}};
}

nlohmann::json toJson(const RunResult& r, const RunResult& ours) {
    const auto warmup = std::span<const double>(r.frameMs).first(size_t(r.warmup));
    const auto timed = std::span<const double>(r.frameMs).subspan(size_t(r.warmup));
    nlohmann::json j = {
        {"engine", r.engine},
        {"collisions", r.collisions},
        {"build_ms", r.buildMs},
        // After the warm-up (the frames after --warmup), as before; then from frame 0.
        {"ms_per_frame", toJson(r.afterWarmup)},
        {"mean_ratio_to_ffdaabb", ratio(r.afterWarmup.mean, ours.afterWarmup.mean)},
        {"median_ratio_to_ffdaabb", ratio(r.afterWarmup.median, ours.afterWarmup.median)},
        {"ms_per_frame_from_frame_0", toJson(r.fromStart)},
        {"mean_ratio_to_ffdaabb_from_frame_0", ratio(r.fromStart.mean, ours.fromStart.mean)},
        {"median_ratio_to_ffdaabb_from_frame_0", ratio(r.fromStart.median, ours.fromStart.median)},
        {"substeps_per_frame", r.substepsPerFrame},
        {"finite_every_frame", r.finiteEveryFrame},
        {"first_non_finite_frame", r.firstNonFiniteFrame},
        {"interpenetration_final", toJson(r.final)},
        {"interpenetration_sampled_max", toJson(r.sampled)},
        {"samples", r.samples},
        {"shape",
         {{"mean_centre_y_m", r.shape.meanCentreY},
          {"min_height_ratio", r.shape.minHeightRatio},
          {"mean_volume_ratio", r.shape.meanVolumeRatio},
          {"min_volume_ratio", r.shape.minVolumeRatio}}},
        {"wall_seconds", r.wallSeconds},
        {"measure_seconds", r.measureSeconds},
        {"warmup_frame_ms", std::vector<double>(warmup.begin(), warmup.end())},
        {"frame_ms", std::vector<double>(timed.begin(), timed.end())}};
    if (r.activeBodies >= 0) j["active_bodies_at_end"] = r.activeBodies;
    return j;
}

std::string cpuModel() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) {
            const size_t colon = line.find(':');
            return colon == std::string::npos ? line : line.substr(colon + 2);
        }
    return "unknown";
}

// Time per frame over the same frames for every engine, from frame 0 and after the warm-up:
// mean first, then median and p90, and each engine's mean and median over ours.
void printTimes(const std::vector<RunResult>& runs, const RunSettings& rs) {
    const RunResult& ours = runs.front();
    const std::string all = fmt::format("from frame 0 ({} frames)", rs.warmup + rs.frames);
    const std::string after =
        fmt::format("after the {} warm-up frames ({} frames)", rs.warmup, rs.frames);
    fmt::print("\ntime per frame, ms (x ours: the engine's mean or median / ours)\n");
    fmt::print("{:<17} | {:^44} | {:^44}\n", "", all, after);
    fmt::print("{:<17}", "engine");
    for (int part = 0; part < 2; ++part)
        fmt::print(" | {:>8} {:>8} {:>8} {:>8} {:>8}", "mean", "median", "p90", "x mean",
                   "x median");
    fmt::print("\n");
    auto ratioText = [](double x) { return x > 0 ? fmt::format("{:.2f}", x) : std::string("-"); };
    for (const RunResult& r : runs) {
        if (r.frameMs.empty()) continue;
        fmt::print("{:<17}", r.engine + " " + r.collisions);
        for (const auto& [stats, base] : {std::pair{&r.fromStart, &ours.fromStart},
                                          std::pair{&r.afterWarmup, &ours.afterWarmup}})
            fmt::print(" | {:>8.3f} {:>8.3f} {:>8.3f} {:>8} {:>8}", stats->mean, stats->median,
                       stats->p90, ratioText(ratio(stats->mean, base->mean)),
                       ratioText(ratio(stats->median, base->median)));
        fmt::print("\n");
    }
}

void printInterpenetration(const std::vector<RunResult>& runs) {
    fmt::print("\n{:<17} | {:>5} {:>6} {:>5} {:>9} {:>7} {:>9} {:>8} {:>7} {:>6} {:>6}\n", "engine",
               "pairs", "inside", "deep", "max depth", "/diam", "mean dep", "lowest y", "gap",
               "vol", "finite");
    fmt::print("{:<17} | {:>5} {:>6} {:>5} {:>9} {:>7} {:>9} {:>8} {:>7} {:>6} {:>6}\n", "", "",
               "verts", "verts", "m", "", "m", "m", "m", "min", "");
    for (const RunResult& r : runs) {
        if (r.frameMs.empty()) continue;
        for (int which = 0; which < 2; ++which) {
            const Interpenetration& p = which == 0 ? r.final : r.sampled;
            const std::string name =
                which == 0 ? r.engine + " " + r.collisions : "  (worst sample)";
            fmt::print("{:<17} | {:>5} {:>6} {:>5} {:>9.4f} {:>7.4f} {:>9.4f} {:>8.4f} {:>7} "
                       "{:>6} {:>6}\n",
                       name, p.bodyPairs, p.insideVertices, p.deepVertices, p.maxDepth,
                       p.maxDepthRelative, p.meanDepth, p.lowestY,
                       p.nearBodies == 0
                           ? std::string("-")
                           : fmt::format("{:.4f}", which == 0 ? p.medianGap : p.minGap),
                       which == 0 ? fmt::format("{:.3f}", r.shape.minVolumeRatio) : "",
                       which == 0 ? (r.finiteEveryFrame ? "yes" : "NO") : "");
        }
    }
}

int run(int argc, char** argv) {
    std::string sceneName = "spheres", mode = "both", jsonPath;
    int objects = 0, threads = 1, substeps = 2;
    RunSettings rs;
    BulletMaterial mat;
    bool skipOurs = false;

    CLI::App app{"ffdaabb_peer_bullet: one of our scenes in Bullet's soft-body world and in "
                 "ours, side by side: ms per frame and interpenetration"};
    app.add_option("--scene", sceneName, "scene name or .json file")->capture_default_str();
    app.add_option("--objects", objects, "object count (0 = the scene's)")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--frames", rs.frames, "frames after the warm-up")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    app.add_option("--warmup", rs.warmup,
                   "warm-up frames: timed, and left out of the after-warm-up figures")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    app.add_option("--sample-every", rs.sampleEvery,
                   "measure interpenetration every N frames, warm-up included (0: final only)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    app.add_option("--mode", mode, "Bullet soft-soft collisions")
        ->check(CLI::IsMember({"CL_SS", "VF_SS", "both"}))
        ->capture_default_str();
    app.add_option("--threads", threads, "our worker threads (Bullet always runs sequentially)")
        ->capture_default_str()
        ->check(CLI::Range(1, 256));
    app.add_option("--substeps", substeps, "Bullet fixed substeps per frame (ours: the scene's)")
        ->capture_default_str()
        ->check(CLI::Range(1, 64));
    app.add_option("--clusters", mat.clusters, "CL_SS: clusters per body (generateClusters k)")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    app.add_option("--pressure", mat.pressure, "Bullet kPR")->capture_default_str();
    app.add_option("--volume", mat.volumeStiffness, "Bullet kVC")->capture_default_str();
    app.add_option("--pose", mat.poseMatching, "Bullet kMT")->capture_default_str();
    app.add_option("--stiffness", mat.linearStiffness, "Bullet kLST")->capture_default_str();
    app.add_option("--damping", mat.damping, "Bullet kDP")->capture_default_str();
    app.add_option("--piterations", mat.positionIterations, "Bullet position iterations")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    app.add_option("--cl-margin", mat.clusterMargin, "Bullet collision margin with CL_SS, metres")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    app.add_option("--vf-margin", mat.vertexFaceMargin,
                   "Bullet collision margin with VF_SS, metres")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    app.add_flag("--trace", rs.trace, "print the lowest and mean vertex height every frame");
    app.add_flag("--skip-ours", skipOurs, "run Bullet only (ratios are then 0)");
    app.add_option("--json", jsonPath, "write the results here");
    CLI11_PARSE(app, argc, argv);

    // Bullet's soft-body world is sequential by construction; pinning the task scheduler makes
    // sure nothing in LinearMath's btParallelFor fans out either.
    btSetTaskScheduler(btGetSequentialTaskScheduler());
    const int bulletThreads = btGetTaskScheduler()->getNumThreads();

    SceneStart start = startScene(sceneName, objects, threads);
    rs.measure.referenceSize = start.referenceSize;
    rs.measure.floorHeight = start.scene.world.floorHeight;
    fmt::print("scene {}: {} bodies, {} vertices, {} triangles; {} frames, timed from frame 0 "
               "and after the {} warm-up frames; our threads {}, Bullet scheduler '{}' with {} "
               "thread(s)\n",
               start.scene.name, start.bodies.size(), start.build.vertices, start.build.triangles,
               rs.warmup + rs.frames, rs.warmup, threads, btGetTaskScheduler()->getName(),
               bulletThreads);

    std::vector<RunResult> runs;
    if (!skipOurs) {
        fmt::print("running ffdaabb ({})...\n", toString(start.scene.world.mode));
        std::fflush(stdout);
        runs.push_back(runOurs(start, rs));
    } else {
        runs.push_back(RunResult{});
        runs.back().engine = "ffdaabb";
        runs.back().collisions = "skipped";
    }
    size_t links = 0, clusters = 0;
    std::vector<BulletCollisions> modes;
    if (mode != "VF_SS") modes.push_back(BulletCollisions::Clusters);
    if (mode != "CL_SS") modes.push_back(BulletCollisions::VertexFace);
    for (BulletCollisions c : modes) {
        fmt::print("running Bullet {}...\n", toString(c));
        std::fflush(stdout);
        size_t l = 0, k = 0;
        runs.push_back(runBullet(start, rs, c, mat, substeps, l, k));
        links = l;
        if (c == BulletCollisions::Clusters) clusters = k;
    }
    printTimes(runs, rs);
    printInterpenetration(runs);
    fmt::print("\ndepths: distance of a vertex inside another body to that body's surface; "
               "'deep': over {:.0f} % of the {:.2f} m diameter; worst sample: field-wise worst "
               "over every {} frames (warm-up included) and the end; gap: median over bodies of "
               "the distance to the nearest neighbour within {:.0f} % of the diameter (0 when "
               "they interpenetrate), on the worst-sample row the closest approach of any two; "
               "vol min: smallest enclosed volume / initial.\n",
               rs.measure.deepFraction * 100, rs.measure.referenceSize, rs.sampleEvery,
               rs.measure.gapFraction * 100);

    if (!jsonPath.empty()) {
        const WorldSettings& ws = start.scene.world;
        nlohmann::json j;
        j["machine"] = {{"cpu", cpuModel()},
                        {"hardware_threads", std::thread::hardware_concurrency()}};
        j["scene"] = {{"name", start.scene.name},          {"bodies", start.bodies.size()},
                      {"vertices", start.build.vertices},  {"triangles", start.build.triangles},
                      {"diameter_m", start.referenceSize}, {"frame_step_s", ws.frameStep}};
        j["frames"] = rs.frames;
        j["warmup"] = rs.warmup;
        j["sample_every"] = rs.sampleEvery;
        j["ffdaabb"] = {{"threads", threads},
                        {"mode", toString(ws.mode)},
                        {"substeps", ws.substeps},
                        {"solver_iterations", ws.solverIterations}};
        j["bullet"] = {
            {"version", btGetVersion()},
            {"double_precision", sizeof(btScalar) == sizeof(double)},
            {"world", "btSoftRigidDynamicsWorld + btDefaultSoftBodySolver, btDbvtBroadphase, "
                      "btSequentialImpulseConstraintSolver"},
            {"task_scheduler", btGetTaskScheduler()->getName()},
            {"threads", bulletThreads},
            {"step", fmt::format("stepSimulation({}, {}, {} / {})", ws.frameStep, substeps + 1,
                                 ws.frameStep, substeps)},
            {"substeps", substeps},
            {"floor", fmt::format("static btBoxShape, half extents ({0}, {1}, {0}), top at y = "
                                  "{2}, friction 1",
                                  mat.groundHalfWidth, mat.groundHalfThickness, ws.floorHeight)},
            {"kPR", mat.pressure},
            {"kLST", mat.linearStiffness},
            {"bending_distance", mat.bendingDistance},
            {"kDP", mat.damping},
            {"kDF", mat.friction},
            {"piterations", mat.positionIterations},
            {"margin_m", {{"CL_SS", mat.clusterMargin}, {"VF_SS", mat.vertexFaceMargin}}},
            {"links_per_body", links},
            {"clusters_per_body", clusters},
            {"kSSHR_CL", mat.softSoftHardness},
            {"kSS_SPLT_CL", mat.softSoftSplit},
            {"kVC", mat.volumeStiffness},
            {"kMT", mat.poseMatching},
            {"kKHR", mat.kineticHardness},
            {"collisions",
             {{"CL_SS", "CL_SS | CL_RS, generateClusters(k)"}, {"VF_SS", "VF_SS | SDF_RS"}}}};
        j["runs"] = nlohmann::json::array();
        for (const RunResult& r : runs)
            if (!r.frameMs.empty()) j["runs"].push_back(toJson(r, runs.front()));
        std::ofstream out(jsonPath);
        if (!out) throw InputError(jsonPath, "cannot open the JSON output for writing.");
        out << j.dump(2) << '\n';
        fmt::print("wrote {}\n", jsonPath);
    }
    const bool finite = std::all_of(runs.begin(), runs.end(), [](const RunResult& r) {
        return r.frameMs.empty() || r.finiteEveryFrame;
    });
    return finite ? 0 : 3;
}

} // namespace
} // namespace ffd::bench

int main(int argc, char** argv) {
    try {
        return ffd::bench::run(argc, argv);
    } catch (const ffd::InputError& e) {
        fmt::print(stderr, "ffdaabb_peer_bullet: error: {}\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        fmt::print(stderr, "ffdaabb_peer_bullet: internal error: {}\n", e.what());
        return 1;
    }
}
