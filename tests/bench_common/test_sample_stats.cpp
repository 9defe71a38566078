// The one mean, median and quantile of bench/common/sample_stats.h (every command's and
// benchmark's "mean" and "median").
#include "sample_stats.h"

#include <gtest/gtest.h>

#include <vector>

using namespace ffd::bench;

TEST(SampleStats, MedianIsTheMiddleOrTheMeanOfTheTwoMiddleValues) {
    EXPECT_EQ(median({}), 0.0);
    EXPECT_EQ(median({7}), 7.0);
    EXPECT_EQ(median({3, 1, 2}), 2.0);
    EXPECT_EQ(median({4, 1, 3, 2}), 2.5); // not the upper middle value 3
    EXPECT_EQ(median({10, 0}), 5.0);
    EXPECT_EQ(median({5, 5, 1, 9, 9, 1}), 5.0);
    EXPECT_EQ(median({1, 2, 100, 1000}), 51.0);
}

TEST(SampleStats, MeanAndQuantiles) {
    EXPECT_EQ(mean(std::vector<double>{}), 0.0);
    EXPECT_EQ(mean(std::vector<double>{1, 2, 3, 10}), 4.0);
    const std::vector<double> v{4, 1, 3, 2, 5};
    EXPECT_EQ(quantile(v, 0), 1.0);
    EXPECT_EQ(quantile(v, 1), 5.0);
    EXPECT_EQ(quantile(v, 0.5), 3.0);
    EXPECT_DOUBLE_EQ(quantile(v, 0.9), 4.6); // between 4 and 5 at 0.9 * 4 = 3.6
    EXPECT_EQ(quantile(v, 2), 5.0);          // clamped
    EXPECT_EQ(quantile({}, 0.5), 0.0);
    for (const std::vector<double>& s :
         {std::vector<double>{4, 1, 3, 2}, std::vector<double>{0.1, 0.7, 0.3, 0.2, 0.9, 0.4}})
        EXPECT_DOUBLE_EQ(quantile(s, 0.5), median(s));
}
