// libFuzzer target: parseScene on arbitrary text (scenes/*.json and variants as seeds,
// scene_parse.dict for the field names).
//
// Contract checked: parseScene either returns a scene that satisfies every documented range
// (at least one object, counts and the total in range, settings that validate) or throws
// InputError; nothing else escapes, and deep or large garbage neither crashes nor exhausts
// the stack. Mesh file paths are resolved against a folder that does not exist, so relative
// ones are refused; absolute ones may name real files, which are only checked to exist.
#include "ffdaabb/error.h"
#include "ffdaabb/scene.h"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

void check(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "fuzz_scene_parse: contract broken: %s\n", what);
        std::abort();
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    ffd::Scene scene;
    try {
        scene = ffd::parseScene(text, "/nonexistent-ffdaabb-fuzz/scene.json");
    } catch (const ffd::InputError&) {
        return 0;
    }
    check(!scene.objects.empty(), "a scene without objects");
    check(scene.objectCount() >= 1 && scene.objectCount() <= 100000, "object count out of range");
    for (const ffd::SceneObject& o : scene.objects) {
        check(o.count >= 1, "an object count below 1");
        check(o.size > 0 && o.size <= 1e4f, "a size out of range");
        check(!o.mesh.empty() || !o.meshFile.empty(), "an object without a mesh");
        try {
            ffd::validate(o.body);
        } catch (const ffd::InputError&) {
            check(false, "body settings that do not validate");
        }
    }
    try {
        ffd::validate(scene.world);
    } catch (const ffd::InputError&) {
        check(false, "world settings that do not validate");
    }
    check(scene.layout.columns[0] >= 1 && scene.layout.columns[1] >= 1, "layout columns below 1");
    // Scaling the object count keeps every entry at least 1 and the total as asked (or the
    // number of entries when that is larger).
    const int entries = int(scene.objects.size());
    for (int count : {1, 3, 100}) {
        ffd::setObjectCount(scene, count);
        check(scene.objectCount() == std::max(count, entries), "setObjectCount missed its total");
    }
    return 0;
}
