#pragma once
/// @file Tiling procedural noise for surface detail: every function is periodic over the unit
/// square with a whole number of cells across it, so the maps still tile. Deterministic on every
/// machine (integer hashing, no platform random numbers).

#include <cstdint>
#include <vector>

namespace crackle::render {

/// Integer hash (the same Wang / splitmix mix as the shaders' crackle_hash).
inline std::uint32_t hash32(std::uint32_t x) {
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

/// Uniform in [0, 1) from a piece label and a channel (the shaders' crackle_random).
inline double piece_random(int label, std::uint32_t channel, std::uint32_t seed) {
    return double(hash32(static_cast<std::uint32_t>(label) * 0x9e3779b9u ^ hash32(channel + seed * 0x85ebca6bu)))
           / 4294967296.0;
}

/// Cells across the unit square in u and v (each at least 1).
struct Cells {
    int u = 1, v = 1;
};

/// Smooth value noise in [0, 1] at (u, v) ∈ ℝ², period 1 in both.
double value_noise(double u, double v, Cells cells, std::uint32_t seed);

/// `octaves` octaves of value noise, each with twice the cells, in [0, 1].
double fbm(double u, double v, Cells cells, std::uint32_t seed, int octaves = 4);

/// fbm() along a row of fixed v: each octave's row terms are computed once and its four lattice
/// values only when u enters another cell, so a map's rows cost a fraction of calling fbm() per
/// pixel. The same values as fbm(), bit for bit.
class FbmRow {
public:
    FbmRow(double v, Cells cells, std::uint32_t seed, int octaves = 4);
    double operator()(double u);
    /// The values at the centres of a row of `width` pixels, u = (x + 0.5) / width: the same as
    /// operator() there, an octave at a time over the row (the loop vectorises).
    void fill(int width, std::vector<double>& out) const;

private:
    struct Octave {
        Cells cells;
        std::uint32_t seed_hash = 0;
        int j0 = 0, j1 = 0, cell = 0; ///< the row's cells; the cell u was last in (unwrapped)
        bool cached = false;
        double ty = 0, a = 0, b = 0, d = 0, e = 0;
    };
    static constexpr int MAX_OCTAVES = 8;
    Octave m_octaves[MAX_OCTAVES];
    int m_count = 0;
};

/// Cellular (Worley) noise: distances (in cell units) to the nearest and second-nearest
/// jittered feature point, and a random number of the nearest point's cell.
struct CellSample {
    double f1 = 0, f2 = 0, id = 0;
};
CellSample cellular(double u, double v, Cells cells, std::uint32_t seed);

} // namespace crackle::render
