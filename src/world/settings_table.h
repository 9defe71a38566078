// The numeric settings' table (ffdaabb/world.h: SettingRange) with the members it describes, for
// the library's validation and the scene reader.
#pragma once

#include "ffdaabb/world.h"

#include <span>
#include <variant>

namespace ffd::detail {

template <class Settings>
using SettingMember = std::variant<float Settings::*, int Settings::*>;

/// Each entry's member, in the order of worldSettingRanges() / bodySettingRanges().
std::span<const SettingMember<WorldSettings>> worldSettingMembers();
std::span<const SettingMember<BodySettings>> bodySettingMembers();

/// The setting's value as a double.
template <class Settings>
double settingValue(const Settings& s, const SettingMember<Settings>& member) {
    return std::visit([&](auto m) { return double(s.*m); }, member);
}

} // namespace ffd::detail
