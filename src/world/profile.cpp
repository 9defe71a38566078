#include "ffdaabb/profile.h"

namespace ffd {

namespace {

using S = Stage;
using C = TableColumn;

constexpr StageInfo kStages[kStageCount] = {
    {S::Dynamics, "lattice_dynamics", "shape matching or springs, external forces, velocities",
     C::Dynamics},
    {S::NodeUpdate, "node_update", "FFD-AABB nodes from particles, per-box and per-body bounds",
     C::MinMaxUpdating},
    {S::OverlapRecovery, "overlap_recovery",
     "pairs placed overlapping remembered, whole pairs pushed apart", C::ObjectsCollision},
    {S::SphereTest, "sphere_test", "phase 1: bounding spheres and candidate pairs (enhanced only)",
     C::DistanceCalculating},
    {S::ObjectContacts, "object_contacts",
     "phases 2-3: spatial hash of nodes, box pairs, node contacts", C::ObjectsCollision},
    {S::FloorContacts, "floor_contacts", "node contacts with the floor", C::Floor},
    {S::OverlapSettling, "overlap_settling", "remembered pairs that are apart forgotten",
     C::ObjectsCollision},
    {S::ResponseBeforeMove, "response_before_move", "pre-stabilisation and the rigid impact phase",
     C::ObjectsCollision},
    {S::PositionUpdate, "position_update", "positions advanced by the velocities", C::Dynamics},
    {S::ResponseAfterMove, "response_after_move",
     "projection of what overlap is left, then the velocity pass", C::ObjectsCollision},
    {S::MeshUpdate, "mesh_update", "embedded mesh vertices from the lattice", C::MeshUpdating},
    {S::Sleeping, "sleeping", "sleeping bodies within reach woken, quiet islands put to sleep",
     C::Dynamics},
};

constexpr TableColumnInfo kColumns[kTableColumnCount] = {
    {C::MeshUpdating, "mesh_update", "mesh updating"},
    {C::MinMaxUpdating, "node_update", "min, max updating"},
    {C::DistanceCalculating, "sphere_test", "distance calculating"},
    {C::Floor, "floor", "floor"},
    {C::ObjectsCollision, "object_collision", "objects collision"},
    {C::Dynamics, "dynamics", "dynamics"},
};

constexpr bool inOrder() {
    for (size_t i = 0; i < kStageCount; ++i)
        if (size_t(kStages[i].stage) != i) return false;
    for (size_t i = 0; i < kTableColumnCount; ++i)
        if (size_t(kColumns[i].column) != i) return false;
    return true;
}
static_assert(inOrder(), "the tables are indexed by Stage and TableColumn");

} // namespace

std::span<const StageInfo, kStageCount> stageTable() {
    return kStages;
}

std::span<const TableColumnInfo, kTableColumnCount> tableColumns() {
    return kColumns;
}

const StageInfo& info(Stage stage) {
    return kStages[size_t(stage)];
}

const TableColumnInfo& info(TableColumn column) {
    return kColumns[size_t(column)];
}

double Profile::ms(TableColumn column) const {
    double sum = 0;
    for (const StageInfo& s : kStages)
        if (s.column == column) sum += stageMs[size_t(s.stage)];
    return sum;
}

} // namespace ffd
