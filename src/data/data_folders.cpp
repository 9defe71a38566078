// The data folders (ffdaabb/data.h).
#include "ffdaabb/data.h"

#include <cstdlib>
#include <mutex>
#include <string>
#include <system_error>

namespace ffd {

namespace {

std::mutex& addedMutex() {
    static std::mutex m;
    return m;
}

std::vector<std::filesystem::path>& added() {
    static std::vector<std::filesystem::path> folders;
    return folders;
}

} // namespace

std::vector<std::filesystem::path> dataFolders() {
    std::vector<std::filesystem::path> folders;
    {
        std::lock_guard<std::mutex> lock(addedMutex());
        folders = added();
    }
    if (const char* env = std::getenv("FFDAABB_DATA"); env && *env) {
        const std::string list = env;
        size_t from = 0;
        while (from <= list.size()) {
            const size_t to = std::min(list.find(':', from), list.size());
            if (to > from) folders.emplace_back(list.substr(from, to - from));
            from = to + 1;
        }
    }
    std::error_code ec;
    const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec && program.has_parent_path())
        folders.push_back(program.parent_path().parent_path() / "share" / "ffdaabb");
    folders.emplace_back(FFD_INSTALL_DATADIR);
    return folders;
}

void addDataFolder(const std::filesystem::path& folder) {
    std::lock_guard<std::mutex> lock(addedMutex());
    added().push_back(folder);
}

std::filesystem::path findData(const std::filesystem::path& relative) {
    for (const std::filesystem::path& folder : dataFolders()) {
        std::error_code ec;
        const std::filesystem::path candidate = folder / relative;
        if (std::filesystem::exists(candidate, ec)) return candidate;
    }
    return {};
}

} // namespace ffd
