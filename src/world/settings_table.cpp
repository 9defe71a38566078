#include "world/settings_table.h"

#include <string_view>

namespace ffd {

namespace {

using W = WorldSettings;
using B = BodySettings;

constexpr SettingRange kWorld[] = {
    {"frameStep", "frame_step", 1e-5, 1.0, "seconds, 0 < frame_step <= 1", false},
    {"substeps", "substeps", 1, 1000, "1..1000", true},
    {"floorHeight", "floor_height", -1e6, 1e6, "metres, |h| <= 1e6", false},
    {"contactSkin", "contact_skin", 0.0, 1.0, "0..1 of a cell", false},
    {"solverIterations", "solver_iterations", 1, 1000, "1..1000", true},
    {"threads", "threads", 0, 1024, "0 (all cores)..1024", true},
    {"sweepThreshold", "sweep_threshold", 0, 1e9, ">= 0", true},
    {"maxSeparationSpeed", "max_separation_speed", 0.0, 1e4, "0 (no bound)..1e4 m/s", false},
    {"pushOutSpeed", "push_out_speed", 0.0, 1e4, "0 (no bound)..1e4 m/s", false},
    {"overlapRecoverySpeed", "overlap_recovery_speed", 0.0, 1e4, "0 (at once)..1e4 m/s", false},
};
const detail::SettingMember<W> kWorldMembers[] = {
    &W::frameStep,        &W::substeps,
    &W::floorHeight,      &W::contactSkin,
    &W::solverIterations, &W::threads,
    &W::sweepThreshold,   &W::maxSeparationSpeed,
    &W::pushOutSpeed,     &W::overlapRecoverySpeed,
};

constexpr SettingRange kBody[] = {
    {"regionHalfWidth", "region_half_width", 1, 4, "1..4", true},
    {"stiffness", "stiffness", 1e-6, 1.0, "0 < stiffness <= 1", false},
    {"youngsModulus", "youngs_modulus", 1.0, 1e12, "Pa, 1..1e12", false},
    {"springIterations", "spring_iterations", 1, 1000, "1..1000", true},
    {"density", "density", 1e-6, 1e6, "kg/m^3, 0 < density <= 1e6", false},
    {"mass", "mass", 0.0, 1e9, "kg, 0 (from density) or up to 1e9", false},
    {"damping", "damping", 0.0, 1e4, "per second, 0..1e4", false},
    {"friction", "friction", 0.0, 10.0, "0..10", false},
    {"restitution", "restitution", 0.0, 1.0, "0..1", false},
    {"contactRigidity", "contact_rigidity", 0.0, 1.0, "0..1", false},
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

namespace detail {

std::span<const SettingMember<WorldSettings>> worldSettingMembers() {
    return kWorldMembers;
}

std::span<const SettingMember<BodySettings>> bodySettingMembers() {
    return kBodyMembers;
}

} // namespace detail

} // namespace ffd
