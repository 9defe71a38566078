#include "world/settings_table.h"

#include "ffdaabb/error.h"

#include <string_view>

namespace ffd {

namespace {

using W = WorldSettings;
using B = BodySettings;

constexpr SettingRange kWorld[] = {
    {"frameStep", "frame_step", 1e-5, 1.0, "seconds, 0 < frame_step <= 1", false, "s",
     "simulated time per step() call"},
    {"substeps", "substeps", 1, 1000, "1..1000", true, "",
     "dynamics and collision passes per frame"},
    {"floorHeight", "floor_height", -1e6, 1e6, "metres, |h| <= 1e6", false, "m",
     "height of the floor plane (normal +y)"},
    {"contactSkin", "contact_skin", 0.0, 1.0, "0..1 of a cell", false, "cells",
     "contact margin, a share of the lattice cell size"},
    {"solverIterations", "solver_iterations", 1, 1000, "1..1000", true, "",
     "Gauss-Seidel sweeps over the contacts per substep and phase"},
    {"threads", "threads", 0, 1024, "0 (all cores)..1024", true, "",
     "worker threads of the world (0: all cores); results do not depend on it"},
    {"sweepThreshold", "sweep_threshold", 0, 1e9, ">= 0", true, "",
     "bodies above which phase 1 pairs spheres by sort-and-sweep"},
    {"maxSeparationSpeed", "max_separation_speed", 0.0, 1e4, "0 (no bound)..1e4 m/s", false, "m/s",
     "bound on how fast the rigid impact phase pushes bodies apart (0: none)"},
    {"pushOutSpeed", "push_out_speed", 0.0, 1e4, "0 (no bound)..1e4 m/s", false, "m/s",
     "overlap beyond the skin pushed out at most this fast (0: at once)"},
    {"overlapRecoverySpeed", "overlap_recovery_speed", 0.0, 1e4, "0 (at once)..1e4 m/s", false,
     "m/s", "bodies placed overlapping are pushed apart at most this fast (0: at once)"},
    {"overlapRecoveryMaxSpeed", "overlap_recovery_max_speed", 0.0, 1e4, "0 (no bound)..1e4 m/s",
     false, "m/s", "bound on a recovering body's centre speed, its velocity counted (0: none)"},
    {"rigidProjection", "rigid_projection", 0.0, 1.0, "0..1", false, "",
     "share of the bodies' rigid approach at a contact projected on their rigid modes (0: off)"},
    {"vertexFloorContacts", "vertex_floor_contacts", 0, 1, "0 (box corners) or 1 (vertices)", true,
     "", "contacts with the floor and plane colliders at the meshes' vertices (1)"},
    {"sleepSpeed", "sleep_speed", 0.0, 1e3, "0 (never sleep)..1e3 m/s", false, "m/s",
     "bodies quieter than this (rms particle speed) for sleep_time fall asleep (0: never)"},
    {"sleepTime", "sleep_time", 0.0, 1e6, "seconds, 0..1e6", false, "s",
     "how long a body and the bodies it touches must be quiet to fall asleep"},
};
const detail::SettingMember<W> kWorldMembers[] = {
    &W::frameStep,
    &W::substeps,
    &W::floorHeight,
    &W::contactSkin,
    &W::solverIterations,
    &W::threads,
    &W::sweepThreshold,
    &W::maxSeparationSpeed,
    &W::pushOutSpeed,
    &W::overlapRecoverySpeed,
    &W::overlapRecoveryMaxSpeed,
    &W::rigidProjection,
    &W::vertexFloorContacts,
    &W::sleepSpeed,
    &W::sleepTime,
};

constexpr SettingRange kBody[] = {
    {"regionHalfWidth", "region_half_width", 1, 4, "1..4", true, "cells",
     "shape matching region half-width (larger: stiffer)"},
    {"stiffness", "stiffness", 1e-6, 1.0, "0 < stiffness <= 1", false, "",
     "shape matching alpha: share of the way to the goal per step"},
    {"youngsModulus", "youngs_modulus", 1.0, 1e12, "Pa, 1..1e12", false, "Pa",
     "mass-spring: Young's modulus (springs get k = E x rest length)"},
    {"springIterations", "spring_iterations", 1, 1000, "1..1000", true, "",
     "mass-spring: conjugate-gradient iterations at most"},
    {"density", "density", 1e-6, 1e6, "kg/m^3, 0 < density <= 1e6", false, "kg/m^3",
     "density, used when mass is 0"},
    {"mass", "mass", 0.0, 1e9, "kg, 0 (from density) or up to 1e9", false, "kg",
     "total mass (0: density x volume)"},
    {"damping", "damping", 0.0, 1e4, "per second, 0..1e4", false, "1/s",
     "rate at which motion other than the rigid one is removed"},
    {"friction", "friction", 0.0, 10.0, "0..10", false, "",
     "Coulomb friction coefficient (a pair uses the geometric mean)"},
    {"restitution", "restitution", 0.0, 1.0, "0..1", false, "",
     "normal restitution (a pair uses the larger)"},
    {"contactRigidity", "contact_rigidity", 0.0, 1.0, "0..1", false, "",
     "share of an impact's approach removed through the body's rigid motion"},
};
const detail::SettingMember<B> kBodyMembers[] = {
    &B::regionHalfWidth,  &B::stiffness, &B::youngsModulus,
    &B::springIterations, &B::density,   &B::mass,
    &B::damping,          &B::friction,  &B::restitution,
    &B::contactRigidity,
};

static_assert(std::size(kWorld) == std::size(kWorldMembers));
static_assert(std::size(kBody) == std::size(kBodyMembers));

} // namespace

std::span<const SettingRange> worldSettingRanges() {
    return kWorld;
}

std::span<const SettingRange> bodySettingRanges() {
    return kBody;
}

const SettingRange* findSettingRange(std::string_view name) {
    for (std::span<const SettingRange> table : {worldSettingRanges(), bodySettingRanges()})
        for (const SettingRange& r : table)
            if (name == r.field || name == r.key) return &r;
    return nullptr;
}

double settingDefault(const SettingRange& setting) {
    // The table's own entry (the argument may be a copy), whose place names its member.
    const SettingRange* entry = findSettingRange(setting.field);
    if (!entry) throw InputError(setting.field, "not a setting of the table");
    if (entry >= std::begin(kWorld) && entry < std::end(kWorld))
        return detail::settingValue(WorldSettings{}, kWorldMembers[entry - std::begin(kWorld)]);
    return detail::settingValue(BodySettings{}, kBodyMembers[entry - std::begin(kBody)]);
}

namespace detail {

std::span<const SettingMember<WorldSettings>> worldSettingMembers() {
    return kWorldMembers;
}

std::span<const SettingMember<BodySettings>> bodySettingMembers() {
    return kBodyMembers;
}

} // namespace detail

} // namespace ffd
