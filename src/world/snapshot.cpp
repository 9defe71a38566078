// Snapshots: World::saveState and World::restoreState (ffdaabb/world.h).
//
// The bytes, every integer and float little-endian and fixed-width (floats as their IEEE-754
// bits, doubles likewise):
//
//   header (32 bytes)  "FFDSTATE", u32 format version, u32 0 (reserved), u64 payload bytes,
//                      u64 payload checksum (checksum(): FNV-1a over the payload's 64-bit
//                      words, each step's high half folded into its low half, then over its
//                      last bytes one by one)
//   payload            sections, each: u32 tag (four ASCII characters, the first in the lowest
//                      byte), u32 section version, u64 bytes, then its bytes. Every section
//                      below appears once, in any order; a tag this build does not know is
//                      refused (a state it cannot reproduce), so adding state means adding a
//                      section to kSections.
//
//   BILD  the build that saved it: library version, format version, compiler, build type,
//         architecture (buildFingerprint); a state is restored by the same build only, since
//         any of these can change a float result
//   SCEN  the scene: the world settings (threads aside), the body count, and per body its rest
//         mesh's hash and size, its lattice, model and material settings and its layout
//         (particles, boxes, mass): checked value by value, so that a refusal names the first
//         that differs (describeScene)
//   SLOT  the handles: per slot its generation and body (or none), then the free slots in order
//   FRAM  the frame counter
//   BODY  per body: the half kick still due, the pending force, the initial pose of its
//         settings (position, rotation, velocity, angular velocity: part of the state, so not
//         compared)
//   PART  per particle: position, velocity, pending force, the shape-matching warm starts
//         (rotation and last substep's rotation step)
//   NODE  per box: its 8 nodes and its bounds, as of the last node update
//   VERT  the mesh vertices
//   COLB  per body, what the collision stages last found of it: placed since the last
//         substep (the overlap recovery), bounds, fastest particle, mean velocity, spread,
//         bounding sphere
//   CLAM  the box pairs' claims of the last substep (object_contacts.cpp: they bound the next)
//   OVLP  the overlap recovery's remembered pairs (overlap_recovery.h)
//   SLEP  sleeping (world/sleeping.h): each body asleep or not, its island and quiet time
//   PINS  the pins (world/pins.h): handles, points, targets, settings, last impulse and force
//
// A restore reads and checks every section into a staging copy before it changes anything,
// then swaps it in: a refused state leaves the world as it was.
#include "collision/overlap_recovery.h"
#include "ffdaabb/error.h"
#include "world/pins.h"
#include "world/settings_table.h"
#include "world/sleeping.h"
#include "world/world_data.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <type_traits>

#ifndef FFD_VERSION
#define FFD_VERSION "unknown"
#endif
#ifndef FFD_BUILD_TYPE
#define FFD_BUILD_TYPE "unknown"
#endif

namespace ffd {

using detail::BodyRecord;
using detail::WorldData;

namespace {

constexpr char kMagic[8] = {'F', 'F', 'D', 'S', 'T', 'A', 'T', 'E'};
constexpr uint32_t kFormatVersion = 2;
constexpr size_t kHeaderBytes = 32;
constexpr bool kLittle = std::endian::native == std::endian::little;

constexpr uint32_t tagOf(const char (&name)[5]) {
    return uint32_t(uint8_t(name[0])) | uint32_t(uint8_t(name[1])) << 8 |
           uint32_t(uint8_t(name[2])) << 16 | uint32_t(uint8_t(name[3])) << 24;
}

std::string tagName(uint32_t tag) {
    std::string s;
    for (int i = 0; i < 4; ++i) {
        const char c = char((tag >> (8 * i)) & 0xFF);
        s += c >= 0x20 && c < 0x7F ? c : '?';
    }
    return s;
}

[[noreturn]] void refuse(const std::string& problem) {
    throw InputError("state", problem);
}

// The shortest text that reads back as the same value (as the same float, for a float's value).
std::string num(double v) {
    const bool isFloat = double(float(v)) == v;
    char buf[64];
    for (int digits = 6; digits <= 17; ++digits) {
        std::snprintf(buf, sizeof buf, "%.*g", digits, v);
        const double back = std::strtod(buf, nullptr);
        if (isFloat ? float(back) == float(v) : back == v) break;
    }
    return buf;
}

// The build, as far as it can change a float result.
std::string buildFingerprint() {
    std::string s = "ffdaabb " FFD_VERSION ", state format " + std::to_string(kFormatVersion);
#if defined(__clang__)
    s += ", Clang " __clang_version__;
#elif defined(__GNUC__)
    s += ", GCC " __VERSION__;
#else
    s += ", another compiler";
#endif
    s += ", " FFD_BUILD_TYPE;
#if defined(__x86_64__)
    s += ", x86-64";
#elif defined(__aarch64__)
    s += ", arm64";
#else
    s += ", another architecture";
#endif
#if defined(__AVX512F__)
    s += " avx512f";
#endif
#if defined(__AVX2__)
    s += " avx2";
#endif
#if defined(__FMA__)
    s += " fma";
#endif
#if defined(__FAST_MATH__)
    s += " fast-math";
#endif
    return s;
}

// FNV-1a over 64-bit little-endian words, each step's high half folded into its low half, then
// over the last bytes one by one: a change within one word is always detected (each step is a
// bijection of the running value). Without the fold (format 1) a product carries a change only
// upwards, so a flip in a word's high bits changed only the top bits of the sum and two flips of
// the same high bit in two words cancelled one time in about 64 (format 2).
uint64_t checksum(std::span<const uint8_t> bytes) {
    constexpr uint64_t kPrime = 1099511628211ull;
    uint64_t h = 14695981039346656037ull;
    size_t i = 0;
    for (; i + 8 <= bytes.size(); i += 8) {
        uint64_t word;
        std::memcpy(&word, bytes.data() + i, 8);
        if constexpr (!kLittle) word = __builtin_bswap64(word);
        h = (h ^ word) * kPrime;
        h ^= h >> 32;
    }
    for (; i < bytes.size(); ++i) h = (h ^ bytes[i]) * kPrime;
    return h;
}

template <class T>
[[maybe_unused]] constexpr size_t kFloatsOf = sizeof(T) / sizeof(float);
template <class T>
constexpr bool kFloatRecord =
    std::is_same_v<T, Vec3> || std::is_same_v<T, Quat> || std::is_same_v<T, Aabb>;
static_assert(sizeof(Vec3) == 3 * sizeof(float) && sizeof(Quat) == 4 * sizeof(float) &&
              sizeof(Aabb) == 6 * sizeof(float));

// Appends the encoding to a byte vector.
class Writer {
public:
    explicit Writer(std::vector<uint8_t>& out) : out_(out) {}

    void u8(uint8_t v) { out_.push_back(v); }
    void u32(uint32_t v) {
        for (int i = 0; i < 4; ++i) out_.push_back(uint8_t(v >> (8 * i)));
    }
    void u64(uint64_t v) {
        for (int i = 0; i < 8; ++i) out_.push_back(uint8_t(v >> (8 * i)));
    }
    void f32(float v) { u32(std::bit_cast<uint32_t>(v)); }
    void f64(double v) { u64(std::bit_cast<uint64_t>(v)); }
    void vec3(Vec3 v) { f32(v.x), f32(v.y), f32(v.z); }
    void quat(Quat q) { f32(q.w), f32(q.x), f32(q.y), f32(q.z); }
    void aabb(const Aabb& b) { vec3(b.lo), vec3(b.hi); }
    void text(const std::string& s) {
        u32(uint32_t(s.size()));
        out_.insert(out_.end(), s.begin(), s.end());
    }
    /// Records of floats (Vec3, Quat, Aabb), without a count.
    template <class T>
    void records(const std::vector<T>& v) {
        static_assert(kFloatRecord<T>);
        if constexpr (kLittle) {
            const auto* p = reinterpret_cast<const uint8_t*>(v.data());
            out_.insert(out_.end(), p, p + v.size() * sizeof(T));
        } else {
            for (const T& r : v) {
                float f[kFloatsOf<T>];
                std::memcpy(f, &r, sizeof(T));
                for (float x : f) f32(x);
            }
        }
    }

    /// Starts a section; returns where its length goes (end it with endSection).
    size_t beginSection(uint32_t tag, uint32_t version) {
        u32(tag);
        u32(version);
        const size_t at = out_.size();
        u64(0);
        return at;
    }
    void endSection(size_t at) {
        const uint64_t bytes = out_.size() - at - 8;
        for (int i = 0; i < 8; ++i) out_[at + size_t(i)] = uint8_t(bytes >> (8 * i));
    }

private:
    std::vector<uint8_t>& out_;
};

// Reads one section's bytes; anything that does not fit is refused as malformed.
class Reader {
public:
    Reader(std::span<const uint8_t> bytes, uint32_t tag) : bytes_(bytes), tag_(tag) {}

    [[noreturn]] void malformed(const std::string& what) const {
        refuse("malformed: section " + tagName(tag_) + " " + what);
    }
    void need(uint64_t n) const {
        if (n > bytes_.size() - at_) malformed("ends early");
    }
    /// Room for `count` records of `size` bytes (a count read from the bytes).
    void need(uint64_t count, size_t size) const {
        if (count > (bytes_.size() - at_) / size) malformed("ends early");
    }
    uint8_t u8() {
        need(1);
        return bytes_[at_++];
    }
    bool flag() {
        const uint8_t v = u8();
        if (v > 1) malformed("holds a flag that is neither 0 nor 1");
        return v == 1;
    }
    uint32_t u32() {
        need(4);
        uint32_t v = 0;
        for (int i = 0; i < 4; ++i) v |= uint32_t(bytes_[at_++]) << (8 * i);
        return v;
    }
    uint64_t u64() {
        need(8);
        uint64_t v = 0;
        for (int i = 0; i < 8; ++i) v |= uint64_t(bytes_[at_++]) << (8 * i);
        return v;
    }
    float f32() { return std::bit_cast<float>(u32()); }
    double f64() { return std::bit_cast<double>(u64()); }
    Vec3 vec3() {
        Vec3 v;
        v.x = f32(), v.y = f32(), v.z = f32();
        return v;
    }
    Quat quat() {
        Quat q;
        q.w = f32(), q.x = f32(), q.y = f32(), q.z = f32();
        return q;
    }
    Aabb aabb() {
        Aabb b;
        b.lo = vec3(), b.hi = vec3();
        return b;
    }
    std::string text() {
        const uint32_t n = u32();
        need(n);
        std::string s(reinterpret_cast<const char*>(bytes_.data() + at_), n);
        at_ += n;
        return s;
    }
    /// A count, which must be `expected` (the world's).
    uint64_t count(uint64_t expected, const char* what) {
        const uint64_t n = u64();
        if (n != expected)
            malformed("holds " + std::to_string(n) + " " + what + " (expected " +
                      std::to_string(expected) + ")");
        return n;
    }
    /// `n` records of floats into `out`.
    template <class T>
    void records(std::vector<T>& out, size_t n) {
        static_assert(kFloatRecord<T>);
        need(n, sizeof(T));
        out.resize(n);
        if constexpr (kLittle) {
            std::memcpy(static_cast<void*>(out.data()), bytes_.data() + at_, n * sizeof(T));
            at_ += n * sizeof(T);
        } else {
            for (T& r : out) {
                float f[kFloatsOf<T>];
                for (float& x : f) x = f32();
                std::memcpy(&r, f, sizeof(T));
            }
        }
    }
    void end() const {
        if (at_ != bytes_.size())
            malformed("has " + std::to_string(bytes_.size() - at_) + " bytes left over");
    }

private:
    std::span<const uint8_t> bytes_;
    size_t at_ = 0;
    uint32_t tag_;
};

bool finite(float v) {
    return std::isfinite(v);
}
bool finite(Vec3 v) {
    return isFinite(v);
}
bool finite(const Quat& q) {
    return std::isfinite(q.w) && std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z);
}
bool finite(const Aabb& b) {
    return isFinite(b.lo) && isFinite(b.hi);
}

// Refuses the first record of `values` that is not finite.
template <class T>
void requireFinite(const Reader& in, const std::vector<T>& values, const char* what) {
    for (size_t i = 0; i < values.size(); ++i)
        if (!finite(values[i]))
            in.malformed("holds a non-finite " + std::string(what) + " (" + std::to_string(i) +
                         ")");
}

// --- the scene -------------------------------------------------------------------------------

// What a state must be restored into: named values, compared one by one.
struct SceneDescription {
    std::vector<std::string> worldNames;
    std::vector<double> worldValues;
    std::vector<std::string> bodyNames;
    std::vector<uint64_t> meshHash; ///< per body
    std::vector<double> bodyValues; ///< per body, bodyNames.size() each
};

SceneDescription describeScene(const WorldData& w) {
    SceneDescription d;
    auto world = [&](std::string name, double value) {
        d.worldNames.push_back(std::move(name));
        d.worldValues.push_back(value);
    };
    const auto ranges = worldSettingRanges();
    const auto members = detail::worldSettingMembers();
    for (size_t i = 0; i < ranges.size(); ++i)
        if (std::string_view(ranges[i].field) != "threads") // results do not depend on it
            world(ranges[i].field, detail::settingValue(w.settings, members[i]));
    world("gravity.x", w.settings.gravity.x);
    world("gravity.y", w.settings.gravity.y);
    world("gravity.z", w.settings.gravity.z);
    world("floor", w.settings.floor);
    world("mode", double(w.settings.mode));
    world("meshUpdate", w.settings.meshUpdate);
    // The plane colliders are part of the scene: a state steps on alike only between the same
    // planes (their count, then their normals, offsets and removals, by a checksum).
    uint64_t planes = 0;
    for (const auto& [plane, live] : w.planeSlots) {
        const float v[5] = {plane.normal.x, plane.normal.y, plane.normal.z, plane.offset,
                            live ? 1.0f : 0.0f};
        planes = planes * 0x100000001B3ull ^
                 checksum(std::span(reinterpret_cast<const uint8_t*>(v), sizeof v));
    }
    world("planes", double(w.planeSlots.size()));
    world("planes.layout", double(planes >> 11)); // 53 bits: exact in a double

    d.bodyNames = {"mesh.vertices",
                   "mesh.triangles",
                   "lattice.cellSize",
                   "lattice.resolution",
                   "lattice.targetCells",
                   "lattice.fillInterior",
                   "lattice.boxSkin",
                   "model",
                   "regionDamping",
                   "allowSleep",
                   "motion"};
    for (const SettingRange& r : bodySettingRanges()) d.bodyNames.push_back(r.field);
    for (const char* name : {"particles", "boxes", "massKg", "cellSizeM"})
        d.bodyNames.push_back(name);
    const auto bodyMembers = detail::bodySettingMembers();
    std::map<const detail::BodyModel*, uint64_t> hashes; // bodies of a model share its mesh
    for (const BodyRecord& r : w.bodies) {
        const TriangleMesh& mesh = r.model->mesh;
        auto [it, added] = hashes.emplace(r.model.get(), 0);
        if (added) {
            const auto bytes = [](const auto& v) {
                return std::span(reinterpret_cast<const uint8_t*>(v.data()),
                                 v.size() * sizeof(v[0]));
            };
            it->second = checksum(bytes(mesh.positions)) ^
                         (checksum(bytes(mesh.triangles)) * 0x9E3779B97F4A7C15ull);
        }
        d.meshHash.push_back(it->second);
        const BodySettings& s = r.settings;
        for (const double v : {double(mesh.positions.size()), double(mesh.triangles.size()),
                               double(s.lattice.cellSize), double(s.lattice.resolution),
                               double(s.lattice.targetCells), double(s.lattice.fillInterior),
                               double(s.lattice.boxSkin), double(s.model), double(s.regionDamping),
                               double(s.allowSleep), double(s.motion)})
            d.bodyValues.push_back(v);
        for (const auto& m : bodyMembers) d.bodyValues.push_back(detail::settingValue(s, m));
        for (const double v :
             {double(r.particleCount), double(r.boxCount), double(r.mass), double(r.cellSize)})
            d.bodyValues.push_back(v);
    }
    return d;
}

void writeScene(const WorldData& w, Writer& out) {
    const SceneDescription d = describeScene(w);
    out.u32(uint32_t(d.worldNames.size()));
    for (size_t i = 0; i < d.worldNames.size(); ++i) {
        out.text(d.worldNames[i]);
        out.f64(d.worldValues[i]);
    }
    out.u32(uint32_t(d.bodyNames.size()));
    for (const std::string& name : d.bodyNames) out.text(name);
    out.u32(uint32_t(d.meshHash.size()));
    for (size_t b = 0; b < d.meshHash.size(); ++b) {
        out.u64(d.meshHash[b]);
        for (size_t k = 0; k < d.bodyNames.size(); ++k)
            out.f64(d.bodyValues[b * d.bodyNames.size() + k]);
    }
}

// A value as the messages show it.
std::string valueText(const std::string& name, double v) {
    if (name == "mode" && v >= 0 && v <= 3) return toString(CollisionMode(int(v)));
    if (name == "planes.layout") return "(other normals or offsets: checksum " + num(v) + ")";
    if (name == "model" && (v == 0 || v == 1)) return toString(DynamicsModel(int(v)));
    if (name == "motion" && v >= 0 && v <= 2) return toString(BodyMotion(int(v)));
    if (name == "floor" || name == "meshUpdate" || name == "regionDamping" ||
        name == "allowSleep" || name == "lattice.fillInterior")
        return v != 0 ? "on" : "off";
    return num(v);
}

bool same(double a, double b) {
    return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b);
}

// Refuses a state whose scene is not this world's, naming the first difference.
void checkScene(Reader& in, const WorldData& w) {
    const SceneDescription here = describeScene(w);
    const uint32_t worldCount = in.u32();
    if (worldCount != here.worldNames.size())
        in.malformed("lists " + std::to_string(worldCount) + " world settings (expected " +
                     std::to_string(here.worldNames.size()) + ")");
    std::vector<double> worldValues(worldCount);
    for (uint32_t i = 0; i < worldCount; ++i) {
        if (in.text() != here.worldNames[i])
            in.malformed("names another world setting than " + here.worldNames[i]);
        worldValues[i] = in.f64();
    }
    const uint32_t fieldCount = in.u32();
    if (fieldCount != here.bodyNames.size())
        in.malformed("lists " + std::to_string(fieldCount) + " body settings (expected " +
                     std::to_string(here.bodyNames.size()) + ")");
    for (uint32_t k = 0; k < fieldCount; ++k)
        if (in.text() != here.bodyNames[k])
            in.malformed("names another body setting than " + here.bodyNames[k]);
    const uint32_t bodies = in.u32();
    if (bodies != w.bodies.size())
        refuse("saved from a scene of " + std::to_string(bodies) + " bodies, this world has " +
               std::to_string(w.bodies.size()));
    for (uint32_t i = 0; i < worldCount; ++i)
        if (!same(worldValues[i], here.worldValues[i]))
            refuse("saved with the world setting " + here.worldNames[i] + " " +
                   valueText(here.worldNames[i], worldValues[i]) + ", this world has " +
                   valueText(here.worldNames[i], here.worldValues[i]));
    for (uint32_t b = 0; b < bodies; ++b) {
        const uint64_t mesh = in.u64();
        const std::string body = "body " + std::to_string(b) + " (of " + std::to_string(bodies) +
                                 ", in the order added)";
        // The sizes first: they say more than a hash.
        for (uint32_t k = 0; k < fieldCount; ++k) {
            const double saved = in.f64();
            const double v = here.bodyValues[size_t(b) * fieldCount + k];
            if (!same(saved, v))
                refuse("saved with " + body + " of " + here.bodyNames[k] + " " +
                       valueText(here.bodyNames[k], saved) + ", this world has " +
                       valueText(here.bodyNames[k], v));
            if (k == 1 && mesh != here.meshHash[b])
                refuse("saved with " + body +
                       " made from another mesh (the same size, other vertices or triangles)");
        }
    }
    in.end();
}

// --- the dynamic state -----------------------------------------------------------------------

// Everything a restore writes, read and checked before the world is touched.
struct Staged {
    uint64_t frame = 0;
    std::vector<detail::Slot> slots;
    std::vector<uint32_t> freeSlots;
    std::vector<uint32_t> bodySlot;
    struct Body {
        bool halfKick = false;
        Vec3 force, position, velocity, angularVelocity;
        Quat rotation;
    };
    std::vector<Body> bodies;
    std::vector<Vec3> x, v, particleForce;
    std::vector<Quat> rotations, rotationSteps;
    std::vector<Vec3> nodes;
    std::vector<Aabb> boxBounds;
    std::vector<Vec3> vertices;
    struct Sleep {
        bool asleep = false;
        float quietTime = 0;
        uint32_t island = 0;
    };
    std::vector<Sleep> sleep;
    uint32_t nextIsland = 1;
    detail::PinState pins;
    struct Collision {
        bool placed = false;
        Aabb bounds;
        float maxSpeed = 0, spread = 0, sphereRadius = 0;
        Vec3 meanVelocity, sphereCentre;
    };
    std::vector<Collision> collision;
    std::vector<detail::BoxPairClaim> claims;
    std::vector<detail::OverlapPair> overlaps;
};

void writeBuild(const WorldData&, Writer& out) {
    out.text(buildFingerprint());
}

void checkBuild(Reader& in, const WorldData&, Staged&) {
    const std::string saved = in.text();
    in.end();
    const std::string here = buildFingerprint();
    if (saved != here) refuse("saved by another build (" + saved + "); this is " + here);
}

void readScene(Reader& in, const WorldData& w, Staged&) {
    checkScene(in, w);
}

void writeSlots(const WorldData& w, Writer& out) {
    out.u32(uint32_t(w.slots.size()));
    for (const detail::Slot& s : w.slots) out.u32(s.generation), out.u32(s.dense);
    out.u32(uint32_t(w.freeSlots.size()));
    for (const uint32_t s : w.freeSlots) out.u32(s);
}

void readSlots(Reader& in, const WorldData& w, Staged& st) {
    const uint32_t count = in.u32();
    in.need(count, 8);
    const size_t n = w.bodies.size();
    st.slots.resize(count);
    st.bodySlot.assign(n, UINT32_MAX);
    size_t free = 0;
    for (uint32_t s = 0; s < count; ++s) {
        st.slots[s].generation = in.u32();
        st.slots[s].dense = in.u32();
        const uint32_t dense = st.slots[s].dense;
        if (dense == UINT32_MAX) {
            ++free;
            continue;
        }
        if (dense >= n || st.bodySlot[dense] != UINT32_MAX)
            in.malformed("gives slot " + std::to_string(s) + " body " + std::to_string(dense) +
                         ", which is out of range or in another slot");
        st.bodySlot[dense] = s;
    }
    if (std::find(st.bodySlot.begin(), st.bodySlot.end(), UINT32_MAX) != st.bodySlot.end())
        in.malformed("leaves a body without a slot");
    const uint32_t freeCount = in.u32();
    if (freeCount != free)
        in.malformed("lists " + std::to_string(freeCount) + " free slots (expected " +
                     std::to_string(free) + ")");
    in.need(freeCount, 4);
    st.freeSlots.resize(freeCount);
    std::vector<uint8_t> listed(count, 0);
    for (uint32_t& s : st.freeSlots) {
        s = in.u32();
        if (s >= count || st.slots[s].dense != UINT32_MAX || listed[s])
            in.malformed("lists slot " + std::to_string(s) +
                         " as free, which is out of range, taken or listed twice");
        listed[s] = 1;
    }
    in.end();
}

void writeFrame(const WorldData& w, Writer& out) {
    out.u64(w.frame);
}

void readFrame(Reader& in, const WorldData&, Staged& st) {
    st.frame = in.u64();
    in.end();
}

void writeBodies(const WorldData& w, Writer& out) {
    out.u32(uint32_t(w.bodies.size()));
    for (const BodyRecord& r : w.bodies) {
        out.u8(r.halfKick);
        out.vec3(r.force);
        out.vec3(r.settings.position);
        out.quat(r.settings.rotation);
        out.vec3(r.settings.velocity);
        out.vec3(r.settings.angularVelocity);
    }
}

void readBodies(Reader& in, const WorldData& w, Staged& st) {
    if (in.u32() != w.bodies.size()) in.malformed("holds another number of bodies");
    st.bodies.resize(w.bodies.size());
    for (Staged::Body& b : st.bodies) {
        b.halfKick = in.flag();
        b.force = in.vec3();
        b.position = in.vec3();
        b.rotation = in.quat();
        b.velocity = in.vec3();
        b.angularVelocity = in.vec3();
        if (!finite(b.force) || !finite(b.position) || !finite(b.rotation) || !finite(b.velocity) ||
            !finite(b.angularVelocity))
            in.malformed("holds a non-finite force or pose");
    }
    in.end();
}

void writeParticles(const WorldData& w, Writer& out) {
    out.u64(w.x.size());
    out.records(w.x);
    out.records(w.v);
    out.records(w.particleForce);
    out.records(w.rotations);
    out.records(w.rotationSteps);
}

void readParticles(Reader& in, const WorldData& w, Staged& st) {
    const size_t n = in.count(w.x.size(), "particles");
    in.records(st.x, n);
    in.records(st.v, n);
    in.records(st.particleForce, n);
    in.records(st.rotations, n);
    in.records(st.rotationSteps, n);
    in.end();
    requireFinite(in, st.x, "position");
    requireFinite(in, st.v, "velocity");
    requireFinite(in, st.particleForce, "force");
    requireFinite(in, st.rotations, "rotation");
    requireFinite(in, st.rotationSteps, "rotation step");
}

void writeNodes(const WorldData& w, Writer& out) {
    out.u64(w.boxBounds.size());
    out.records(w.nodes);
    out.records(w.boxBounds);
}

void readNodes(Reader& in, const WorldData& w, Staged& st) {
    const size_t n = in.count(w.boxBounds.size(), "boxes");
    in.records(st.nodes, n * 8);
    in.records(st.boxBounds, n);
    in.end();
    requireFinite(in, st.nodes, "node");
    requireFinite(in, st.boxBounds, "box bound");
}

void writeVertices(const WorldData& w, Writer& out) {
    out.u64(w.vertices.size());
    out.records(w.vertices);
}

void readVertices(Reader& in, const WorldData& w, Staged& st) {
    in.records(st.vertices, in.count(w.vertices.size(), "vertices"));
    in.end();
    requireFinite(in, st.vertices, "vertex");
}

void writeCollisionBodies(const WorldData& w, Writer& out) {
    out.u32(uint32_t(w.collision.bodies.size()));
    for (const detail::CollisionBody& c : w.collision.bodies) {
        out.u8(c.placed);
        out.aabb(c.bounds);
        out.f32(c.maxSpeed);
        out.vec3(c.meanVelocity);
        out.f32(c.spread);
        out.vec3(c.sphereCentre);
        out.f32(c.sphereRadius);
    }
}

void readCollisionBodies(Reader& in, const WorldData& w, Staged& st) {
    if (in.u32() != w.bodies.size()) in.malformed("holds another number of bodies");
    st.collision.resize(w.bodies.size());
    for (Staged::Collision& c : st.collision) {
        c.placed = in.flag();
        c.bounds = in.aabb();
        c.maxSpeed = in.f32();
        c.meanVelocity = in.vec3();
        c.spread = in.f32();
        c.sphereCentre = in.vec3();
        c.sphereRadius = in.f32();
    }
    in.end();
}

void writeClaims(const WorldData& w, Writer& out) {
    out.u64(w.collision.claims.size());
    for (const detail::BoxPairClaim& c : w.collision.claims) {
        out.u64(c.key);
        out.f32(c.claimed);
        out.f32(c.deepest);
    }
}

void readClaims(Reader& in, const WorldData& w, Staged& st) {
    const uint64_t count = in.u64();
    in.need(count, 16);
    st.claims.resize(size_t(count));
    const uint64_t boxes = w.boxBounds.size();
    for (size_t i = 0; i < st.claims.size(); ++i) {
        detail::BoxPairClaim& c = st.claims[i];
        c.key = in.u64();
        c.claimed = in.f32();
        c.deepest = in.f32();
        const uint64_t low = c.key >> 32, high = c.key & 0xFFFFFFFFu;
        if (!(low < high && high < boxes) || w.collision.boxBody[low] == w.collision.boxBody[high])
            in.malformed("holds a claim of boxes that are not a pair of two bodies' boxes");
        if (i > 0 && !(st.claims[i - 1].key < c.key)) in.malformed("holds claims out of order");
        if (!finite(c.claimed) || !finite(c.deepest)) in.malformed("holds a non-finite claim");
    }
    in.end();
}

void writeOverlaps(const WorldData& w, Writer& out) {
    out.u64(w.collision.overlaps.size());
    for (const detail::OverlapPair& p : w.collision.overlaps) {
        out.u32(p.a);
        out.u32(p.b);
        out.u8(p.whole);
        out.u8(p.deep);
        out.u8(p.confirmed);
        out.f32(p.out.x);
        out.f32(p.out.y);
        out.f32(p.out.z);
        out.f32(p.depth);
    }
}

void readOverlaps(Reader& in, const WorldData& w, Staged& st) {
    const uint64_t count = in.u64();
    in.need(count, 27);
    st.overlaps.resize(size_t(count));
    const uint32_t n = uint32_t(w.bodies.size());
    for (size_t i = 0; i < st.overlaps.size(); ++i) {
        detail::OverlapPair& p = st.overlaps[i];
        p.a = in.u32();
        p.b = in.u32();
        p.whole = in.flag();
        p.deep = in.flag();
        p.confirmed = in.flag();
        p.out.x = in.f32();
        p.out.y = in.f32();
        p.out.z = in.f32();
        p.depth = in.f32();
        if (!finite(p.out) || !finite(p.depth) || p.depth < 0)
            in.malformed("holds a non-finite or negative way out");
        if (!(p.a < n && ((p.b < n && p.a < p.b) || p.b == detail::kFloorBody)))
            in.malformed("holds a pair of bodies out of range");
        auto key = [](const detail::OverlapPair& q) { return uint64_t(q.a) << 32 | q.b; };
        if (i > 0 && !(key(st.overlaps[i - 1]) < key(p))) in.malformed("holds pairs out of order");
    }
    in.end();
}

// Sleeping (world/sleeping.h): who sleeps, with whom, and how long the awake have been quiet.
void writeSleep(const WorldData& w, Writer& out) {
    out.u32(w.nextIsland);
    out.u32(uint32_t(w.bodies.size()));
    for (const BodyRecord& r : w.bodies) {
        out.u8(r.asleep);
        out.f32(r.quietTime);
        out.u32(r.island);
    }
}

void readSleep(Reader& in, const WorldData& w, Staged& st) {
    st.nextIsland = in.u32();
    if (st.nextIsland == 0) in.malformed("holds island number 0 as the next");
    if (in.u32() != w.bodies.size()) in.malformed("holds another number of bodies");
    st.sleep.resize(w.bodies.size());
    for (Staged::Sleep& b : st.sleep) {
        b.asleep = in.flag();
        b.quietTime = in.f32();
        b.island = in.u32();
        if (!std::isfinite(b.quietTime) || b.quietTime < 0)
            in.malformed("holds a quiet time that is negative or not finite");
        if (b.asleep != (b.island != 0)) in.malformed("holds a sleeper without an island");
    }
    in.end();
}

// Pins (world/pins.h): their handles, points, targets, settings and what they did last.
void writePins(const WorldData& w, Writer& out) {
    const detail::PinState& p = w.pins;
    out.u32(uint32_t(p.slots.size()));
    for (const detail::PinSlot& s : p.slots) out.u32(s.generation), out.u32(s.dense);
    out.u32(uint32_t(p.freeSlots.size()));
    for (const uint32_t s : p.freeSlots) out.u32(s);
    out.u32(uint32_t(p.list.size()));
    for (const detail::Pin& pin : p.list) {
        out.u32(pin.slot);
        out.u32(pin.body.index);
        out.u32(pin.body.generation);
        for (int k = 0; k < 8; ++k) out.u32(pin.particle[k]), out.f32(pin.weight[k]);
        for (const Vec3 v :
             {pin.target, pin.start, pin.followed, pin.previous, pin.impulse, pin.force})
            out.vec3(v);
        const PinSettings& s = pin.settings;
        for (const float f : {s.stiffness, s.rigidity, s.swingDamping, s.maxSpeed}) out.f32(f);
    }
}

void readPins(Reader& in, const WorldData& w, Staged& st) {
    detail::PinState& p = st.pins;
    const uint32_t slots = in.u32();
    in.need(slots, 8);
    p.slots.resize(slots);
    for (detail::PinSlot& s : p.slots) s.generation = in.u32(), s.dense = in.u32();
    const uint32_t freeCount = in.u32();
    in.need(freeCount, 4);
    p.freeSlots.resize(freeCount);
    for (uint32_t& s : p.freeSlots) {
        s = in.u32();
        if (s >= slots || p.slots[s].dense != UINT32_MAX)
            in.malformed("lists a pin slot in use as free");
    }
    const uint32_t count = in.u32();
    in.need(count, 4);
    p.list.resize(count);
    for (uint32_t i = 0; i < count; ++i) {
        detail::Pin& pin = p.list[i];
        pin.slot = in.u32();
        pin.body.index = in.u32();
        pin.body.generation = in.u32();
        if (pin.slot >= slots || p.slots[pin.slot].dense != i)
            in.malformed("holds pin " + std::to_string(i) + " in a slot that is not its own");
        // Its body, among the bodies as the state has them (the slots read before).
        const bool bodyValid = pin.body.index < st.slots.size() &&
                               st.slots[pin.body.index].dense != UINT32_MAX &&
                               st.slots[pin.body.index].generation == pin.body.generation;
        if (!bodyValid) in.malformed("holds pin " + std::to_string(i) + " of no body");
        const uint32_t particles = w.bodies[st.slots[pin.body.index].dense].particleCount;
        for (int k = 0; k < 8; ++k) {
            pin.particle[k] = in.u32();
            pin.weight[k] = in.f32();
            if (pin.particle[k] >= particles || !std::isfinite(pin.weight[k]))
                in.malformed("holds pin " + std::to_string(i) + " of a point not on its body");
        }
        for (Vec3* v :
             {&pin.target, &pin.start, &pin.followed, &pin.previous, &pin.impulse, &pin.force}) {
            *v = in.vec3();
            if (!finite(*v)) in.malformed("holds a pin with a non-finite target or force");
        }
        PinSettings& s = pin.settings;
        for (float* f : {&s.stiffness, &s.rigidity, &s.swingDamping, &s.maxSpeed}) *f = in.f32();
        try {
            validate(s);
        } catch (const InputError&) {
            in.malformed("holds pin " + std::to_string(i) + " with settings out of range");
        }
    }
    in.end();
}

struct Section {
    uint32_t tag;
    uint32_t version;
    void (*write)(const WorldData&, Writer&);
    void (*read)(Reader&, const WorldData&, Staged&);
};

// In the order they are written and checked: the build, then the scene, then the state.
constexpr Section kSections[] = {
    {tagOf("BILD"), 1, writeBuild, checkBuild},
    {tagOf("SCEN"), 1, writeScene, readScene},
    {tagOf("SLOT"), 1, writeSlots, readSlots},
    {tagOf("FRAM"), 1, writeFrame, readFrame},
    {tagOf("BODY"), 1, writeBodies, readBodies},
    {tagOf("PART"), 1, writeParticles, readParticles},
    {tagOf("NODE"), 1, writeNodes, readNodes},
    {tagOf("VERT"), 1, writeVertices, readVertices},
    {tagOf("COLB"), 1, writeCollisionBodies, readCollisionBodies},
    {tagOf("CLAM"), 1, writeClaims, readClaims},
    {tagOf("OVLP"), 2, writeOverlaps, readOverlaps},
    {tagOf("SLEP"), 1, writeSleep, readSleep},
    {tagOf("PINS"), 1, writePins, readPins},
};

// Writes the staged state into the world (nothing here can fail).
void apply(WorldData& w, Staged& st) {
    w.frame = st.frame;
    w.slots.swap(st.slots);
    w.freeSlots.swap(st.freeSlots);
    for (size_t b = 0; b < w.bodies.size(); ++b) {
        BodyRecord& r = w.bodies[b];
        const Staged::Body& s = st.bodies[b];
        r.slot = st.bodySlot[b];
        r.halfKick = s.halfKick;
        r.force = s.force;
        r.settings.position = s.position;
        r.settings.rotation = s.rotation;
        r.settings.velocity = s.velocity;
        r.settings.angularVelocity = s.angularVelocity;
        r.asleep = st.sleep[b].asleep;
        r.quietTime = st.sleep[b].quietTime;
        r.island = st.sleep[b].island;
        detail::CollisionBody& c = w.collision.bodies[b];
        const Staged::Collision& sc = st.collision[b];
        c.placed = sc.placed;
        c.bounds = sc.bounds;
        c.maxSpeed = sc.maxSpeed;
        c.meanVelocity = sc.meanVelocity;
        c.spread = sc.spread;
        c.sphereCentre = sc.sphereCentre;
        c.sphereRadius = sc.sphereRadius;
    }
    w.x.swap(st.x);
    w.v.swap(st.v);
    w.particleForce.swap(st.particleForce);
    w.rotations.swap(st.rotations);
    w.rotationSteps.swap(st.rotationSteps);
    w.nodes.swap(st.nodes);
    w.boxBounds.swap(st.boxBounds);
    w.vertices.swap(st.vertices);
    detail::CollisionState& cs = w.collision;
    cs.claims.swap(st.claims);
    cs.nextClaims.clear();
    cs.overlaps.swap(st.overlaps);
    cs.wholePairs.clear();
    cs.pairs.clear();
    cs.all.clear(); // the last step's contacts are not part of the state
    cs.objectCount = 0;
    w.nextIsland = st.nextIsland;
    w.pins.list.swap(st.pins.list);
    w.pins.slots.swap(st.pins.slots);
    w.pins.freeSlots.swap(st.pins.freeSlots);
    detail::refreshAwake(w); // the awake list, contact inverse masses, batches, flags
    w.profile = Profile{};
}

} // namespace

std::vector<uint8_t> World::saveState() const {
    const WorldData& w = *state_;
    std::vector<uint8_t> out;
    out.reserve(kHeaderBytes + 65536 + w.bodies.size() * 256 + w.x.size() * 56 +
                w.boxBounds.size() * 120 + w.vertices.size() * 12 + w.collision.claims.size() * 16 +
                w.collision.overlaps.size() * 11);
    out.resize(kHeaderBytes); // magic, version, reserved; payload bytes and checksum at the end
    std::memcpy(out.data(), kMagic, sizeof kMagic);
    for (int i = 0; i < 4; ++i) out[8 + size_t(i)] = uint8_t(kFormatVersion >> (8 * i));
    Writer payload(out);
    for (const Section& s : kSections) {
        const size_t at = payload.beginSection(s.tag, s.version);
        s.write(w, payload);
        payload.endSection(at);
    }
    const std::span<const uint8_t> body(out.data() + kHeaderBytes, out.size() - kHeaderBytes);
    const uint64_t bytes = body.size(), sum = checksum(body);
    for (int i = 0; i < 8; ++i) {
        out[16 + size_t(i)] = uint8_t(bytes >> (8 * i));
        out[24 + size_t(i)] = uint8_t(sum >> (8 * i));
    }
    return out;
}

void World::restoreState(std::span<const uint8_t> state) {
    WorldData& w = *state_;
    if (state.size() < sizeof kMagic || std::memcmp(state.data(), kMagic, sizeof kMagic) != 0)
        refuse("not an ffdaabb state (it does not start with \"FFDSTATE\")");
    if (state.size() < kHeaderBytes)
        refuse("truncated: " + std::to_string(state.size()) + " bytes, shorter than the " +
               std::to_string(kHeaderBytes) + "-byte header");
    Reader header(state.first(kHeaderBytes).subspan(sizeof kMagic), tagOf("HEAD"));
    const uint32_t version = header.u32();
    if (version != kFormatVersion)
        refuse("format version " + std::to_string(version) + ", this build reads version " +
               std::to_string(kFormatVersion));
    if (header.u32() != 0) refuse("malformed: the header's reserved field is not 0");
    const uint64_t bytes = header.u64(), sum = header.u64();
    const std::span<const uint8_t> payload = state.subspan(kHeaderBytes);
    if (payload.size() < bytes)
        refuse("truncated: the header announces " + std::to_string(bytes) +
               " bytes after it, there are " + std::to_string(payload.size()));
    if (payload.size() > bytes)
        refuse("malformed: " + std::to_string(payload.size() - bytes) +
               " bytes after the state's end (expected none)");
    if (checksum(payload) != sum) refuse("corrupted: its checksum does not match its contents");

    // The sections, each once, each known.
    std::map<uint32_t, std::pair<uint32_t, std::span<const uint8_t>>> found;
    size_t at = 0;
    while (at < payload.size()) {
        Reader frame(payload.subspan(at), tagOf("LIST"));
        const uint32_t tag = frame.u32();
        const uint32_t sectionVersion = frame.u32();
        const uint64_t length = frame.u64();
        if (length > payload.size() - at - 16)
            refuse("malformed: section " + tagName(tag) + " runs past the end");
        const bool known = std::any_of(std::begin(kSections), std::end(kSections),
                                       [&](const Section& s) { return s.tag == tag; });
        if (!known) refuse("holds a section this build does not know (" + tagName(tag) + ")");
        if (!found.emplace(tag, std::pair(sectionVersion, payload.subspan(at + 16, length))).second)
            refuse("malformed: section " + tagName(tag) + " appears twice");
        at += 16 + length;
    }
    Staged staged;
    for (const Section& s : kSections) {
        const auto it = found.find(s.tag);
        if (it == found.end()) refuse("malformed: section " + tagName(s.tag) + " is missing");
        if (it->second.first != s.version)
            refuse("section " + tagName(s.tag) + " is of version " +
                   std::to_string(it->second.first) + ", this build reads version " +
                   std::to_string(s.version));
        Reader in(it->second.second, s.tag);
        s.read(in, w, staged);
    }
    apply(w, staged);
}

} // namespace ffd
