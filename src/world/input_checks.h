// The checks of the World's inputs that throw InputError naming the field and the value, shared
// by the world's files (world.cpp, pins.cpp).
#pragma once

#include "ffdaabb/error.h"
#include "ffdaabb/math.h"

#include <cstdio>
#include <string>

namespace ffd::detail {

/// A value as the input errors show it ("%g").
inline std::string valueText(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

/// InputError unless lo <= value <= hi (NaN is out of range); `expected` says the range.
inline void requireRange(const char* field, double value, double lo, double hi,
                         const char* expected) {
    if (!(value >= lo && value <= hi))
        throw InputError(field, "value " + valueText(value) + " is out of range (expected " +
                                    expected + ")");
}

/// InputError unless every coordinate is finite.
inline void requireFinite(const char* field, Vec3 v) {
    if (!isFinite(v))
        throw InputError(field, "value (" + valueText(v.x) + ", " + valueText(v.y) + ", " +
                                    valueText(v.z) + ") is not finite (expected finite numbers)");
}

} // namespace ffd::detail
