#include "mesh/lattice.hpp"

#include <map>

namespace crackle::mesh {

std::vector<Vec2> triangular_lattice(const Vec2& period, std::size_t count, double* stretch) {
    const double row_factor = std::sqrt(3.0) / 2.0;
    const double a = std::sqrt(period.x() * period.y() / (static_cast<double>(count) * row_factor));
    const int cols = std::max(3, static_cast<int>(std::lround(period.x() / a)));
    int rows = std::max(4, static_cast<int>(std::lround(period.y() / (a * row_factor))));
    if (rows % 2) ++rows;
    const double ax = period.x() / cols, ay = period.y() / rows;
    if (stretch) *stretch = ay / (ax * row_factor);
    std::vector<Vec2> pts;
    pts.reserve(static_cast<std::size_t>(cols * rows));
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < cols; ++i)
            pts.emplace_back((i + 0.5 * (j % 2) + 0.25) * ax, (j + 0.5) * ay);
    return pts;
}

int icosphere_level(std::size_t count) {
    int best = 0;
    double best_err = 1e300;
    for (int level = 0; level < 12; ++level) {
        const double n = 10.0 * std::pow(4.0, level) + 2.0;
        const double err = std::abs(std::log(n / static_cast<double>(count)));
        if (err < best_err) {
            best_err = err;
            best = level;
        }
    }
    return best;
}

std::vector<Vec3> icosphere_points(double radius, int level) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vec3> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    for (Vec3& p : v)
        p.normalize();
    std::vector<std::array<int, 3>> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                             {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                             {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                             {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    for (int l = 0; l < level; ++l) {
        std::map<std::pair<int, int>, int> midpoint;
        auto mid = [&](int a, int b) {
            const auto key = std::minmax(a, b);
            auto it = midpoint.find(key);
            if (it != midpoint.end()) return it->second;
            v.push_back((v[static_cast<std::size_t>(a)] + v[static_cast<std::size_t>(b)]).normalized());
            const int id = static_cast<int>(v.size() - 1);
            midpoint.emplace(key, id);
            return id;
        };
        std::vector<std::array<int, 3>> next;
        next.reserve(4 * faces.size());
        for (const auto& f : faces) {
            const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
            next.push_back({f[0], ab, ca});
            next.push_back({f[1], bc, ab});
            next.push_back({f[2], ca, bc});
            next.push_back({ab, bc, ca});
        }
        faces.swap(next);
    }
    for (Vec3& p : v)
        p *= radius;
    return v;
}

} // namespace crackle::mesh
