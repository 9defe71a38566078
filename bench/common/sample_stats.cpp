#include "sample_stats.h"

#include <algorithm>
#include <numeric>

namespace ffd::bench {

double mean(std::span<const double> sample) {
    if (sample.empty()) return 0;
    return std::accumulate(sample.begin(), sample.end(), 0.0) / double(sample.size());
}

double median(std::vector<double> sample) {
    if (sample.empty()) return 0;
    const size_t mid = sample.size() / 2;
    const auto upper = sample.begin() + std::ptrdiff_t(mid);
    std::nth_element(sample.begin(), upper, sample.end());
    if (sample.size() % 2 == 1) return *upper;
    // Even count: the lower middle value is the largest of the lower half.
    return 0.5 * (*std::max_element(sample.begin(), upper) + *upper);
}

double quantile(std::vector<double> sample, double q) {
    if (sample.empty()) return 0;
    std::sort(sample.begin(), sample.end());
    const double pos = std::clamp(q, 0.0, 1.0) * double(sample.size() - 1);
    const size_t lo = size_t(pos);
    const size_t hi = std::min(lo + 1, sample.size() - 1);
    return sample[lo] + (sample[hi] - sample[lo]) * (pos - double(lo));
}

} // namespace ffd::bench
