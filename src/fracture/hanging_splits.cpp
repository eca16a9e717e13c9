#include "fracture/hanging_splits.hpp"

#include <cmath>
#include <functional>
#include <map>

namespace crackle::fracture {

std::vector<HangingSplit> hanging_splits(const std::vector<NodePair>& single_links, const std::vector<Vec3>& position,
                                         const Vec2& period) {
    // Reference positions from one node to another (the nearest periodic image).
    auto along = [&](std::uint32_t from, std::uint32_t to) {
        Vec3 d = position[to] - position[from];
        for (int k = 0; k < 2; ++k)
            if (period[k] > 0) d[k] -= period[k] * std::round(d[k] / period[k]);
        return d;
    };
    std::map<std::uint32_t, std::vector<std::uint32_t>> single;
    for (const auto& [a, b] : single_links)
        single[a].push_back(b), single[b].push_back(a);
    std::vector<HangingSplit> out;
    for (const auto& [a, b] : single_links) {
        const Vec3 ab = along(a, b);
        const double len2 = ab.squaredNorm();
        if (len2 <= 0) continue;
        auto on_segment = [&](std::uint32_t m, double& t) {
            const Vec3 am = along(a, m);
            t = am.dot(ab) / len2;
            return t > 1e-6 && t < 1 - 1e-6 && (am - t * ab).norm() <= 0.02 * std::sqrt(len2);
        };
        // Depth first over single-sided links through nodes on the segment, forwards along it.
        HangingSplit split{{std::min(a, b), std::max(a, b)}, {a}, {0.0}};
        std::function<bool(std::uint32_t, double)> reach = [&](std::uint32_t at, double t_at) {
            if (split.path.size() > 5) return false;
            for (std::uint32_t next : single[at]) {
                if (next == b && at != a) return split.path.push_back(b), split.t.push_back(1.0), true;
                double t = 0;
                if (next == b || !on_segment(next, t) || t <= t_at) continue;
                split.path.push_back(next);
                split.t.push_back(t);
                if (reach(next, t)) return true;
                split.path.pop_back();
                split.t.pop_back();
            }
            return false;
        };
        if (reach(a, 0.0)) out.push_back(std::move(split));
    }
    return out;
}

} // namespace crackle::fracture
