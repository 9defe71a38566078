// The checks between the step's stages (world/stage_checks.h): quiet on a running pile, and each
// names what a broken state breaks.
#include "ffdaabb/world.h"
#include "world/stage_checks.h"
#include "world/world_data.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace ffd;

namespace {

World pile() {
    World world;
    for (int i = 0; i < 12; ++i)
        world.addBody(test::ball(), test::sphereAt({0.4f * float(i % 3), 1.0f + 1.8f * float(i / 3),
                                                    0.3f * float(i % 2)}));
    return world;
}

} // namespace

TEST(StageChecks, QuietOnARunningPile) {
    World world = pile();
    for (int f = 0; f < 60; ++f) {
        world.step();
        const detail::WorldData& w = detail::dataOf(world);
        ASSERT_EQ(detail::particleProblem(w), "") << f;
        ASSERT_EQ(detail::nodeProblem(w), "") << f;
        ASSERT_EQ(detail::sphereProblem(w), "") << f;
        ASSERT_EQ(detail::meshProblem(w), "") << f;
    }
    EXPECT_GT(detail::dataOf(world).collision.pairs.size(), 0u);
}

TEST(StageChecks, EachNamesWhatIsBroken) {
    World world = pile();
    for (int f = 0; f < 30; ++f) world.step();
    detail::WorldData& w = detail::dataOf(world);
    const float nan = std::numeric_limits<float>::quiet_NaN();

    const Vec3 v = w.v[7];
    w.v[7].y = nan;
    EXPECT_EQ(detail::particleProblem(w), "particle velocity 7 is not finite");
    w.v[7] = v;

    const Vec3 node = w.nodes[3 * 8 + 2];
    w.nodes[3 * 8 + 2].x += 1.0f;
    EXPECT_EQ(detail::nodeProblem(w), "node 2 of box 3 is outside the box's bounds");
    w.nodes[3 * 8 + 2] = node;
    w.boxBounds[5].hi.y += 100.0f;
    w.nodes[5 * 8] = w.boxBounds[5].hi;
    EXPECT_EQ(detail::nodeProblem(w).rfind("box 5 is outside the bounds of body", 0), 0u);

    ASSERT_GT(w.collision.pairs.size(), 1u);
    std::swap(w.collision.pairs[0], w.collision.pairs[1]);
    EXPECT_EQ(detail::sphereProblem(w), "pair 1 is out of order or repeated");
    std::swap(w.collision.pairs[0], w.collision.pairs[1]);
    const uint32_t body = w.collision.pairs[0].a;
    w.collision.bodies[body].sphereRadius *= 0.5f;
    EXPECT_EQ(
        detail::sphereProblem(w).rfind("the bounding sphere of body " + std::to_string(body), 0),
        0u);

    w.vertices[11].z = std::numeric_limits<float>::infinity();
    EXPECT_EQ(detail::meshProblem(w), "mesh vertex 11 is not finite");
}
