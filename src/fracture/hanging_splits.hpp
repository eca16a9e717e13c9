#pragma once
/// @file Crack edges split on one side only. fem-split refines next to a tip (thesis §5.6.2):
/// a crack that later runs along a refined edge has its hanging nodes on one side (a → m → b)
/// and the unrefined edge a → b on the other. As a graph of crack links this is a triangle, a
/// spurious pair of degree-3 nodes; the statistics and the crack network both take the finer
/// side as the crack's path and drop the coarse link.

#include "core/math.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace crackle::fracture {

using NodePair = std::pair<std::uint32_t, std::uint32_t>; ///< (a, b) with a < b

/// One crack edge with hanging nodes on one side.
struct HangingSplit {
    NodePair coarse;                 ///< the unrefined side a → b
    std::vector<std::uint32_t> path; ///< the finer side a, m₁, …, b
    std::vector<double> t;           ///< per path node: its place along a → b, 0 … 1
};

/// For every single-sided link a → b (a lip with no partner on the same two nodes), a path of
/// other single-sided links from a to b (at most five links) whose inner nodes lie on the
/// segment ab, within 2 % of its length, in order along it. `position`: per node, its
/// reference position (x, y, 0 in domain coordinates on a periodic domain, where `period` > 0
/// gives the nearest image; zero period: 3D positions, no wrapping).
std::vector<HangingSplit> hanging_splits(const std::vector<NodePair>& single_links, const std::vector<Vec3>& position,
                                         const Vec2& period);

} // namespace crackle::fracture
