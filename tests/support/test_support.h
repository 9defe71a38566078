// Helpers shared by the test folders.
#pragma once

#include "ffdaabb/math.h"
#include "ffdaabb/mesh.h"
#include "ffdaabb/world.h"

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace ffd::test {

/// Sets an environment variable for the lifetime of the object, then restores it.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const char* value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old;
        if (value)
            ::setenv(name, value, 1);
        else
            ::unsetenv(name);
    }
    ~ScopedEnv() {
        if (old_)
            ::setenv(name_, old_->c_str(), 1);
        else
            ::unsetenv(name_);
    }
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;

private:
    const char* name_;
    std::optional<std::string> old_;
};

/// A fresh empty folder under the system temp dir, removed with its contents on destruction.
class TempDir {
public:
    TempDir();
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    const std::filesystem::path& path() const { return path_; }
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

private:
    std::filesystem::path path_;
};

/// Writes `content` to `path` (binary, exact bytes).
void writeFile(const std::filesystem::path& path, const std::string& content);
/// Reads a whole file.
std::string readFile(const std::filesystem::path& path);

/// A smooth random deformation of space: x -> x + amplitude * size * sum of a few low-frequency
/// sine waves along random directions, deterministic for a seed. `size` sets the length scale.
class SmoothDeformation {
public:
    SmoothDeformation(uint32_t seed, float size, float amplitude);
    Vec3 operator()(Vec3 p) const;

private:
    struct Wave {
        Vec3 direction; // wave vector (1/m)
        Vec3 offset;    // displacement direction * amplitude
        float phase;
    };
    std::vector<Wave> waves_;
};

/// Result of running a command.
struct RunResult {
    int status = -1; ///< exit status (or 128 + signal)
    std::string out, err;
};

/// Runs a program with arguments (args[0]: a path, or a name looked up in PATH), capturing
/// stdout and stderr. `timeoutSeconds` kills it when exceeded (status 124).
RunResult runProgram(const std::vector<std::string>& args, int timeoutSeconds = 120);

/// Runs the ffdaabb CLI built alongside the tests with `args` (already split), capturing
/// stdout and stderr. `timeoutSeconds` kills it when exceeded (status 124).
RunResult runCli(const std::vector<std::string>& args, int timeoutSeconds = 300);

/// Path of the CLI binary under test.
std::filesystem::path cliPath();

/// An icosphere of 2 subdivisions (162 vertices), 1 m across, centred on the origin.
TriangleMesh ball();

/// Settings of a ball() body: the paper's 38-cell lattice, at `position` with `velocity`.
BodySettings sphereAt(Vec3 position, Vec3 velocity = {});

/// A ball() scaled to 0.5 m across (radius 0.25): the balls the collider tests pour among pegs,
/// steps and bowls (with sphereAt's settings, the paper's lattice).
TriangleMesh smallBall();

/// Settings of a static or kinematic collider body at `position` with a lattice of about
/// `targetCells` cells.
BodySettings collider(BodyMotion motion, Vec3 position, int targetCells = 64);

/// Four smallBall() bodies poured from 1.8-3.6 m into a static bowl (radius 1.2 m, wall 0.2 m,
/// its rim 1.25 m above the floor), ball i moved `shift` * i metres along x from the others'
/// layout: shifts of a few millimetres give different piles. Returns the balls; the bowl is
/// the world's first body.
std::vector<BodyId> pourBallsIntoABowl(World& world, float shift);

/// A ball() 1,000 times heavier (density 10,000) resting on a light one (density 10) on the
/// floor, offset sideways by `offset` metres: the mass-ratio case. Returns the light body.
BodyId addHeavyOnLight(World& world, float offset);

/// `count` ball() bodies created with one centre, each turned at random (rotations from a
/// std::mt19937 seeded with `seed`). 200 of them at (0, 0.6, 0), just above the floor, are the
/// "200 at one spot" case.
void addBallsAtOneSpot(World& world, int count, Vec3 centre, unsigned seed);

/// How deep the deepest mesh vertex lies inside another body's closed mesh (metres, 0 when none
/// is): the winding-number measure of bench/common/interpenetration.h over all bodies.
double deepestInside(const World& world, float referenceSize = 1.0f);

/// The largest linear velocity of any body, m/s.
float fastestBody(const World& world);

/// How fast the bodies' centres of mass move from one frame to the next (what a viewer sees,
/// the velocity and any move by positions together): construct it on the world, then call
/// `afterStep` after each World::step() for the fastest centre over that frame, m/s. Follows the
/// bodies the world had when it was made.
class CentreSpeeds {
public:
    explicit CentreSpeeds(const World& world);
    float afterStep(const World& world);

private:
    std::vector<BodyId> bodies_;
    std::vector<Vec3> before_;
};

/// A body's root-mean-square particle speed, m/s.
double rmsSpeed(const World& world, BodyId body);

/// A 0.8 x 0.4 x 0.6 m box set 5 cm off centre on a like box on the floor, in a world with
/// `settings` (sleeping off: watched awake): the upper box's rmsSpeed averaged over 4-8 s, how
/// much a resting stack buzzes (docs/LIMITS.md, known problem 5).
double stackBuzz(WorldSettings settings);

/// The height of a body's lowest mesh vertex (the deformed mesh), m.
float lowestVertex(const World& world, BodyId body);

/// A body's spin about its centre of mass, rad/s: the angular velocity that fits its particles'
/// velocities about their mean best (least squares, mass-weighted).
Vec3 spinOf(const World& world, BodyId body);

/// The least distance between two bodies' centres of mass, m (infinity with fewer than two).
float closestCentres(const World& world);

/// True when p lies in the convex hull of the 8 points (within tol, absolute): for every plane
/// through three of the points that has all 8 on one side, p must be on that side too.
bool insideConvexHull(const Vec3 points[8], Vec3 p, float tol);

} // namespace ffd::test
