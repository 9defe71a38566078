#include "runner.h"

#include "ffdaabb/error.h"
#include "sample_stats.h"
#include "util/atomic_file.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace ffd::cli {

Scene sceneFromOptions(const std::string& name, const SceneOverrides& o,
                       const SceneOverrideNames& names) {
    Scene scene = loadScene(name);
    if (o.objects) {
        if (*o.objects < 1 || *o.objects > 100000)
            throw InputError(names.objects, "value " + std::to_string(*o.objects) +
                                                " is out of range (expected 1..100000)");
        setObjectCount(scene, *o.objects);
    }
    if (o.mode && !parseCollisionMode(*o.mode, scene.world.mode))
        throw InputError(names.mode, "unknown mode \"" + *o.mode +
                                         "\" (expected enhanced, previous, brute or none)");
    if (o.threads) {
        const SettingRange& range = *findSettingRange("threads");
        if (*o.threads < range.min || *o.threads > range.max)
            throw InputError(names.threads, "value " + std::to_string(*o.threads) +
                                                " is out of range (expected " + range.expected +
                                                ")");
        scene.world.threads = *o.threads;
    }
    if (o.seed) {
        if (*o.seed < 0 || *o.seed > 2147483647)
            throw InputError(names.seed, "value " + std::to_string(*o.seed) +
                                             " is out of range (expected 0..2147483647)");
        scene.layout.seed = uint32_t(*o.seed);
    }
    return scene;
}

Timings timings(const Profile& p) {
    Timings t{};
    for (const StageInfo& s : stageTable()) t[size_t(timingOf(s.stage))] = p.ms(s.stage);
    for (const TableColumnInfo& c : tableColumns()) t[size_t(timingOf(c.column))] = p.ms(c.column);
    t[kTotalTiming] = p.total;
    return t;
}

nlohmann::json stagesJson(const double (&ms)[kTimingCount]) {
    nlohmann::json j;
    for (const StageInfo& s : stageTable()) j[s.key] = ms[timingOf(s.stage)];
    j["total"] = ms[kTotalTiming];
    return j;
}

nlohmann::json tableColumnsJson(const double (&ms)[kTimingCount]) {
    nlohmann::json j;
    for (const TableColumnInfo& c : tableColumns()) j[c.key] = ms[timingOf(c.column)];
    j["total"] = ms[kTotalTiming];
    return j;
}

void summariseStages(const std::vector<Timings>& frameMs, double (&mean)[kTimingCount],
                     double (&median)[kTimingCount]) {
    for (int s = 0; s < kTimingCount; ++s) {
        std::vector<double> v;
        v.reserve(frameMs.size());
        for (const auto& f : frameMs) v.push_back(f[size_t(s)]);
        mean[s] = bench::mean(v);
        median[s] = bench::median(std::move(v));
    }
}

RunResult runScene(const Scene& scene, const RunOptions& options,
                   const std::function<void(const SceneBuild&)>& atEnd) {
    RunResult r;
    r.scene = scene.name;
    r.mode = toString(scene.world.mode);
    r.objects = scene.objectCount();
    r.frames = options.frames;
    r.warmup = options.warmup;
    r.threads = scene.world.threads;
    r.seed = scene.layout.seed;
    SceneBuild build = buildScene(scene);
    if (options.atStart) {
        options.atStart(build);
        build.bodies = build.world.bodies(); // a restored state brings its handles
    }
    r.startFrame = build.world.frame();
    r.vertices = build.vertices;
    r.triangles = build.triangles;
    r.cells = build.cells;
    r.particles = build.particles;
    r.nodes = build.nodes;
    r.buildMs = build.buildMilliseconds;

    // The meshes, judged by the interpenetration measure against the largest object's size.
    r.measureEvery = options.measureEvery;
    std::vector<bench::MeshView> views;
    for (BodyId id : build.bodies)
        views.push_back({build.world.vertices(id), build.world.triangles(id)});
    bench::InterpenetrationSettings measure;
    for (const SceneObject& object : scene.objects)
        measure.referenceSize = std::max(measure.referenceSize, object.size);
    measure.floorHeight = scene.world.floorHeight;
    r.referenceSize = measure.referenceSize;
    auto sample = [&](int frame) {
        const bench::Interpenetration p = bench::measureInterpenetration(views, measure);
        if (r.measureSamples == 0 || p.maxDepth > r.interpenetration.maxDepth)
            r.deepestFrame = frame;
        bench::keepWorst(r.interpenetration, p);
        ++r.measureSamples;
    };

    const auto start = std::chrono::steady_clock::now();
    const int total = options.warmup + options.frames;
    for (int f = 0; f < total; ++f) {
        build.world.step();
        if (options.measureEvery > 0 && ((f + 1) % options.measureEvery == 0 || f + 1 == total))
            sample(int(build.world.frame()));
        if (f >= options.warmup) {
            const Profile& p = build.world.profile();
            r.frameMs.push_back(timings(p));
            r.counts.add(p);
        }
        if (options.progress) options.progress(f + 1, total);
    }
    r.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.counts.average();
    r.sleepingAtEnd = build.world.profile().sleepingBodies;
    summariseStages(r.frameMs, r.meanMs, r.medianMs);
    r.stateHash = build.world.stateHash();
    for (BodyId id : build.bodies) {
        for (const Vec3& p : build.world.particles(id)) r.finite = r.finite && isFinite(p);
        for (const Vec3& p : build.world.velocities(id)) r.finite = r.finite && isFinite(p);
    }
    if (atEnd) atEnd(build);
    return r;
}

void ProfileCounts::add(const Profile& p) {
    candidatePairs += p.candidatePairs;
    potentialPairs += p.potentialPairs;
    boxPairs += p.boxPairs;
    contactBoxPairs += p.contactBoxPairs;
    contacts += p.contacts;
    floorContacts += p.floorContacts;
    sleepingBodies += p.sleepingBodies;
    maxContactDepth = std::max(maxContactDepth, double(p.maxContactDepth));
    ++frames;
}

void ProfileCounts::average() {
    if (frames == 0) return;
    for (double* sum : {&candidatePairs, &potentialPairs, &boxPairs, &contactBoxPairs, &contacts,
                        &floorContacts, &sleepingBodies})
        *sum /= frames;
}

void ProfileCounts::toJson(nlohmann::json& j) const {
    j["candidate_pairs"] = candidatePairs;
    j["potential_pairs"] = potentialPairs;
    j["box_pairs"] = boxPairs;
    j["contact_box_pairs"] = contactBoxPairs;
    j["contacts"] = contacts;
    j["floor_contacts"] = floorContacts;
    j["sleeping_bodies"] = sleepingBodies;
    j["max_contact_depth"] = maxContactDepth;
}

StandoffSummary summariseStandoff(const BoxStandoff& standoff) {
    StandoffSummary s;
    s.directions = int(standoff.standoff.size());
    const std::vector<double> sample(standoff.standoff.begin(), standoff.standoff.end());
    s.median = bench::median(sample);
    s.p90 = bench::quantile(sample, 0.9);
    s.max = standoff.max;
    s.worstDirection = standoff.worstDirection;
    return s;
}

nlohmann::json standoffJson(const StandoffSummary& s) {
    return {{"directions", s.directions}, {"median", s.median}, {"p90", s.p90}, {"max", s.max}};
}

nlohmann::json interpenetrationJson(const RunResult& r) {
    if (r.measureSamples == 0) return {{"sample_every", 0}, {"samples", 0}};
    const bench::Interpenetration& p = r.interpenetration;
    return {{"sample_every", r.measureEvery},
            {"samples", r.measureSamples},
            {"reference_size_m", r.referenceSize},
            {"max_depth_relative", p.maxDepthRelative},
            {"max_depth_m", p.maxDepth},
            {"deepest_frame", r.deepestFrame},
            {"deepest_vertex", p.deepestBody < 0 ? nlohmann::json(nullptr)
                                                 : nlohmann::json{{"object", p.deepestBody},
                                                                  {"vertex", p.deepestVertex},
                                                                  {"inside", p.deepestInside}}},
            {"max_inside_vertices", p.insideVertices},
            {"max_deep_vertices", p.deepVertices},
            {"max_body_pairs", p.bodyPairs},
            {"below_floor_m", p.belowFloor}};
}

nlohmann::json statsJson(const RunResult& r) {
    char hash[17];
    std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(r.stateHash));
    nlohmann::json j = {{"scene", r.scene},
                        {"mode", r.mode},
                        {"objects", r.objects},
                        {"vertices", r.vertices},
                        {"triangles", r.triangles},
                        {"cells", r.cells},
                        {"particles", r.particles},
                        {"box_nodes", r.nodes},
                        {"vertices_per_object", double(r.vertices) / std::max(1, r.objects)},
                        {"triangles_per_object", double(r.triangles) / std::max(1, r.objects)},
                        {"cells_per_object", double(r.cells) / std::max(1, r.objects)},
                        {"frames", r.frames},
                        {"warmup_frames", r.warmup},
                        {"start_frame", r.startFrame},
                        {"threads", r.threads},
                        {"seed", r.seed},
                        {"stage_ms", stagesJson(r.meanMs)},
                        {"stage_ms_median", stagesJson(r.medianMs)},
                        {"table1_ms", tableColumnsJson(r.meanMs)},
                        {"table1_ms_median", tableColumnsJson(r.medianMs)},
                        {"frames_per_second", r.framesPerSecond()},
                        {"sleeping_bodies_at_end", r.sleepingAtEnd},
                        {"interpenetration", interpenetrationJson(r)},
                        {"state_hash", hash},
                        {"finite", r.finite},
                        {"build_ms", r.buildMs},
                        {"wall_seconds", r.wallSeconds}};
    r.counts.toJson(j);
    return j;
}

void writeTextFile(const std::string& path, const std::string& text) {
    AtomicFile file(path);
    std::fwrite(text.data(), 1, text.size(), file.handle());
    file.commit();
}

std::function<void(int, int)> progressBar(const std::string& label) {
    if (!::isatty(2)) return {};
    return [label, last = -1](int done, int total) mutable {
        const int percent = total > 0 ? done * 100 / total : 100;
        if (percent == last && done != total) return;
        last = percent;
        const int width = 40, filled = width * percent / 100;
        fmt::print(stderr, "\r{} [{}{}] {:3d}% ({}/{} frames)", label,
                   std::string(size_t(filled), '#'), std::string(size_t(width - filled), ' '),
                   percent, done, total);
        if (done == total) fmt::print(stderr, "\n");
        std::fflush(stderr);
    };
}

void exportObj(const SceneBuild& build, const std::string& path) {
    AtomicFile file(path);
    writeObj(build, file.handle());
    file.commit();
}

void writeObj(const SceneBuild& build, std::FILE* f) {
    std::fprintf(f, "# ffdaabb: %zu bodies, final deformed meshes\n", build.bodies.size());
    size_t base = 1;
    for (size_t i = 0; i < build.bodies.size(); ++i) {
        const BodyId id = build.bodies[i];
        std::fprintf(f, "o body_%zu\n", i);
        const auto vertices = build.world.vertices(id);
        for (const Vec3& v : vertices)
            std::fprintf(f, "v %.7g %.7g %.7g\n", double(v.x), double(v.y), double(v.z));
        for (const auto& t : build.world.triangles(id))
            std::fprintf(f, "f %zu %zu %zu\n", t[0] + base, t[1] + base, t[2] + base);
        base += vertices.size();
    }
}

} // namespace ffd::cli
