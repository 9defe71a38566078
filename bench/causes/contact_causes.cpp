// ffdaabb_contact_causes: why mesh vertices end up inside other bodies.
//
// Steps a scene and, every N frames, finds every mesh vertex inside another body's closed mesh
// by the engine-independent measure (bench/common/interpenetration.h, generalised winding
// number) and classifies it by the first of these causes that applies, judged on the state
// after the frame (boxes recomputed from the particles then) and on the contacts of its last
// substep:
//
//   own box     the vertex lies outside its own cell's deformed box (the six face planes the
//               narrow phase uses) by more than its body's contact skin: the box no longer
//               bounds the mesh there, so no box test can see it;
//   no box      it lies in no box of the other body (within that body's skin): inside the other
//               mesh but outside all of its boxes' planes;
//   crossing    the vertex's box and a box of the other body holding it overlap, no node of
//               either lies inside the other (within the other body's contact skin) and the
//               last substep made no contact between the two boxes: edges or faces cross;
//   no contact  some node of one box lies inside the other, but the last substep made no
//               contact between the two boxes: the pair was not a candidate, or the boxes met
//               during that substep (found in the next);
//   unresolved  the last substep made a contact between the two boxes and the vertex is still
//               inside: the response did not remove it (competing contacts, too few
//               iterations, shape matching spreading the correction, a wrong way out); split by
//               how well the contacts' pushes point the way out of the other mesh, and by
//               whether those contacts' constraints hold at the frame's end (the solver did
//               its job and the contacts' geometry is what leaves the meshes overlapping) or
//               are still violated (the solver did not converge).
//
// Contacts are matched to the boxes they join (the box of A's point, B's box), so the tool
// classifies node contacts (the paper's phase 3, before 2026-11) and box-pair contacts alike.
// Prints a table per cause (vertices, share, deepest and mean depth) and writes it as JSON.
//
// The other side, on the same samples: contacts between meshes that do not touch. A contact
// joins two cells; each cell's part of its mesh lies in the cell's box and in the convex hull
// of the triangles that touch the cell (in the rest pose, by their bounds), so the two parts
// are at least as far apart along the contact's normal as the larger of the two separations
// (boxes, and those triangles' deformed vertices). A contact whose parts are apart by more than
// the skin pushes on meshes that are not there: that is how far the boxes stand off curved
// surfaces (docs/ALGORITHM.md section 2, "boxes are not tight").
//
// And, on the same frames, where the contacts' partners leave their boxes: the contacts found
// afresh on the state after the frame (the world restored afterwards, so the run goes on as
// it would have), each contact's constraint at detection, dot(pA - pB, n) - offset, against
// the distance its box pair's manifold found. They differ where B's point, kept within its
// box, is not the projection of A's point onto the reference plane (docs/ALGORITHM.md section
// 4, "Where the partner leaves the box").
#include "collision/contact.h"
#include "collision/narrow_phase.h"
#include "collision/pipeline.h"
#include "ffdaabb/scene.h"
#include "ffdaabb/world.h"
#include "interpenetration.h"
#include "json_output.h"
#include "util/atomic_file.h"
#include "world/world_data.h"

#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

using namespace ffd;

namespace {

enum Cause { kOwnBox, kNoBox, kCrossing, kNoContact, kUnresolved, kCauseCount };
constexpr const char* kCauseNames[kCauseCount] = {"own box", "no box", "crossing", "no contact",
                                                  "unresolved"};
constexpr const char* kCauseKeys[kCauseCount] = {"own_box", "no_box", "crossing", "no_contact",
                                                 "unresolved"};

struct Tally {
    long long vertices = 0;
    double maxDepth = 0, depthSum = 0;
    void add(double depth) {
        ++vertices;
        maxDepth = std::max(maxDepth, depth);
        depthSum += depth;
    }
};

// A deformed box of the world: its 8 nodes, node bounds and face planes.
struct Box {
    const Vec3* nodes;
    Aabb bounds;
    detail::BoxPlanes planes;
};

// The world's box nodes are those of the last substep's node update, before that substep's
// motion; the mesh is the frame's end. The boxes are judged on nodes and bounds recomputed from
// the particles at the frame's end, so that both describe the same instant.
struct Boxes {
    std::vector<Vec3> nodes;
    std::vector<Aabb> bounds;
};

void updateBoxes(const detail::WorldData& w, Boxes& out) {
    out.nodes.resize(w.nodes.size());
    out.bounds.resize(w.boxBounds.size());
    for (const detail::BodyRecord& r : w.bodies) {
        updateBoxNodes(
            r.model->lattice, std::span<const Vec3>(w.x.data() + r.firstParticle, r.particleCount),
            std::span<Vec3>(out.nodes.data() + size_t(r.firstBox) * 8, size_t(r.boxCount) * 8));
        for (uint32_t k = r.firstBox; k < r.firstBox + r.boxCount; ++k) {
            Aabb b;
            for (int n = 0; n < 8; ++n) b.add(out.nodes[size_t(k) * 8 + n]);
            out.bounds[k] = b;
        }
    }
}

Box boxAt(const Boxes& boxes, uint32_t box) {
    Box b{&boxes.nodes[size_t(box) * 8], boxes.bounds[box],
          detail::boxPlanes(&boxes.nodes[size_t(box) * 8])};
    return b;
}

// Whether p lies within `skin` of every face plane of the box (all six faces count).
bool holds(const Box& box, Vec3 p, float skin) {
    return detail::testNodeInBox(box.planes, box.bounds, 63, p, skin).inside;
}

// Per cell of a model's lattice, the vertices of the triangles whose rest bounds meet the cell:
// the cell's part of the mesh lies in their convex hull (the mesh is flat between its deformed
// vertices).
std::vector<std::vector<uint32_t>> cellTriangleVertices(const detail::BodyModel& model) {
    const Lattice& L = model.lattice;
    std::vector<std::vector<uint32_t>> out(L.cells.size());
    const float h = L.cellSize;
    auto gridOf = [&](float v, int axis) { return int(std::floor((v - L.origin[axis]) / h)); };
    for (const auto& t : model.mesh.triangles) {
        Aabb bounds;
        for (int k = 0; k < 3; ++k) bounds.add(model.mesh.positions[t[k]]);
        for (int k = gridOf(bounds.lo.z, 2); k <= gridOf(bounds.hi.z, 2); ++k)
            for (int j = gridOf(bounds.lo.y, 1); j <= gridOf(bounds.hi.y, 1); ++j)
                for (int i = gridOf(bounds.lo.x, 0); i <= gridOf(bounds.hi.x, 0); ++i) {
                    const uint32_t cell = L.findCell({i, j, k});
                    if (cell != UINT32_MAX) out[cell].insert(out[cell].end(), t.begin(), t.end());
                }
    }
    for (std::vector<uint32_t>& v : out) {
        std::sort(v.begin(), v.end());
        v.erase(std::unique(v.begin(), v.end()), v.end());
    }
    return out;
}

// The contacts found afresh on the samples' states, and those whose constraint at detection is
// off their manifold's distance.
struct PartnerTally {
    long long contacts = 0, over1mm = 0, over1cm = 0, shallower = 0; // of those over 1 mm
    double most = 0;                                                 // metres
};

// The contacts of the samples, and those between mesh parts apart by more than the skin.
struct ApartTally {
    long long contacts = 0, pairs = 0, apartContacts = 0, apartPairs = 0;
    long long overlapping = 0, overlappingApart = 0; // found with their boxes overlapping
};

} // namespace

int main(int argc, char** argv) {
    CLI::App app{"Classifies the mesh vertices found inside other bodies by cause"};
    std::string sceneName = "alphabets", jsonPath;
    int frames = 300, every = 10, objects = 0;
    app.add_option("--scene", sceneName, "Scene name or file (default alphabets)");
    app.add_option("--frames", frames, "Frames to step (default 300)")
        ->check(CLI::Range(1, 1000000));
    app.add_option("--every", every, "Classify every N frames (default 10)")
        ->check(CLI::Range(1, 1000000));
    app.add_option("--objects", objects, "Object count (default: the scene's)")
        ->check(CLI::Range(0, 100000));
    app.add_option("--json", jsonPath, "Write the table as JSON to this file");
    CLI11_PARSE(app, argc, argv);

    Scene scene;
    std::optional<AtomicFile> jsonFile; // opened first: a bad path fails before the run
    try {
        scene = loadScene(sceneName);
        if (objects > 0) setObjectCount(scene, objects);
        if (!jsonPath.empty()) jsonFile.emplace(jsonPath, "w");
    } catch (const std::exception& e) {
        fmt::print(stderr, "ffdaabb_contact_causes: {}\n", e.what());
        return 2;
    }
    SceneBuild build = buildScene(scene);
    World& world = build.world;
    detail::WorldData& w = detail::dataOf(world);
    std::vector<bench::MeshView> views;
    std::vector<const detail::BodyRecord*> records;
    for (BodyId id : build.bodies) {
        views.push_back({world.vertices(id), world.triangles(id)});
        records.push_back(w.find(id));
    }
    float largest = 0;
    for (const SceneObject& o : scene.objects) largest = std::max(largest, o.size);
    bench::InterpenetrationSettings settings;
    settings.referenceSize = largest;

    std::array<Tally, kCauseCount> total{};
    Boxes now;
    Tally ownBoxExcess; // of the own-box vertices: how far outside their box, in cells
    // Of the unresolved ones, by the best alignment of their contacts' pushes with the way out
    // (cosine below 0, 0 to 0.7, 0.7 and above).
    std::array<Tally, 3> way{};
    // Of the unresolved ones, whether their contacts hold at the frame's end (the most violated
    // one within a tenth of the skin) or are still violated.
    std::array<Tally, 2> held{};
    // Of the no-contact ones, whether the last substep tested the box pair and found no contact
    // (apart along its planes by the margin, or the clipped face beyond it) or never tested it
    // (no node came within the margin of the other box, or the pair was no candidate).
    std::array<Tally, 2> tested{};
    std::vector<Vec3> pushes;
    // Each model's cells' triangle vertices (bodyParts: each body's model's), and each world
    // box's body and cell.
    std::unordered_map<const detail::BodyModel*, std::vector<std::vector<uint32_t>>> parts;
    std::vector<const std::vector<std::vector<uint32_t>>*> bodyParts(w.bodies.size());
    std::vector<std::pair<uint32_t, uint32_t>> boxOwner(w.nodes.size() / 8);
    for (uint32_t b = 0; b < w.bodies.size(); ++b) {
        const detail::BodyRecord& r = w.bodies[b];
        auto [it, added] = parts.try_emplace(r.model.get());
        if (added) it->second = cellTriangleVertices(*r.model);
        bodyParts[b] = &it->second;
        for (uint32_t k = 0; k < r.boxCount; ++k)
            boxOwner[r.firstBox + k] = {b, r.model->lattice.boxes[k].cell};
    }
    ApartTally apart;
    PartnerTally partners;
    detail::ContactList fresh;
    std::vector<std::pair<uint64_t, bool>> pairApart; // per contact: its box pair, apart
    nlohmann::json perFrame = nlohmann::json::array();
    for (int f = 1; f <= frames; ++f) {
        world.step();
        if (f % every != 0) continue;
        updateBoxes(w, now);
        // The last substep's object contacts by the pair of boxes they join: (the box of A's
        // point, B's box). A contact pushes its A along its normal.
        std::unordered_multimap<uint64_t, const detail::Contact*> contacts;
        for (const detail::Contact& c : w.collision.objectContacts())
            contacts.emplace((uint64_t(c.nodeA / 8) << 32) | c.boxB, &c);
        std::array<Tally, kCauseCount> here{};
        auto classify = [&](size_t a, size_t vertex, size_t b, double depth) {
            const detail::BodyRecord& A = *records[a];
            const detail::BodyRecord& B = *records[b];
            const Lattice& LA = A.model->lattice;
            const Vec3 p = views[a].vertices[vertex];
            pushes.clear();
            float residual = INFINITY; // the most violated of the vertex's contacts, now
            bool found = false;        // a box pair without contact was tested in the last substep
            const uint32_t own = LA.cellBox[LA.vertices[vertex].cell];
            Cause cause = kOwnBox;
            if (own != UINT32_MAX) {
                const uint32_t ownBox = A.firstBox + own;
                const Box boxA = boxAt(now, ownBox);
                const float skinA = w.settings.contactSkin * A.cellSize;
                const float skinB = w.settings.contactSkin * B.cellSize;
                if (!holds(boxA, p, skinA)) {
                    // How far outside its own box: the largest signed distance to its planes.
                    float outside = -INFINITY;
                    for (int face = 0; face < 6; ++face)
                        outside = std::max(outside, dot(boxA.planes.normal[face], p) -
                                                        boxA.planes.offset[face]);
                    ownBoxExcess.add(std::max(0.0f, outside) / A.cellSize);
                } else {
                    cause = kNoBox;
                    // Each box of B holding the vertex: the furthest the detection got with
                    // any of them.
                    for (uint32_t k = B.firstBox; k < B.firstBox + B.boxCount; ++k) {
                        if (!now.bounds[k].contains(p, skinB)) continue;
                        const Box boxB = boxAt(now, k);
                        if (!holds(boxB, p, skinB)) continue;
                        bool nodeInside = false, contact = false;
                        // The way the pair's contacts push A (those whose A is B push A the
                        // opposite way of their normal).
                        auto push = [&](uint64_t key, float sign) {
                            const auto [first, last] = contacts.equal_range(key);
                            for (auto it = first; it != last; ++it) {
                                contact = true;
                                pushes.push_back(it->second->normal * sign);
                                residual = std::min(
                                    residual,
                                    detail::separation(*it->second, w.collision.boxParticles, w.x));
                            }
                        };
                        push((uint64_t(ownBox) << 32) | k, 1.0f);
                        push((uint64_t(k) << 32) | ownBox, -1.0f);
                        for (uint32_t n = 0; n < 8; ++n)
                            nodeInside = nodeInside ||
                                         holds(boxB, now.nodes[ownBox * 8 + n], skinB) ||
                                         holds(boxA, now.nodes[k * 8 + n], skinA);
                        const Cause reached = contact      ? kUnresolved
                                              : nodeInside ? kNoContact
                                                           : kCrossing;
                        if (reached == kNoContact) {
                            const uint64_t pair = ownBox < k ? (uint64_t(ownBox) << 32 | k)
                                                             : (uint64_t(k) << 32 | ownBox);
                            found =
                                found || std::binary_search(w.collision.boxPairKeys.begin(),
                                                            w.collision.boxPairKeys.end(), pair);
                        }
                        cause = std::max(cause, reached);
                    }
                }
            }
            here[cause].add(depth);
            if (cause == kNoContact) tested[found ? 0 : 1].add(depth);
            if (cause == kUnresolved) {
                // Whether those contacts push the vertex's body the way out: the best cosine
                // between a push and the way to the other mesh's nearest surface point.
                const Vec3 out = normalize(bench::closestPointOnSurface(p, views[b]) - p);
                float best = -1;
                for (const Vec3& n : pushes) best = std::max(best, dot(n, out));
                way[best < 0 ? 0 : best < 0.7f ? 1 : 2].add(depth);
                const float skinA = w.settings.contactSkin * records[a]->cellSize;
                held[residual > -0.1f * skinA ? 0 : 1].add(depth);
            }
        };
        bench::measureInterpenetration(views, settings, classify);
        // The contacts between mesh parts apart along their normal by more than the skin.
        ApartTally frameApart;
        pairApart.clear();
        for (const detail::Contact& c : w.collision.objectContacts()) {
            const auto [bodyA, cellA] = boxOwner[c.nodeA / 8];
            const auto [bodyB, cellB] = boxOwner[c.boxB];
            // A's part's lowest along the normal and B's highest: by their triangles' vertices
            // and by their boxes' nodes, whichever bounds tighter.
            float hullA = INFINITY, hullB = -INFINITY, boxA = INFINITY, boxB = -INFINITY;
            for (const uint32_t v : (*bodyParts[bodyA])[cellA])
                hullA = std::min(hullA, dot(views[bodyA].vertices[v], c.normal));
            for (const uint32_t v : (*bodyParts[bodyB])[cellB])
                hullB = std::max(hullB, dot(views[bodyB].vertices[v], c.normal));
            for (int n = 0; n < 8; ++n) {
                boxA = std::min(boxA, dot(now.nodes[size_t(c.nodeA / 8) * 8 + n], c.normal));
                boxB = std::max(boxB, dot(now.nodes[size_t(c.boxB) * 8 + n], c.normal));
            }
            const bool isApart = std::max(hullA, boxA) - std::min(hullB, boxB) >
                                 w.settings.contactSkin * w.collision.bodies[bodyB].cellSize;
            ++frameApart.contacts;
            frameApart.apartContacts += isApart;
            if (c.distance < 0) {
                ++frameApart.overlapping;
                frameApart.overlappingApart += isApart;
            }
            // A pair's contacts share its normal, so its verdict; they need not be consecutive
            // (the order is by A's point, then B's box).
            pairApart.emplace_back((uint64_t(c.nodeA / 8) << 32) | c.boxB, isApart);
        }
        std::sort(pairApart.begin(), pairApart.end());
        pairApart.erase(
            std::unique(pairApart.begin(), pairApart.end(),
                        [](const auto& x, const auto& y) { return x.first == y.first; }),
            pairApart.end());
        frameApart.pairs = (long long)pairApart.size();
        for (const auto& [key, isApart] : pairApart) frameApart.apartPairs += isApart;
        apart.contacts += frameApart.contacts, apart.pairs += frameApart.pairs;
        apart.apartContacts += frameApart.apartContacts, apart.apartPairs += frameApart.apartPairs;
        apart.overlapping += frameApart.overlapping;
        apart.overlappingApart += frameApart.overlappingApart;
        // The contacts found afresh on this state, against their manifolds' distances.
        PartnerTally framePartners;
        {
            const std::vector<uint8_t> saved = world.saveState();
            detail::CollisionWorld view = detail::collisionView(w);
            detail::updateNodes(view, 0, w.bodies.size());
            w.collision.pairs.clear();
            detail::sphereTest(view);
            detail::ObjectContactCounts counts;
            detail::findObjectContacts(view, w.settings.mode, fresh, counts);
            for (const detail::Contact& c : fresh) {
                const float constraint =
                    detail::separation(c, w.collision.boxParticles, w.x); // at detection
                const double off = std::fabs(double(constraint) - double(c.distance));
                ++framePartners.contacts;
                if (off > 1e-3) {
                    ++framePartners.over1mm;
                    framePartners.shallower += constraint > c.distance;
                }
                framePartners.over1cm += off > 1e-2;
                framePartners.most = std::max(framePartners.most, off);
            }
            world.restoreState(saved);
            // Restoring replaced the world's arrays: the meshes and records again.
            for (size_t k = 0; k < build.bodies.size(); ++k) {
                views[k] = {world.vertices(build.bodies[k]), world.triangles(build.bodies[k])};
                records[k] = w.find(build.bodies[k]);
            }
        }
        partners.contacts += framePartners.contacts;
        partners.over1mm += framePartners.over1mm;
        partners.over1cm += framePartners.over1cm;
        partners.shallower += framePartners.shallower;
        partners.most = std::max(partners.most, framePartners.most);
        nlohmann::json row = {{"frame", f},
                              {"partners_off_1mm", framePartners.over1mm},
                              {"partners_most_off_m", framePartners.most},
                              {"contacts", frameApart.contacts},
                              {"contacts_apart", frameApart.apartContacts},
                              {"box_pairs", frameApart.pairs},
                              {"box_pairs_apart", frameApart.apartPairs}};
        for (int c = 0; c < kCauseCount; ++c) {
            total[c].vertices += here[c].vertices;
            total[c].depthSum += here[c].depthSum;
            total[c].maxDepth = std::max(total[c].maxDepth, here[c].maxDepth);
            row[kCauseKeys[c]] = {{"vertices", here[c].vertices},
                                  {"max_depth_m", here[c].maxDepth}};
        }
        perFrame.push_back(row);
    }

    long long all = 0;
    for (const Tally& t : total) all += t.vertices;
    fmt::print("{}: {} objects, {} frames, classified every {} frames: {} vertex samples inside "
               "another body\n",
               scene.name, build.bodies.size(), frames, every, all);
    fmt::print("  {:<11} {:>9} {:>7} {:>10} {:>10}\n", "cause", "vertices", "share", "max cm",
               "mean cm");
    nlohmann::json causes;
    for (int c = 0; c < kCauseCount; ++c) {
        const Tally& t = total[c];
        const double mean = t.vertices ? t.depthSum / double(t.vertices) : 0;
        fmt::print("  {:<11} {:>9} {:>6.1f}% {:>10.2f} {:>10.2f}\n", kCauseNames[c], t.vertices,
                   all ? 100.0 * double(t.vertices) / double(all) : 0.0, 100 * t.maxDepth,
                   100 * mean);
        causes[kCauseKeys[c]] = {
            {"vertices", t.vertices}, {"max_depth_m", t.maxDepth}, {"mean_depth_m", mean}};
    }
    if (ownBoxExcess.vertices > 0)
        fmt::print("  own box: outside the box's planes by {:.3f} of a cell on average, {:.3f} at "
                   "most\n",
                   ownBoxExcess.depthSum / double(ownBoxExcess.vertices), ownBoxExcess.maxDepth);
    const char* wayNames[3] = {"against the way out (cos < 0)", "sideways (cos 0-0.7)",
                               "the way out (cos >= 0.7)"};
    for (int k = 0; k < 3; ++k)
        fmt::print("  unresolved, best push {:<30} {:>6} vertices, max {:.2f} cm, mean {:.2f} cm\n",
                   wayNames[k], way[k].vertices, 100 * way[k].maxDepth,
                   way[k].vertices ? 100 * way[k].depthSum / double(way[k].vertices) : 0.0);
    const char* testedNames[2] = {"tested, no contact", "not tested"};
    for (int k = 0; k < 2; ++k)
        fmt::print("  no contact, box pair {:<31} {:>6} vertices, max {:.2f} cm, mean {:.2f} cm\n",
                   testedNames[k], tested[k].vertices, 100 * tested[k].maxDepth,
                   tested[k].vertices ? 100 * tested[k].depthSum / double(tested[k].vertices)
                                      : 0.0);
    const char* heldNames[2] = {"hold at the frame's end", "still violated"};
    for (int k = 0; k < 2; ++k)
        fmt::print("  unresolved, contacts {:<31} {:>6} vertices, max {:.2f} cm, mean {:.2f} cm\n",
                   heldNames[k], held[k].vertices, 100 * held[k].maxDepth,
                   held[k].vertices ? 100 * held[k].depthSum / double(held[k].vertices) : 0.0);
    auto share = [](long long part, long long whole) {
        return whole > 0 ? 100.0 * double(part) / double(whole) : 0.0;
    };
    fmt::print("  contacts between meshes apart: {} of {} object contacts ({:.1f} %) and {} of {} "
               "box pairs ({:.1f} %) join mesh parts apart along the normal by more than the "
               "skin; {} of the {} contacts found with their boxes overlapping ({:.1f} %)\n",
               apart.apartContacts, apart.contacts, share(apart.apartContacts, apart.contacts),
               apart.apartPairs, apart.pairs, share(apart.apartPairs, apart.pairs),
               apart.overlappingApart, apart.overlapping,
               share(apart.overlappingApart, apart.overlapping));
    fmt::print("  partners kept within their boxes: of {} object contacts found afresh on those "
               "states, {} ({:.1f} %) have a constraint at detection more than 1 mm off their "
               "manifold's distance ({} of them shallower), {} more than 1 cm; the most {:.2f} "
               "cm\n",
               partners.contacts, partners.over1mm, share(partners.over1mm, partners.contacts),
               partners.shallower, partners.over1cm, 100 * partners.most);
    const nlohmann::json partnersJson = {{"contacts", partners.contacts},
                                         {"off_1mm", partners.over1mm},
                                         {"off_1mm_shallower", partners.shallower},
                                         {"off_1cm", partners.over1cm},
                                         {"most_off_m", partners.most}};
    const nlohmann::json apartJson = {
        {"contacts", apart.contacts},       {"contacts_apart", apart.apartContacts},
        {"box_pairs", apart.pairs},         {"box_pairs_apart", apart.apartPairs},
        {"overlapping", apart.overlapping}, {"overlapping_apart", apart.overlappingApart}};
    if (jsonFile) {
        const std::string text =
            nlohmann::json{{"scene", scene.name},      {"objects", build.bodies.size()},
                           {"frames", frames},         {"every", every},
                           {"causes", causes},         {"meshes_apart", apartJson},
                           {"partners", partnersJson}, {"per_frame", perFrame}}
                .dump(1) +
            "\n";
        return bench::commitJson(*jsonFile, text, "ffdaabb_contact_causes");
    }
    return 0;
}
