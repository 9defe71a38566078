#include "test_support.h"

#include "ffdaabb/generators.h"
#include "interpenetration.h"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <fcntl.h>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

namespace ffd::test {

TempDir::TempDir() {
    static int counter = 0;
    path_ = std::filesystem::temp_directory_path() /
            ("ffdaabb-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
}

TempDir::~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
}

void writeFile(const std::filesystem::path& path, const std::string& content) {
    std::ofstream out(path, std::ios::binary);
    out.write(content.data(), std::streamsize(content.size()));
    if (!out) throw std::runtime_error("cannot write " + path.string());
}

std::string readFile(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

SmoothDeformation::SmoothDeformation(uint32_t seed, float size, float amplitude) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    auto randomUnit = [&] {
        for (;;) {
            Vec3 v{u(rng), u(rng), u(rng)};
            const float l = length(v);
            if (l > 0.1f && l <= 1.0f) return v / l;
        }
    };
    for (int i = 0; i < 4; ++i) {
        Wave w;
        w.direction = randomUnit() * (3.14159265f / size * (0.5f + 0.5f * std::fabs(u(rng))));
        w.offset = randomUnit() * (amplitude * size * 0.25f);
        w.phase = 3.14159265f * u(rng);
        waves_.push_back(w);
    }
}

Vec3 SmoothDeformation::operator()(Vec3 p) const {
    Vec3 q = p;
    for (const Wave& w : waves_) q += w.offset * std::sin(dot(w.direction, p) + w.phase);
    return q;
}

std::filesystem::path cliPath() {
    return std::filesystem::path(FFD_BINARY_DIR) / "bin" / "ffdaabb";
}

RunResult runProgram(const std::vector<std::string>& args, int timeoutSeconds) {
    TempDir dir;
    const std::string outPath = (dir / "out").string(), errPath = (dir / "err").string();
    std::vector<char*> argv;
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        const int out = ::open(outPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int err = ::open(errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(out, 1);
        ::dup2(err, 2);
        ::alarm(unsigned(timeoutSeconds));
        ::execvp(argv[0], argv.data());
        std::_Exit(127);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    RunResult r;
    if (WIFEXITED(status))
        r.status = WEXITSTATUS(status);
    else if (WIFSIGNALED(status))
        r.status = WTERMSIG(status) == SIGALRM ? 124 : 128 + WTERMSIG(status);
    r.out = readFile(outPath);
    r.err = readFile(errPath);
    return r;
}

RunResult runCli(const std::vector<std::string>& args, int timeoutSeconds) {
    std::vector<std::string> command{cliPath().string()};
    command.insert(command.end(), args.begin(), args.end());
    return runProgram(command, timeoutSeconds);
}

TriangleMesh ball() {
    TriangleMesh m = icosphere(2);
    transform(m, 0.5f, {});
    return m;
}

BodySettings sphereAt(Vec3 position, Vec3 velocity) {
    BodySettings s;
    s.lattice.targetCells = 38;
    s.position = position;
    s.velocity = velocity;
    return s;
}

TriangleMesh smallBall() {
    TriangleMesh m = ball();
    transform(m, 0.5f, {});
    return m;
}

BodySettings collider(BodyMotion motion, Vec3 position, int targetCells) {
    BodySettings s;
    s.motion = motion;
    s.position = position;
    s.lattice.targetCells = targetCells;
    return s;
}

BodyId addHeavyOnLight(World& world, float offset) {
    BodySettings s = sphereAt({0, 0.5f, 0});
    s.density = 10;
    const BodyId light = world.addBody(ball(), s);
    s = sphereAt({offset, 1.52f, 0});
    s.density = 10000;
    world.addBody(ball(), s);
    return light;
}

std::vector<BodyId> pourBallsIntoABowl(World& world, float shift) {
    world.addBody(bowl(1.2f, 0.2f, 32), collider(BodyMotion::Static, {0, 1.25f, 0}, 400));
    std::vector<BodyId> balls;
    for (int i = 0; i < 4; ++i)
        balls.push_back(world.addBody(
            smallBall(), sphereAt({0.3f * float(i % 2) - 0.15f + shift * float(i),
                                   1.8f + 0.6f * float(i), 0.3f * float(i / 2) - 0.15f})));
    return balls;
}

void addBallsAtOneSpot(World& world, int count, Vec3 centre, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-0.5f, 0.5f);
    for (int i = 0; i < count; ++i) {
        BodySettings s = sphereAt(centre);
        s.rotation = normalize(Quat{u(rng), u(rng), u(rng), u(rng)});
        world.addBody(ball(), s);
    }
}

double rmsSpeed(const World& world, BodyId body) {
    const std::span<const Vec3> v = world.velocities(body);
    double sum = 0;
    for (const Vec3& u : v) sum += double(lengthSquared(u));
    return std::sqrt(sum / double(v.size()));
}

double stackBuzz(WorldSettings settings) {
    settings.sleepSpeed = 0;
    World world(settings);
    const TriangleMesh slab = box({0.4f, 0.2f, 0.3f});
    BodySettings s;
    s.position = {0, 0.2f, 0};
    world.addBody(slab, s);
    s.position = {0.05f, 0.602f, 0};
    const BodyId upper = world.addBody(slab, s);
    double sum = 0;
    int count = 0;
    for (int f = 0; f < 480; ++f) {
        world.step();
        if (f >= 240) sum += rmsSpeed(world, upper), ++count;
    }
    return sum / count;
}

float lowestVertex(const World& world, BodyId body) {
    float lowest = INFINITY;
    for (const Vec3& v : world.vertices(body)) lowest = std::min(lowest, v.y);
    return lowest;
}

Vec3 spinOf(const World& world, BodyId body) {
    const std::span<const Vec3> x = world.particles(body), v = world.velocities(body);
    const Vec3 c = world.centreOfMass(body), p = world.linearVelocity(body);
    Mat3 inertia{};
    Vec3 momentum{};
    for (uint32_t i = 0; i < x.size(); ++i) {
        const float m = world.particleMass(body, i);
        const Vec3 r = x[i] - c;
        momentum += cross(r, v[i] - p) * m;
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k)
                inertia.m[j][k] += m * ((j == k ? dot(r, r) : 0.0f) - r[j] * r[k]);
    }
    Mat3 inverseInertia;
    if (!inverse(inertia, inverseInertia)) return {};
    return inverseInertia * momentum;
}

double deepestInside(const World& world, float referenceSize) {
    std::vector<bench::MeshView> views;
    for (BodyId id : world.bodies()) views.push_back({world.vertices(id), world.triangles(id)});
    bench::InterpenetrationSettings s;
    s.referenceSize = referenceSize;
    return bench::measureInterpenetration(views, s).maxDepth;
}

float fastestBody(const World& world) {
    float fastest = 0;
    for (BodyId id : world.bodies()) fastest = std::max(fastest, length(world.linearVelocity(id)));
    return fastest;
}

CentreSpeeds::CentreSpeeds(const World& world) : bodies_(world.bodies()) {
    for (const BodyId b : bodies_) before_.push_back(world.centreOfMass(b));
}

float CentreSpeeds::afterStep(const World& world) {
    float fastest = 0;
    for (size_t i = 0; i < bodies_.size(); ++i) {
        const Vec3 c = world.centreOfMass(bodies_[i]);
        fastest = std::max(fastest, length(c - before_[i]) / world.settings().frameStep);
        before_[i] = c;
    }
    return fastest;
}

float closestCentres(const World& world) {
    const std::vector<BodyId> ids = world.bodies();
    float closest = INFINITY;
    for (size_t a = 0; a < ids.size(); ++a)
        for (size_t b = a + 1; b < ids.size(); ++b)
            closest =
                std::min(closest, length(world.centreOfMass(ids[a]) - world.centreOfMass(ids[b])));
    return closest;
}

bool insideConvexHull(const Vec3 points[8], Vec3 p, float tol) {
    for (int a = 0; a < 8; ++a)
        for (int b = a + 1; b < 8; ++b)
            for (int c = b + 1; c < 8; ++c) {
                const Vec3 n = cross(points[b] - points[a], points[c] - points[a]);
                const float len = length(n);
                if (len < 1e-12f) continue;
                const Vec3 unit = n / len;
                float lo = 0, hi = 0;
                for (int k = 0; k < 8; ++k) {
                    const float d = dot(unit, points[k] - points[a]);
                    lo = std::min(lo, d), hi = std::max(hi, d);
                }
                const float scale = std::max(hi - lo, 1e-30f);
                // Supporting plane when all points lie (numerically) on one side.
                const float pd = dot(unit, p - points[a]);
                if (lo >= -1e-6f * scale && pd < -tol) return false;
                if (hi <= 1e-6f * scale && pd > tol) return false;
            }
    return true;
}

} // namespace ffd::test
