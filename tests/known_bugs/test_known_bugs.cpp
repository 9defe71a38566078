// Bugs found by the robustness work (issue 7) that are not fixed yet, as tests of the behaviour
// we want. CTest runs them with WILL_FAIL: each must fail today. When one passes, its bug is
// fixed: move the test to its area folder (tests/extreme, tests/collision) and delete the
// entry in docs/LIMITS.md. They run every time, so a fix is noticed at once.
#include "ffdaabb/generators.h"
#include "ffdaabb/world.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace ffd;
using ffd::test::ball;

// A sphere 1,000 times heavier resting on a light one, offset sideways by 0 to 10 cm (as
// tests/extreme MassRatioOneToAThousand and HeavySphereDoesNotCrushALightOne, which check that
// both recover and that the heavy one stays out of the light one). Wanted: the light one never
// thrown faster than 15 m/s. Today the contact split by mass leaves the light sphere almost all
// of each correction, and it is squeezed out at 20-28 m/s (docs/LIMITS.md).
TEST(KnownBugs, LightSphereIsNotThrownFromUnderAHeavyOne) {
    for (const float offset : {0.0f, 0.03f, 0.05f, 0.07f, 0.1f}) {
        SCOPED_TRACE("offset " + std::to_string(offset));
        World world;
        const BodyId light = test::addHeavyOnLight(world, offset);
        float fastest = 0;
        for (int f = 0; f < 300; ++f) {
            world.step();
            fastest = std::max(fastest, length(world.linearVelocity(light)));
        }
        EXPECT_LT(fastest, 15.0f);
    }
}

// 200 spheres created at one spot (tests/extreme TwoHundredAtOneSpotSeparate, the same layout):
// the dense-pile issue asks them apart within 3 s. Wanted: no vertex inside another sphere
// deeper than 1 cm (the mesh measure) after 3 s. Today the last whole pairs, pushed apart by
// positions at the recovery speed, are held back by their neighbours' contacts: over six layouts
// (rotations from seeds 1-6) the meshes are apart from 2.5 to 3.8 s, and this one is 26 cm deep
// at 3 s (docs/LIMITS.md, known problem 1).
TEST(KnownBugs, TwoHundredAtOneSpotApartInThreeSeconds) {
    World world;
    test::addTwoHundredAtOneSpot(world);
    for (int f = 0; f < 180; ++f) world.step();
    EXPECT_LE(test::deepestInside(world), 0.01);
}
