// Invariant checks at the step's stage boundaries. On with FFD_CHECKS (the dev, asan and tsan
// presets), they stop the program with the broken invariant, where it was checked and what was
// found; off (release), they cost nothing. What they check are the library's own invariants,
// never the user's input: that is validated where it comes in, with InputError.
#pragma once

#include <string>

#ifndef FFD_CHECKS
#define FFD_CHECKS 0
#endif

namespace ffd::detail {

/// Prints "ffdaabb: invariant broken at FILE:LINE: WHAT (CONDITION)" and aborts.
[[noreturn]] void invariantBroken(const char* condition, const char* file, int line,
                                  const std::string& what);

} // namespace ffd::detail

#if FFD_CHECKS
/// FFD_CHECK(condition, what): `what` (a string) is only evaluated when the condition fails.
#define FFD_CHECK(condition, what)                                                                 \
    ((condition) ? void(0) : ::ffd::detail::invariantBroken(#condition, __FILE__, __LINE__, (what)))
#else
#define FFD_CHECK(condition, what) void(0)
#endif
