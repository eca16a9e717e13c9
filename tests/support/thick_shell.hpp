#pragma once
/// @file Closed-form oracles for a layer bonded to a rigid background with a free top, shrinking
/// by an eigenstrain that varies linearly through its thickness: the plane-stress laminate on a
/// plane, and Lamé's thick cylinder (generalized plane strain) and thick sphere, solved as the
/// thermoelastic problems they are (Timoshenko & Goodier, "Theory of Elasticity", §150 and
/// §151: u(r) = (1 + ν)/(1 − ν)·(1/rⁿ)∫ₐʳ αT ρⁿ dρ + C₁ r + C₂ / rⁿ with n = 1 for the cylinder
/// and 2 for the sphere), with αT = −e(r) for a shrinkage e, u(R) = 0 at the bonded bottom and
/// σ_rr = 0 at the top. Written from the textbook, independently of the wedge code.

#include "core/math.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::test {

enum class Shell { Plane, Cylinder, Sphere };

/// The in-surface stresses (Pa) at a depth of a layer R ≤ r ≤ R + h (depth 0: bottom, 1: top):
/// the hoop stress and, on the cylinder, the axial one (on the sphere both are the hoop stress;
/// on the plane both are the laminate's biaxial stress).
struct ShellStress {
    double hoop = 0, axial = 0;
    double largest() const { return std::max(hoop, axial); }
};

/// The layer's stresses for a shrinkage e(r) linear from e_bottom at r = R to e_top at r = R + h
/// (positive = shrinks; the background is rigid and does not move).
inline ShellStress thick_shell_stress(Shell shell, double E, double nu, double R, double h, double e_bottom,
                                      double e_top, double depth) {
    auto e_at = [&](double r) { return e_bottom + (e_top - e_bottom) * (r - R) / h; };
    if (shell == Shell::Plane) {
        // A free-standing laminate held flat in its plane: σ_zz = 0, σ = E/(1 − ν)·e(z).
        const double s = E / (1 - nu) * e_at(R + depth * h);
        return {s, s};
    }
    const double n = shell == Shell::Cylinder ? 1.0 : 2.0;
    const double lambda = nu * E / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
    const double k = (1 + nu) / (1 - nu);
    // ∫ₐʳ αT ρⁿ dρ with αT = −e: e is linear in ρ, so the integral is exact in closed form.
    const double slope = (e_top - e_bottom) / h, e0 = e_bottom - slope * R; // e(ρ) = e0 + slope·ρ
    auto integral = [&](double r) {
        auto F = [&](double x) { return e0 * std::pow(x, n + 1) / (n + 1) + slope * std::pow(x, n + 2) / (n + 2); };
        return -(F(r) - F(R));
    };
    // u = k·I(r)/rⁿ + C₁ r + C₂ / rⁿ; the particular part and its derivative at r.
    auto u_p = [&](double r) { return k * integral(r) / std::pow(r, n); };
    auto du_p = [&](double r) { return k * (-e_at(r)) - n * k * integral(r) / std::pow(r, n + 1); };
    // Stresses from (u, u') with αT = −e: σ_rr = λ tr ε + 2μ ε_rr − (3λ + 2μ)αT, ε_zz = 0 (cylinder).
    auto stresses = [&](double r, double C1, double C2, double& s_rr, double& s_tt, double& s_zz) {
        const double u = u_p(r) + C1 * r + C2 / std::pow(r, n);
        const double du = du_p(r) + C1 - n * C2 / std::pow(r, n + 1);
        const double e_rr = du, e_tt = u / r;
        const double tr = e_rr + n * e_tt; // the sphere has two hoop directions
        const double thermal = (3 * lambda + 2 * mu) * (-e_at(r));
        s_rr = lambda * tr + 2 * mu * e_rr - thermal;
        s_tt = lambda * tr + 2 * mu * e_tt - thermal;
        s_zz = lambda * tr - thermal; // cylinder only
    };
    // u(R) = 0: C₂ = −C₁ Rⁿ⁺¹. σ_rr(R + h) = 0 is linear in C₁: solve from two evaluations.
    auto s_rr_top = [&](double C1) {
        double s_rr = 0, s_tt = 0, s_zz = 0;
        stresses(R + h, C1, -C1 * std::pow(R, n + 1), s_rr, s_tt, s_zz);
        return s_rr;
    };
    const double f0 = s_rr_top(0.0), f1 = s_rr_top(1.0);
    const double C1 = -f0 / (f1 - f0);
    double s_rr = 0, s_tt = 0, s_zz = 0;
    stresses(R + depth * h, C1, -C1 * std::pow(R, n + 1), s_rr, s_tt, s_zz);
    return {s_tt, shell == Shell::Cylinder ? s_zz : s_tt};
}

} // namespace crackle::test
