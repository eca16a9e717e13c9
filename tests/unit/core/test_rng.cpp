#include "core/rng.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <vector>

using crackle::Rng;
using crackle::RngStream;

TEST_SUITE("core") {
    TEST_CASE("rng: matches the PCG32 reference output (pcg32-demo with seed 42 and stream 54)") {
        Rng rng(42u, std::uint64_t{54u});
        const std::array<std::uint32_t, 6> expected = {0xa15c02b7, 0x7b47f409, 0xba1d3330,
                                                       0x83d2f293, 0xbfa4784b, 0xcbed606e};
        for (std::uint32_t e : expected)
            CHECK(rng.next_u32() == e);
    }

    TEST_CASE("rng: same seed and stream give the same sequence while other streams and seeds differ") {
        Rng a(42, RngStream::Sampling), b(42, RngStream::Sampling);
        Rng c(42, RngStream::Material), d(43, RngStream::Sampling);
        int same_c = 0, same_d = 0;
        for (int i = 0; i < 1000; ++i) {
            const auto x = a.next_u32();
            CHECK(x == b.next_u32());
            same_c += x == c.next_u32();
            same_d += x == d.next_u32();
        }
        CHECK(same_c < 3);
        CHECK(same_d < 3);
    }

    TEST_CASE("rng: uniform() lies in the unit interval with mean 1/2 and variance 1/12") {
        Rng rng(7, RngStream::Test);
        const int n = 200000;
        double sum = 0, sum2 = 0;
        for (int i = 0; i < n; ++i) {
            const double u = rng.uniform();
            REQUIRE(u >= 0.0);
            REQUIRE(u < 1.0);
            sum += u;
            sum2 += u * u;
        }
        const double mean = sum / n, var = sum2 / n - mean * mean;
        // 5σ bands: σ(mean) = √(1/12/n) ≈ 6.5e-4
        CHECK(std::abs(mean - 0.5) < 5 * std::sqrt(1.0 / 12 / n));
        CHECK(std::abs(var - 1.0 / 12) < 2e-3);
    }

    TEST_CASE("rng: uniform_int(n) hits every value equally often (chi-square)") {
        Rng rng(11, RngStream::Test);
        const std::uint32_t k = 7;
        const int n = 70000;
        std::vector<int> count(k, 0);
        for (int i = 0; i < n; ++i) {
            const auto v = rng.uniform_int(k);
            REQUIRE(v < k);
            ++count[v];
        }
        double chi2 = 0;
        const double expected = double(n) / k;
        for (int c : count)
            chi2 += (c - expected) * (c - expected) / expected;
        CHECK(chi2 < 22.5); // p ≈ 0.001 for 6 degrees of freedom
        CHECK(rng.uniform_int(1) == 0);
        CHECK(rng.uniform_int(0) == 0);
    }

    TEST_CASE("rng: normal() has mean 0 and variance 1") {
        Rng rng(3, RngStream::Test);
        const int n = 200000;
        double sum = 0, sum2 = 0;
        for (int i = 0; i < n; ++i) {
            const double x = rng.normal();
            REQUIRE(std::isfinite(x));
            sum += x;
            sum2 += x * x;
        }
        CHECK(std::abs(sum / n) < 5.0 / std::sqrt(double(n)));
        CHECK(std::abs(sum2 / n - 1.0) < 0.02);
    }
}
