// The last step of the cause tools' --json output: the text goes to the AtomicFile opened before
// the run (so a bad path fails before any work), and is committed into place. A failed write
// prints "<tool>: --json: <why>" and gives exit status 2, the status a bad path gets too.
#pragma once

#include "util/atomic_file.h"

#include <cstdio>
#include <exception>
#include <string>
#include <string_view>

namespace ffd::bench {

/// Writes `text` to `file` and renames it into place. Returns the tool's exit status: 0, or 2
/// after a message on stderr naming the tool, the flag and the reason.
inline int commitJson(AtomicFile& file, std::string_view text, std::string_view tool) {
    try {
        std::fwrite(text.data(), 1, text.size(), file.handle());
        file.commit();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: --json: %s\n", std::string(tool).c_str(), e.what());
        return 2;
    }
    return 0;
}

} // namespace ffd::bench
