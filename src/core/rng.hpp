#pragma once
/// @file Deterministic random numbers: PCG32 (O'Neill 2014, "PCG: A family of simple fast
/// space-efficient statistically good algorithms"), one stream per pipeline stage.
/// No std::*_distribution: their output differs between standard libraries. Every mapping
/// from raw bits to numbers is written here (pbrt-v4: util/rng.h).

#include <cmath>
#include <cstdint>

namespace crackle {

/// The pipeline stages that draw random numbers, each on its own PCG stream, so that adding
/// draws in one stage never shifts the numbers another stage sees.
enum class RngStream : std::uint64_t {
    Sampling = 1, ///< point distribution (discretization)
    Material = 2, ///< property noise fields, threshold perturbation
    Fracture = 3, ///< tie breaking in the fracture models
    Post = 4,     ///< post-processing (per-piece variation)
    Bake = 5,     ///< colour variation while baking
    Test = 99,    ///< tests only
};

class Rng {
public:
    Rng(std::uint64_t seed, RngStream stream) { set_sequence(seed, static_cast<std::uint64_t>(stream)); }
    Rng(std::uint64_t seed, std::uint64_t stream) { set_sequence(seed, stream); }

    /// pcg32_srandom_r: seed the state and select the stream (the increment).
    void set_sequence(std::uint64_t seed, std::uint64_t stream) {
        m_state = 0u;
        m_inc = (stream << 1u) | 1u;
        next_u32();
        m_state += seed;
        next_u32();
    }

    /// pcg32_random_r: XSH-RR output of a 64-bit LCG.
    std::uint32_t next_u32() {
        const std::uint64_t old = m_state;
        m_state = old * MULTIPLIER + m_inc;
        const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
        const auto rot = static_cast<std::uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31u));
    }

    std::uint64_t next_u64() { return (std::uint64_t(next_u32()) << 32u) | next_u32(); }

    /// Uniform in [0, 1) with 53 random bits.
    double uniform() { return double(next_u64() >> 11u) * 0x1.0p-53; }

    /// Uniform in [a, b).
    double uniform(double a, double b) { return a + (b - a) * uniform(); }

    /// Uniform integer in [0, n), unbiased (rejection of the short last interval).
    std::uint32_t uniform_int(std::uint32_t n) {
        if (n <= 1) return 0;
        const std::uint32_t threshold = (~n + 1u) % n;
        for (;;) {
            const std::uint32_t r = next_u32();
            if (r >= threshold) return r % n;
        }
    }

    /// Standard normal deviate (Box–Muller, one of the pair).
    double normal() {
        const double u1 = 1.0 - uniform(); // (0, 1]
        const double u2 = uniform();
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * 3.14159265358979323846 * u2);
    }

private:
    static constexpr std::uint64_t MULTIPLIER = 0x5851f42d4c957f2dULL;
    std::uint64_t m_state = 0;
    std::uint64_t m_inc = 1;
};

} // namespace crackle
