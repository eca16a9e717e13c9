#pragma once
/// @file The fillets of a groove's profile (render/groove.hpp): where a groove's slope turns
/// from the plate top's to its wall's and from the wall's to the floor's, at a bounded rate.

#include "core/math.hpp"

#include <algorithm>
#include <array>
#include <cstddef>

namespace crackle::render {

constexpr double MAX_WALL_DEG = 80.0; ///< the steepest wall a groove gets (a wider groove instead)

/// J(α, ξ) = ∫₀^ξ tan(α · S(t)ᵉ) dt, S = the fillet's turning (a circular arc with eased ends):
/// the depth a fillet of unit length reaches after ξ of it while the slope angle turns from 0
/// towards α (tabulated; cubic Hermite in ξ, linear in α). The exponent e ≥ 1 holds the slope
/// back towards the fillet's start: e = 1 is a V-like groove whose slope grows evenly, a larger e
/// a rounded ridge, flat on top and steep at the lip.
class FilletTable {
public:
    /// `lift` ≥ 1 steepens the relief the fillet is cut into (see Fillets): row α turns evenly
    /// in the slope angle that shows, atan(lift · tan α), and its slopes are divided by the lift.
    explicit FilletTable(double exponent, double lift = 1.0);
    /// The fastest the slope angle turns, in α per unit of fillet length: max of d/dt Sᵉ.
    double steepest_turn() const { return m_steepest; }
    /// J(α, ξ) (inline: the grooves read it at every pixel).
    double operator()(double alpha, double xi) const;

private:
    static constexpr int ALPHA_STEPS = 160, XI_STEPS = 64;
    static std::size_t index(int a, int x) { return static_cast<std::size_t>(a * (XI_STEPS + 1) + x); }
    std::array<float, (ALPHA_STEPS + 1) * (XI_STEPS + 1)> m_table{}, m_slope{};
    double m_steepest = 1.5;
};

inline double FilletTable::operator()(double alpha, double xi) const {
    const double fa = std::clamp(alpha / (MAX_WALL_DEG * PI / 180.0), 0.0, 1.0) * ALPHA_STEPS;
    const double fx = std::clamp(xi, 0.0, 1.0) * XI_STEPS;
    const int a = std::min(static_cast<int>(fa), ALPHA_STEPS - 1), x = std::min(static_cast<int>(fx), XI_STEPS - 1);
    const double sa = fa - a, sx = fx - x;
    // Cubic Hermite in ξ with the exact slopes (dJ/dξ = tan(α Sᵉ)): the groove's slope is
    // continuous between the table's nodes (linear interpolation would band the normals).
    const double h00 = (2 * sx - 3) * sx * sx + 1, h10 = ((sx - 2) * sx + 1) * sx, h01 = (3 - 2 * sx) * sx * sx,
                 h11 = (sx - 1) * sx * sx, step = 1.0 / XI_STEPS;
    auto at = [&](int row) {
        return h00 * m_table[index(row, x)] + h10 * step * m_slope[index(row, x)] + h01 * m_table[index(row, x + 1)]
               + h11 * step * m_slope[index(row, x + 1)];
    };
    return (1 - sa) * at(a) + sa * at(a + 1);
}

/// The lip fillet's table (its exponent from the groove's shape) and the floor fillet's. The
/// curl's lift scales the groove's height by `lift` (1 + curl) at the floor (the relief is
/// (top + lift) · (1 − share)), so the floor fillet turns evenly in the slope angle that shows,
/// atan(lift · tan θ), not in θ (its table is built so).
struct Fillets {
    FilletTable top, bottom;
    double lift = 1;

    double shown(double alpha) const;
};

} // namespace crackle::render
