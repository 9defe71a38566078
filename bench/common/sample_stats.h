// Summary statistics of a sample (frame times, gaps between bodies): the one mean, median and
// quantile that every command (run, bench, soak) and benchmark (the Bullet comparison) uses, so
// that a key such as "median" means the same number in every output.
#pragma once

#include <span>
#include <vector>

namespace ffd::bench {

/// The arithmetic mean (summed in double); 0 for an empty sample.
double mean(std::span<const double> sample);

/// The true median: the middle value of the sorted sample, or the mean of the two middle values
/// when the count is even; 0 for an empty sample.
double median(std::vector<double> sample);

/// The q-quantile (q in [0, 1], clamped) by linear interpolation between the sorted values at
/// q * (count - 1), so quantile(v, 0.5) equals median(v) up to rounding; 0 for an empty sample.
double quantile(std::vector<double> sample, double q);

} // namespace ffd::bench
