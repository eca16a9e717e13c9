#pragma once
/// @file The candidate a fracture loop acts on next (§5.6.2, §5.7.3): the one most over its
/// threshold, ties broken at random from the run's seed.

#include "core/rng.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace crackle::fracture {

/// Over candidates 0..n−1: the one with the highest ratio above 1 among those `eligible`
/// accepts (asked only of candidates that could win, as it may cost more than the ratio);
/// ratios within 1e-12 of the best are tied and one of them is drawn from `rng`. Returns false
/// when none is over 1; else `pick` and `best` (the highest ratio).
template <class RatioOf, class Eligible>
bool pick_most_over(std::size_t n, RatioOf&& ratio_of, Eligible&& eligible, Rng& rng, std::size_t& pick, double& best) {
    best = 1.0;
    std::vector<std::size_t> ties;
    for (std::size_t i = 0; i < n; ++i) {
        const double r = ratio_of(i);
        if (r <= 1.0 || r < best * (1 - 1e-12)) continue;
        if (!eligible(i)) continue;
        if (r > best * (1 + 1e-12)) {
            best = r;
            ties.assign(1, i);
        } else {
            ties.push_back(i);
        }
    }
    if (ties.empty()) return false;
    pick = ties.size() == 1 ? ties[0] : ties[rng.uniform_int(static_cast<std::uint32_t>(ties.size()))];
    return true;
}

} // namespace crackle::fracture
