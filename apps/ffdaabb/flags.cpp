#include "flags.h"
#include "commands.h"
#include "runner.h"

#include "ffdaabb/error.h"

#include <fmt/core.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <system_error>

namespace ffd::cli {

namespace {

std::string quoted(const std::string& text) {
    // Long or odd values are cut so that the message stays one readable line.
    std::string shown = text.size() > 40 ? text.substr(0, 37) + "..." : text;
    for (char& c : shown)
        if (static_cast<unsigned char>(c) < 0x20) c = '?';
    return "\"" + shown + "\"";
}

std::string range(long long lo, long long hi) {
    return std::to_string(lo) + ".." + std::to_string(hi);
}

// The whole number in `text`, in [lo, hi]; `expected` says the range in the message.
long long parseIntegerIn(const std::string& flag, const std::string& text, long long lo,
                         long long hi, const std::string& expected) {
    long long value = 0;
    const char* first = text.data();
    const char* last = text.data() + text.size();
    const auto [end, ec] = std::from_chars(first, last, value);
    if (ec == std::errc::result_out_of_range)
        throw InputError(flag,
                         "value " + quoted(text) + " is out of range (expected " + expected + ")");
    if (text.empty() || ec != std::errc() || end != last)
        throw InputError(flag, "value " + quoted(text) + " is not a whole number (expected " +
                                   expected + ")");
    if (value < lo || value > hi)
        throw InputError(flag, "value " + std::to_string(value) + " is out of range (expected " +
                                   expected + ")");
    return value;
}

} // namespace

long long parseInteger(const std::string& flag, const std::string& text, long long lo,
                       long long hi) {
    return parseIntegerIn(flag, text, lo, hi, range(lo, hi));
}

long long parseIntegerSetting(const std::string& flag, const std::string& text,
                              const char* setting) {
    const SettingRange& r = *findSettingRange(setting);
    return parseIntegerIn(flag, text, (long long)r.min, (long long)r.max, r.expected);
}

double parseNumber(const std::string& flag, const std::string& text, double lo, double hi,
                   const std::string& expected) {
    double value = 0;
    const char* first = text.data();
    const char* last = text.data() + text.size();
    const auto [end, ec] = std::from_chars(first, last, value);
    if (text.empty() || (ec != std::errc() && ec != std::errc::result_out_of_range) || end != last)
        throw InputError(flag,
                         "value " + quoted(text) + " is not a number (expected " + expected + ")");
    if (ec == std::errc::result_out_of_range || !std::isfinite(value) || value < lo || value > hi)
        throw InputError(flag,
                         "value " + quoted(text) + " is out of range (expected " + expected + ")");
    return value;
}

void addSceneFlags(CLI::App* cmd, SceneFlags& f, bool threads) {
    cmd->add_option("--scene", f.scene,
                    "Scene name (alphabets, spheres, teapots, buddhas) or a .json file")
        ->required();
    f.objectsOption = cmd->add_option("--objects", f.objects,
                                      "Total number of objects, 1..100000 (default: the scene's)");
    f.modeOption =
        cmd->add_option("--mode", f.mode, "Collision mode: enhanced, previous, brute or none");
    if (threads)
        f.threadsOption =
            cmd->add_option("--threads", f.threads,
                            std::string("Worker threads, ") +
                                findSettingRange("threads")->expected + " (default: the scene's)");
    f.seedOption =
        cmd->add_option("--seed", f.seed, "Layout seed, 0..2147483647 (default: the scene's)");
}

Scene sceneFromFlags(const SceneFlags& f) {
    // Values given are checked here, before the scene is loaded, so that a bad flag is reported
    // as such even when the scene is bad too.
    SceneOverrides o;
    if (given(f.objectsOption)) o.objects = int(parseInteger("--objects", f.objects, 1, 100000));
    CollisionMode mode;
    if (given(f.modeOption) && !parseCollisionMode(f.mode, mode))
        throw InputError("--mode", "unknown mode " + quoted(f.mode) +
                                       " (expected enhanced, previous, brute or none)");
    if (given(f.modeOption)) o.mode = f.mode;
    if (given(f.threadsOption))
        o.threads = int(parseIntegerSetting("--threads", f.threads, "threads"));
    if (given(f.seedOption)) o.seed = parseInteger("--seed", f.seed, 0, 2147483647);
    return sceneFromOptions(f.scene, o);
}

void checkOutputPath(const std::string& flag, const std::string& path) {
    if (path.empty()) return;
    namespace fs = std::filesystem;
    const fs::path p(path);
    std::error_code ec;
    const fs::file_status status = fs::status(p, ec);
    if (fs::is_directory(status))
        throw InputError(flag, "\"" + path + "\" is a folder (expected a file name)");
    // Outputs are renamed into place: that would replace a device or a pipe (/dev/null) itself.
    if (fs::exists(status) && !fs::is_regular_file(status))
        throw InputError(flag, "\"" + path +
                                   "\" is not a regular file (a device, pipe or socket; expected "
                                   "a file name)");
    // The file is written as "<name>.tmp-<pid>" first: that name must fit too.
    if (p.filename().string().size() > 200)
        throw InputError(flag, "the file name is " + std::to_string(p.filename().string().size()) +
                                   " characters long (expected at most 200)");
    const fs::path parent = p.has_parent_path() ? p.parent_path() : fs::path(".");
    const fs::file_status parentStatus = fs::status(parent, ec);
    if (!fs::exists(parentStatus))
        throw InputError(flag, "cannot write \"" + path + "\": the folder " + parent.string() +
                                   " does not exist");
    if (!fs::is_directory(parentStatus))
        throw InputError(flag,
                         "cannot write \"" + path + "\": " + parent.string() + " is not a folder");
}

void checkDistinctOutputs(const std::string& flagA, const std::string& pathA,
                          const std::string& flagB, const std::string& pathB) {
    if (pathA.empty() || pathB.empty()) return;
    std::error_code ecA, ecB;
    const auto a = std::filesystem::weakly_canonical(std::filesystem::absolute(pathA), ecA);
    const auto b = std::filesystem::weakly_canonical(std::filesystem::absolute(pathB), ecB);
    if (pathA == pathB || (!ecA && !ecB && a == b))
        throw InputError(flagB, "\"" + pathB + "\" is the same file as " + flagA + " \"" + pathA +
                                    "\" (expected two different files)");
}

} // namespace ffd::cli
