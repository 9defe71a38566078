#include "util/check.h"

#include <cstdio>
#include <cstdlib>

namespace ffd::detail {

void invariantBroken(const char* condition, const char* file, int line, const std::string& what) {
    std::fprintf(stderr, "ffdaabb: invariant broken at %s:%d: %s (%s)\n", file, line, what.c_str(),
                 condition);
    std::fflush(stderr);
    std::abort();
}

} // namespace ffd::detail
