// What each stage of the step hands the next, checked (util/check.h: FFD_CHECK, on in the dev,
// asan and tsan presets). Each function returns what it found wrong, or an empty string; tests
// call them directly.
#pragma once

#include <string>

namespace ffd::detail {

struct WorldData;

/// After lattice_dynamics, position_update and the response: every particle's position and
/// velocity finite.
std::string particleProblem(const WorldData& world);

/// After node_update: every box node finite and inside its box's bounds, every box's bounds
/// inside its body's.
std::string nodeProblem(const WorldData& world);

/// After sphere_test: the candidate pairs in canonical order (a < b, sorted, no repeats, bodies
/// in range), and each candidate body's bounding sphere holding its boxes' bounds (so that
/// phase 1 drops no pair the narrow phase could find).
std::string sphereProblem(const WorldData& world);

/// After mesh_update: every mesh vertex finite.
std::string meshProblem(const WorldData& world);

} // namespace ffd::detail
