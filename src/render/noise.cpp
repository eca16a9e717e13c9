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

FbmRow::FbmRow(double v, Cells c, std::uint32_t seed, int octaves) : m_count(std::clamp(octaves, 0, MAX_OCTAVES)) {
    for (int o = 0; o < m_count; ++o) {
        Octave& k = m_octaves[o];
        k.cells = Cells{c.u << o, c.v << o};
        k.seed_hash = hash32(seed + static_cast<std::uint32_t>(o) * 1013u);
        const double y = v * k.cells.v, fy = std::floor(y);
        k.ty = y - fy;
        k.ty = k.ty * k.ty * (3.0 - 2.0 * k.ty);
        k.j0 = wrap_cell(static_cast<int>(fy), k.cells.v);
        k.j1 = k.j0 + 1 == k.cells.v ? 0 : k.j0 + 1;
    }
}

double FbmRow::operator()(double u) {
    double sum = 0, amplitude = 0.5, total = 0;
    for (int o = 0; o < m_count; ++o) {
        Octave& k = m_octaves[o];
        // value_noise(u, v, k.cells, seed + o · 1013), its row terms kept.
        const double x = u * k.cells.u, fx = std::floor(x);
        double tx = x - fx;
        tx = tx * tx * (3.0 - 2.0 * tx);
        if (const int cell = static_cast<int>(fx); !k.cached || cell != k.cell) {
            const int i0 = wrap_cell(cell, k.cells.u), i1 = i0 + 1 == k.cells.u ? 0 : i0 + 1;
            k.cell = cell, k.cached = true;
            k.a = lattice(i0, k.j0, k.seed_hash), k.b = lattice(i1, k.j0, k.seed_hash);
            k.d = lattice(i0, k.j1, k.seed_hash), k.e = lattice(i1, k.j1, k.seed_hash);
        }
        const double value = (k.a + (k.b - k.a) * tx) + ((k.d + (k.e - k.d) * tx) - (k.a + (k.b - k.a) * tx)) * k.ty;
        sum += amplitude * value;
        total += amplitude;
        amplitude *= 0.5;
    }
    return sum / total;
}

void FbmRow::fill(int width, std::vector<double>& out) const {
    const auto n = static_cast<std::size_t>(std::max(width, 0));
    out.assign(n, 0.0);
    std::vector<double> near_row, far_row; // the lattice along rows j0 and j1, one past the end wrapped
    std::vector<int> cell(n);
    std::vector<double> tx(n);
    double amplitude = 0.5, total = 0;
    for (int o = 0; o < m_count; ++o) {
        const Octave& k = m_octaves[o];
        const int cells = k.cells.u;
        near_row.resize(static_cast<std::size_t>(cells) + 1);
        far_row.resize(static_cast<std::size_t>(cells) + 1);
        for (int i = 0; i <= cells; ++i) {
            const int wrapped = i == cells ? 0 : i;
            near_row[static_cast<std::size_t>(i)] = lattice(wrapped, k.j0, k.seed_hash);
            far_row[static_cast<std::size_t>(i)] = lattice(wrapped, k.j1, k.seed_hash);
        }
        for (std::size_t x = 0; x < n; ++x) {
            const double u = (double(x) + 0.5) / width;
            // u > 0, so the floor is the truncation (a conversion that vectorises; std::floor
            // is a call without SSE4.1).
            const double at = u * cells;
            const int c = static_cast<int>(at);
            const double t = at - double(c);
            tx[x] = t * t * (3.0 - 2.0 * t);
            cell[x] = c < cells ? c : wrap_cell(c, cells); // in range but for rounding
        }
        for (std::size_t x = 0; x < n; ++x) {
            const auto i = static_cast<std::size_t>(cell[x]);
            const double a = near_row[i], b = near_row[i + 1], d = far_row[i], e = far_row[i + 1], t = tx[x];
            out[x] += amplitude * ((a + (b - a) * t) + ((d + (e - d) * t) - (a + (b - a) * t)) * k.ty);
        }
        total += amplitude;
        amplitude *= 0.5;
    }
    for (double& value : out)
        value /= total;
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
