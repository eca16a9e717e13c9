#include "render/noise.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::render {

namespace {

int wrap_cell(int i, int n) {
    return ((i % n) + n) % n;
}

/// Lattice value at cell (i, j); `seed_hash` is hash32 of the seed.
double lattice(int i, int j, std::uint32_t seed_hash) {
    return double(hash32(static_cast<std::uint32_t>(i) * 73856093u ^ static_cast<std::uint32_t>(j) * 19349663u
                         ^ seed_hash))
           / 4294967296.0;
}

} // namespace

double value_noise(double u, double v, Cells c, std::uint32_t seed) {
    const double x = u * c.u, y = v * c.v;
    const double fx = std::floor(x), fy = std::floor(y);
    const int i = static_cast<int>(fx), j = static_cast<int>(fy);
    double tx = x - fx, ty = y - fy;
    tx = tx * tx * (3.0 - 2.0 * tx);
    ty = ty * ty * (3.0 - 2.0 * ty);
    const int i0 = wrap_cell(i, c.u), i1 = i0 + 1 == c.u ? 0 : i0 + 1;
    const int j0 = wrap_cell(j, c.v), j1 = j0 + 1 == c.v ? 0 : j0 + 1;
    const std::uint32_t sh = hash32(seed);
    const double a = lattice(i0, j0, sh), b = lattice(i1, j0, sh);
    const double d = lattice(i0, j1, sh), e = lattice(i1, j1, sh);
    return (a + (b - a) * tx) + ((d + (e - d) * tx) - (a + (b - a) * tx)) * ty;
}

double fbm(double u, double v, Cells c, std::uint32_t seed, int octaves) {
    double sum = 0, amplitude = 0.5, total = 0;
    for (int o = 0; o < octaves; ++o) {
        sum += amplitude * value_noise(u, v, Cells{c.u << o, c.v << o}, seed + static_cast<std::uint32_t>(o) * 1013u);
        total += amplitude;
        amplitude *= 0.5;
    }
    return sum / total;
}

CellSample cellular(double u, double v, Cells c, std::uint32_t seed) {
    const double x = u * c.u, y = v * c.v;
    const int i = static_cast<int>(std::floor(x)), j = static_cast<int>(std::floor(y));
    CellSample s;
    s.f1 = s.f2 = 1e9;
    for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di) {
            const int ci = i + di, cj = j + dj;
            const auto key = static_cast<std::uint32_t>(wrap_cell(ci, c.u)) * 0x27d4eb2du
                             ^ static_cast<std::uint32_t>(wrap_cell(cj, c.v)) * 0x165667b1u ^ hash32(seed + 0x9e37u);
            const double px = ci + double(hash32(key)) / 4294967296.0;
            const double py = cj + double(hash32(key ^ 0x5bd1e995u)) / 4294967296.0;
            const double d = std::hypot(px - x, py - y);
            if (d < s.f1) {
                s.f2 = s.f1;
                s.f1 = d;
                s.id = double(hash32(key ^ 0xc2b2ae35u)) / 4294967296.0;
            } else if (d < s.f2) {
                s.f2 = d;
            }
        }
    return s;
}

} // namespace crackle::render
