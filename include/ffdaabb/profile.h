// What a step costs, stage by stage: the stages of World::step in one table that the profile,
// the command line's reports, the benchmarks, the viewer and the docs all read.
//
//   const ffd::Profile& p = world.profile();
//   for (const ffd::StageInfo& s : ffd::stageTable())
//       std::printf("%-22s %.3f ms\n", s.key, p.ms(s.stage));
//   double collision = p.ms(ffd::TableColumn::ObjectsCollision); // a column of the paper's Table 1
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace ffd {

/// The stages of World::step, in the order they run in each substep; mesh_update runs once per
/// frame, after the substeps, and sleeping once per frame, its waking before the substeps and
/// its falling asleep after mesh_update.
enum class Stage : uint8_t {
    Dynamics,           ///< shape matching or springs, external forces, velocities
    NodeUpdate,         ///< FFD-AABB nodes from particles, per-box and per-body bounds
    OverlapRecovery,    ///< pairs placed overlapping remembered, whole pairs pushed apart
    SphereTest,         ///< phase 1: bounding spheres and candidate pairs (enhanced only)
    ObjectContacts,     ///< phases 2-3: spatial hash of nodes, box pairs, node contacts
    FloorContacts,      ///< node contacts with the floor
    OverlapSettling,    ///< remembered pairs that are apart forgotten
    ResponseBeforeMove, ///< pre-stabilisation and the rigid impact phase
    PositionUpdate,     ///< positions advanced by the velocities
    ResponseAfterMove,  ///< projection of what overlap is left, then the velocity pass
    MeshUpdate,         ///< embedded mesh vertices from the lattice
    Sleeping,           ///< once a frame: sleeping bodies within reach woken, quiet islands put
                        ///< to sleep
};
inline constexpr size_t kStageCount = 12;

/// The columns of the paper's Table 1 (Jeon, Choi, Hong 2012), and the dynamics it leaves out:
/// each the sum of its stages (StageInfo::column).
enum class TableColumn : uint8_t {
    MeshUpdating,        ///< "mesh updating": mesh_update
    MinMaxUpdating,      ///< "min, max updating": node_update
    DistanceCalculating, ///< "distance calculating": sphere_test (0 in the previous method)
    Floor,               ///< "floor": floor_contacts
    ObjectsCollision,    ///< "objects collision": object contacts, their response, overlap recovery
    Dynamics,            ///< not in the paper's table: lattice dynamics and position update
};
inline constexpr size_t kTableColumnCount = 6;

struct StageInfo {
    Stage stage;
    const char* key;     ///< its name in JSON, CSV and tables: "object_contacts"
    const char* summary; ///< what it does, in a line
    TableColumn column;  ///< the Table 1 column it counts in
};

struct TableColumnInfo {
    TableColumn column;
    const char* key;     ///< its name in JSON and CSV: "object_collision"
    const char* heading; ///< the paper's heading: "objects collision"
};

/// Every stage, in Stage order (the order they run).
std::span<const StageInfo, kStageCount> stageTable();
/// Every Table 1 column, in TableColumn order.
std::span<const TableColumnInfo, kTableColumnCount> tableColumns();
const StageInfo& info(Stage stage);
const TableColumnInfo& info(TableColumn column);

/// Stage timings (milliseconds, summed over the substeps of the last frame) and counters of
/// the last frame.
struct Profile {
    std::array<double, kStageCount> stageMs{}; ///< by Stage
    double total = 0;                          ///< the whole step()

    double ms(Stage stage) const { return stageMs[size_t(stage)]; }
    /// A Table 1 column: the sum of its stages.
    double ms(TableColumn column) const;

    int candidatePairs = 0; ///< object pairs passed to the spatial hash (last substep)
    int potentialPairs = 0; ///< node/box pairs tested in the narrow phase (last substep)
    /// Box pairs that phase 3 tested, each once (separating axes on their face planes): the
    /// pairs of boxes that those node/box tests found within a margin (last substep).
    int boxPairs = 0;
    int contactBoxPairs = 0; ///< of those, the pairs that gave a contact (last substep)
    int contacts = 0;        ///< object contacts (last substep)
    int floorContacts = 0;   ///< floor contacts (last substep)
    int overlapPairs = 0;    ///< pairs placed overlapping and not yet apart (last substep)
    int wholePairs = 0;      ///< of those, pushed apart as whole bodies (last substep)
    int sleepingBodies = 0;  ///< bodies asleep at the end of the frame
    /// Deepest contact violation left after the response (a box node inside another object's
    /// cell box or below the floor), metres, over the frame's substeps: the pipeline's own
    /// measure, not the meshes' (a node inside a box need not be a vertex inside a mesh, nor
    /// the reverse); the meshes' interpenetration is `ffdaabb run`'s `interpenetration`.
    float maxContactDepth = 0;
};

} // namespace ffd
