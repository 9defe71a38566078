// The stage table (ffdaabb/profile.h): every stage timed into its own entry, the paper's Table 1
// columns as sums of stages, and the docs listing every stage.
#include "ffdaabb/profile.h"
#include "ffdaabb/world.h"
#include "world/world_data.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

using namespace ffd;
using ffd::test::ball;

namespace {

World pile(CollisionMode mode, int threads = 1) {
    WorldSettings ws;
    ws.mode = mode;
    ws.threads = threads;
    World world(ws);
    BodySettings s;
    s.lattice.targetCells = 38;
    for (int i = 0; i < 8; ++i) {
        s.position = {float(i % 2) * 0.5f, 1.0f + 1.9f * float(i / 2), float(i % 3) * 0.3f};
        world.addBody(ball(), s);
    }
    return world;
}

} // namespace

TEST(Profile, TheTablesAreInOrderWithDistinctKeys) {
    std::set<std::string> keys;
    size_t i = 0;
    for (const StageInfo& s : stageTable()) {
        EXPECT_EQ(size_t(s.stage), i++);
        EXPECT_TRUE(keys.insert(s.key).second) << s.key;
        EXPECT_EQ(&info(s.stage), &s);
        EXPECT_GT(std::string(s.summary).size(), 10u);
    }
    EXPECT_EQ(i, kStageCount);
    std::set<std::string> columns;
    i = 0;
    for (const TableColumnInfo& c : tableColumns()) {
        EXPECT_EQ(size_t(c.column), i++);
        EXPECT_TRUE(columns.insert(c.key).second) << c.key;
        int stages = 0;
        for (const StageInfo& s : stageTable()) stages += s.column == c.column;
        EXPECT_GT(stages, 0) << c.key << " sums no stage";
    }
}

TEST(Profile, EveryStageIsTimedAndTheColumnsAreTheirSums) {
    World world = pile(CollisionMode::Enhanced);
    // From frame 90 on, the first frame with object contacts (the balls roll over each other).
    for (int f = 0; f < 90 || (world.profile().contacts == 0 && f < 300); ++f) world.step();
    const Profile& p = world.profile();
    ASSERT_GT(p.contacts, 0);
    double sum = 0;
    for (const StageInfo& s : stageTable()) {
        EXPECT_GE(p.ms(s.stage), 0.0) << s.key;
        sum += p.ms(s.stage);
    }
    // The stages that always work in a pile of touching bodies take time.
    for (Stage s : {Stage::Dynamics, Stage::NodeUpdate, Stage::SphereTest, Stage::ObjectContacts,
                    Stage::FloorContacts, Stage::ResponseBeforeMove, Stage::PositionUpdate,
                    Stage::ResponseAfterMove, Stage::MeshUpdate})
        EXPECT_GT(p.ms(s), 0.0) << info(s).key;
    EXPECT_LE(sum, p.total);
    double columns = 0;
    for (const TableColumnInfo& c : tableColumns()) {
        double stages = 0;
        for (const StageInfo& s : stageTable())
            if (s.column == c.column) stages += p.ms(s.stage);
        EXPECT_EQ(p.ms(c.column), stages) << c.key;
        columns += p.ms(c.column);
    }
    EXPECT_NEAR(columns, sum, 1e-9 * sum);
}

// Phase 3's counts: each box pair it tests was named by at least one node/box pair, a pair
// gives at most eight points (four of the clipped face, four beside its sides), and the counts
// are the same in every mode (phase 1 removes only pairs that cannot touch) and on two threads
// (their chunks of pairs summed).
TEST(Profile, BoxPairCountsBoundTheContactsAndAgreeAcrossModesAndThreads) {
    World enhanced = pile(CollisionMode::Enhanced), previous = pile(CollisionMode::Previous),
          threaded = pile(CollisionMode::Enhanced, 2);
    int framesWithContacts = 0;
    for (int f = 0; f < 240; ++f) {
        enhanced.step();
        previous.step();
        threaded.step();
        const Profile& p = enhanced.profile();
        ASSERT_LE(p.boxPairs, p.potentialPairs) << "frame " << f;
        ASSERT_LE(p.contactBoxPairs, p.boxPairs) << "frame " << f;
        ASSERT_LE(p.contacts, 8 * p.contactBoxPairs) << "frame " << f;
        ASSERT_EQ(p.contacts > 0, p.contactBoxPairs > 0) << "frame " << f;
        for (const World* other : {&previous, &threaded}) {
            ASSERT_EQ(other->profile().boxPairs, p.boxPairs) << "frame " << f;
            ASSERT_EQ(other->profile().contactBoxPairs, p.contactBoxPairs) << "frame " << f;
        }
        framesWithContacts += p.contacts > 0;
    }
    EXPECT_GT(framesWithContacts, 60); // the balls land on each other
}

// The stage observer (instrumentation, bench/causes/energy_stages.cpp) is told after each stage
// of a step, in the order they run: the frame's wake-up, each substep's ten stages, then the
// mesh update and the frame's sleep test. Watching changes nothing.
TEST(Profile, TheStageObserverSeesEveryStageInOrderAndChangesNothing) {
    World watched = pile(CollisionMode::Enhanced), plain = pile(CollisionMode::Enhanced);
    std::vector<Stage> seen;
    detail::dataOf(watched).stageObserver = [&](Stage s) { seen.push_back(s); };
    const std::vector<Stage> substep = {Stage::Dynamics,        Stage::NodeUpdate,
                                        Stage::OverlapRecovery, Stage::SphereTest,
                                        Stage::ObjectContacts,  Stage::FloorContacts,
                                        Stage::OverlapSettling, Stage::ResponseBeforeMove,
                                        Stage::PositionUpdate,  Stage::ResponseAfterMove};
    std::vector<Stage> frame = {Stage::Sleeping};
    for (int k = 0; k < watched.settings().substeps; ++k)
        frame.insert(frame.end(), substep.begin(), substep.end());
    frame.push_back(Stage::MeshUpdate);
    frame.push_back(Stage::Sleeping);
    for (int f = 0; f < 120; ++f) {
        seen.clear();
        watched.step();
        plain.step();
        ASSERT_EQ(seen, frame) << "frame " << f;
    }
    EXPECT_EQ(watched.stateHash(), plain.stateHash());
}

TEST(Profile, ThePreviousMethodSpendsNothingOnDistanceCalculating) {
    World world = pile(CollisionMode::Previous);
    for (int f = 0; f < 30; ++f) world.step();
    EXPECT_EQ(world.profile().ms(TableColumn::DistanceCalculating), 0.0);
    EXPECT_GT(world.profile().ms(TableColumn::ObjectsCollision), 0.0);
}

TEST(Profile, TheArchitectureDocListsEveryStage) {
    std::ifstream in(std::string(FFD_SOURCE_DIR) + "/docs/ARCHITECTURE.md");
    ASSERT_TRUE(in) << "docs/ARCHITECTURE.md";
    std::stringstream text;
    text << in.rdbuf();
    const std::string doc = text.str();
    const size_t from = doc.find("## The step"), to = doc.find("```mermaid", from);
    ASSERT_NE(from, std::string::npos);
    const std::string section = doc.substr(from, to - from);
    // A line of the list starts with the stage's key (indented within the substep).
    for (const StageInfo& s : stageTable()) {
        const std::string key = std::string(s.key) + " ";
        EXPECT_TRUE(section.find("\n  " + key) != std::string::npos ||
                    section.find("\n" + key) != std::string::npos)
            << s.key << " is missing from the step's list in docs/ARCHITECTURE.md";
    }
}
