#pragma once
/// @file Connected regions of a periodic pixel grid (4-neighbours, wrapping in both directions:
/// plane and cylinder tiles), for tests that read pieces back from baked maps.

#include <cstddef>
#include <utility>
#include <vector>

namespace crackle::test {

/// Labels (0, 1, …; −1 outside) of the regions of pixels where `inside(i)` holds, two
/// neighbours joining where `same(i, j)` holds too. Returns the number of regions.
template <class Inside, class Same> int label_regions(int w, int h, Inside inside, Same same, std::vector<int>& label) {
    label.assign(std::size_t(w) * std::size_t(h), -1);
    int regions = 0;
    std::vector<std::size_t> stack;
    for (std::size_t start = 0; start < label.size(); ++start) {
        if (label[start] >= 0 || !inside(start)) continue;
        label[start] = regions;
        stack.push_back(start);
        while (!stack.empty()) {
            const std::size_t i = stack.back();
            stack.pop_back();
            const int x = int(i % std::size_t(w)), y = int(i / std::size_t(w));
            for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
                const std::size_t j = std::size_t((y + dy + h) % h) * std::size_t(w) + std::size_t((x + dx + w) % w);
                if (label[j] < 0 && inside(j) && same(i, j)) {
                    label[j] = regions;
                    stack.push_back(j);
                }
            }
        }
        ++regions;
    }
    return regions;
}

} // namespace crackle::test
