// The channel-crack oracle (tests/support/cross_section.hpp), an independent 2D plane-strain
// model of a film's cross-section, checked against the literature and against itself: Beuth's
// (1992) Z for a film on a substrate of its own material, Clapeyron's theorem, mesh convergence,
// the closed-form energy of the uncracked film, and crack shielding at small spacing.

#include "support/accuracy.hpp"
#include "support/cross_section.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <ctime>
#include <string>

using namespace crackle;
namespace oracle = crackle::test::oracle;

namespace {

/// A film of unit thickness and modulus, Poisson's ratio ν, uniform shrinkage 10⁻³, on a rigid
/// base, channels W = `spacing` apart.
oracle::CrossSection rigid_section(double nu, double spacing) {
    oracle::CrossSection s;
    s.film.poisson = nu;
    s.spacing = spacing;
    return s;
}

/// The same film on an elastic substrate of depth H_s with the film's own E and ν.
oracle::CrossSection homogeneous_section(double depth, double spacing) {
    oracle::CrossSection s = rigid_section(0.3, spacing);
    s.substrate.rigid = false;
    s.substrate.depth = depth;
    s.substrate.young = s.film.young;
    s.substrate.poisson = s.film.poisson;
    return s;
}

/// Clapeyron: cracking releases the work of the uncracked crack-face traction σ(z) on the
/// opening, ½·∫₀ʰ σ·δ dz per unit channel advance, so G_ss = (1/(2h))·∫₀ʰ σ(z)·δ(z) dz with
/// σ(z) = E_f·s(z)/(1 − ν_f). δ is quadratic on each element's (corner, mid, corner) triple and
/// σ linear, so Simpson's rule on each triple is exact.
double release_rate_from_opening(const oracle::CrossSection& s, const oracle::ChannelResult& r) {
    const oracle::Film& f = s.film;
    const auto sigma = [&](double z) {
        const double shrinkage = f.shrinkage_bottom + (f.shrinkage_top - f.shrinkage_bottom) * z / f.thickness;
        return f.young * shrinkage / (1 - f.poisson);
    };
    double work = 0;
    for (std::size_t k = 0; k + 2 < r.opening.size(); k += 2) {
        const double z0 = r.opening_z[k], z1 = r.opening_z[k + 1], z2 = r.opening_z[k + 2];
        work += (z2 - z0) / 6
                * (sigma(z0) * r.opening[k] + 4 * sigma(z1) * r.opening[k + 1] + sigma(z2) * r.opening[k + 2]);
    }
    return work / (2 * f.thickness);
}

/// Uncracked film (closed form): ε_xx = ε_yy = 0 hold everywhere and σ_zz = 0, so each layer
/// carries the equibiaxial stress σ(z) = E·s(z)/(1 − ν), of energy density σ²·(1 − ν)/E =
/// E·s²/(1 − ν); the base or substrate is unstrained. Over the half-cell, with s linear,
/// U = (W/2)·E/(1 − ν)·∫₀ʰ s² dz = (W/2)·E/(1 − ν)·h·(s_b² + s_b·s_t + s_t²)/3.
double uncracked_energy(const oracle::CrossSection& s) {
    const oracle::Film& f = s.film;
    const double sb = f.shrinkage_bottom, st = f.shrinkage_top;
    return 0.5 * s.spacing * f.young / (1 - f.poisson) * f.thickness * (sb * sb + sb * st + st * st) / 3;
}

double relative_difference(double a, double b) {
    return std::abs(a - b) / std::abs(b);
}

} // namespace

TEST_SUITE("claims") {
    TEST_CASE("oracle channel: a film on a substrate of its own material gives Beuth's Z = 1.976") {
        // Beuth 1992 (Int. J. Solids Struct. 29:1657) and Hutchinson & Suo 1992 (Adv. Appl. Mech.
        // 29, table of Z for channel cracking, α = β = 0): Z = 1.976. A substrate 40 h deep under a half-cell 40 h
        // wide; the finite domain (fixed bottom, neighbouring channels 80 h away) lowers Z by ~0.2 %.
        const oracle::CrossSection s = homogeneous_section(40.0, 80.0);
        const oracle::ChannelResult r = oracle::channel_crack(s);
        CAPTURE(r.z);
        CAPTURE(r.elements);
        test::record_claim("oracle channel", "Z of a film on a substrate of its own material (Beuth 1992: 1.976)",
                           "Z, nu = 0.3, H_s = W/2 = 40 h", r.z, "within 1.5 % of 1.976");
        CHECK(r.z == doctest::Approx(1.976).epsilon(0.015));
    }

    TEST_CASE("oracle channel: G_ss from the energies equals the work of the crack-face traction on the opening") {
        // Uniform shrinkage on a rigid base, and a shrinkage gradient (s_top = 3·s_bottom) on a
        // substrate twice as stiff.
        oracle::CrossSection uniform = rigid_section(0.3, 20.0);
        oracle::CrossSection gradient = homogeneous_section(10.0, 20.0);
        gradient.film.shrinkage_top = 3 * gradient.film.shrinkage_bottom;
        gradient.substrate.young = 2 * gradient.film.young;
        for (const oracle::CrossSection& s : {uniform, gradient}) {
            const oracle::ChannelResult r = oracle::channel_crack(s);
            const double from_opening = release_rate_from_opening(s, r);
            const double mismatch = relative_difference(from_opening, r.release_rate);
            CAPTURE(s.substrate.rigid);
            CAPTURE(r.release_rate);
            CAPTURE(from_opening);
            test::record_claim("oracle channel", "Clapeyron: energy difference = work of released traction",
                               s.substrate.rigid ? "|G_opening/G_energy - 1|, rigid base, uniform"
                                                 : "|G_opening/G_energy - 1|, substrate, gradient",
                               mismatch, "< 0.005");
            CHECK(r.release_rate > 0);
            CHECK(r.opening.front() == 0.0); // held closed at the root
            CHECK(r.opening.back() > 0);
            CHECK(mismatch < 0.005);
        }
    }

    TEST_CASE("oracle channel: Z on a rigid base converges under mesh refinement") {
        // Three meshes, each graded more finely towards the crack root (Hutchinson & Suo 1992:
        // the root is singular); Z is an energy, so it converges fast. The middle one is
        // channel_z_rigid's (the default Grading).
        const std::array<oracle::Grading, 3> meshes = {{{1e-3, 1.6, 0.5}, {1e-4, 1.4, 0.5}, {1e-5, 1.25, 0.3}}};
        for (const double nu : {0.3, 0.45}) {
            CAPTURE(nu);
            std::array<double, 3> z{};
            std::array<int, 3> elements{};
            for (std::size_t k = 0; k < 3; ++k) {
                oracle::CrossSection s = rigid_section(nu, 20.0);
                s.grading = meshes[k];
                const oracle::ChannelResult r = oracle::channel_crack(s);
                z[k] = r.z;
                elements[k] = r.elements;
            }
            CAPTURE(z[0]);
            CAPTURE(z[1]);
            CAPTURE(z[2]);
            const double change = relative_difference(z[1], z[2]);
            const std::clock_t start = std::clock();
            const double z_default = oracle::channel_z_rigid(nu);
            const double cpu_s = double(std::clock() - start) / CLOCKS_PER_SEC;
            const double default_error = relative_difference(z_default, z[2]);
            const std::string at = "nu = " + std::string(nu == 0.3 ? "0.3" : "0.45");
            test::record_claim("oracle channel", "Z converges on a rigid base",
                               "|Z(2nd finest) / Z(finest) - 1|, " + at + ", " + std::to_string(elements[1]) + " vs "
                                   + std::to_string(elements[2]) + " elements",
                               change, "< 0.003");
            test::record_claim("oracle channel", "Z of an isolated channel on a rigid base",
                               "Z_rigid, " + at + ", " + std::to_string(elements[2]) + " elements", z[2],
                               nu == 0.3 ? "within 0.5 % of 1.087 (Python Q9 prototype)" : "recorded");
            test::record_claim("oracle channel", "channel_z_rigid is converged",
                               "|channel_z_rigid / Z(finest) - 1|, " + at, default_error, "< 0.003");
            // CPU time is checked, not recorded: scripts/accuracy-check compares recorded values
            // with docs/accuracy.md, and a time is not deterministic.
            CHECK(change < 0.003);
            CHECK(default_error < 0.003);
#ifdef __OPTIMIZE__ // unoptimized (Debug) Eigen is tens of times slower
            CHECK(cpu_s < 1.0);
#else
            (void)cpu_s;
#endif
            if (nu == 0.3) CHECK(z[2] == doctest::Approx(1.087).epsilon(0.005));
        }
        // A very stiff substrate (E_s = 10⁴·E_f) behaves as the rigid base.
        oracle::CrossSection stiff = homogeneous_section(20.0, 40.0);
        stiff.substrate.young = 1e4 * stiff.film.young;
        const double z_stiff = oracle::channel_crack(stiff).z;
        const double z_rigid = oracle::channel_z_rigid(0.3);
        CAPTURE(z_stiff);
        CAPTURE(z_rigid);
        test::record_claim("oracle channel", "a stiff substrate acts as a rigid base",
                           "|Z(E_s = 1e4 E_f) / Z_rigid - 1|", relative_difference(z_stiff, z_rigid), "< 0.001");
        CHECK(z_stiff == doctest::Approx(z_rigid).epsilon(0.001));
    }

    TEST_CASE("oracle channel: the uncracked energy equals the closed form") {
        for (const bool rigid : {true, false}) {
            for (const double top : {1e-3, -2e-3}) {
                oracle::CrossSection s = rigid ? rigid_section(0.3, 6.0) : homogeneous_section(3.0, 6.0);
                s.film.shrinkage_top = top; // 1e-3: uniform; −2e-3: a gradient through zero
                s.substrate.young = 3 * s.film.young;
                const oracle::ChannelResult r = oracle::channel_crack(s);
                const double exact = uncracked_energy(s);
                const double error = relative_difference(r.energy_uncracked, exact);
                CAPTURE(rigid);
                CAPTURE(top);
                CAPTURE(r.energy_uncracked);
                CAPTURE(exact);
                test::record_claim("oracle channel", "uncracked energy = closed form",
                                   std::string("relative error, ") + (rigid ? "rigid base" : "substrate")
                                       + (top == 1e-3 ? ", uniform" : ", gradient"),
                                   error, "< 1e-9");
                CHECK(error < 1e-9);
                CHECK(r.energy_cracked < r.energy_uncracked);
            }
        }
    }

    TEST_CASE("oracle channel: closely spaced channels on a rigid base shield each other") {
        // Hutchinson & Suo 1992: when the spacing W is comparable to h, the stress between
        // channels is already partly relaxed and the next channel releases less energy.
        const double z_close = oracle::channel_z_rigid(0.3, 2.0);
        const double z_far = oracle::channel_z_rigid(0.3, 24.0);
        CAPTURE(z_close);
        CAPTURE(z_far);
        test::record_claim("oracle channel", "channels shield each other", "Z_rigid, nu = 0.3, W = 2 h", z_close,
                           "< 0.9 Z(W = 24 h)");
        test::record_claim("oracle channel", "channels shield each other", "Z_rigid, nu = 0.3, W = 24 h", z_far,
                           "> Z(W = 2 h)");
        CHECK(z_close < 0.9 * z_far);
    }
}
