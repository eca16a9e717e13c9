#include "render/fillet.hpp"

#include "core/math.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::render {

namespace {

/// The share of a fillet over which its turning rate ramps up (and down again at its end).
constexpr double RAMP = 0.15;

/// A fillet's slope angle, as a share of its wall's, at t ∈ [0, 1] of its length: the rate of
/// turning ramps up linearly over RAMP of the fillet, holds, and ramps down over the last RAMP
/// (a circular arc with eased ends: its fastest turn is 1 / (1 − RAMP) of the mean, where a
/// smoothstep's is 1.5, so the fillet is that much shorter for the same bound per pixel).
double turned(double t) {
    t = std::clamp(t, 0.0, 1.0);
    const double rate = 1.0 / (1.0 - RAMP);
    if (t < RAMP) return 0.5 * rate * t * t / RAMP;
    if (t > 1.0 - RAMP) return 1.0 - 0.5 * rate * (1.0 - t) * (1.0 - t) / RAMP;
    return rate * (0.5 * RAMP + (t - RAMP));
}

} // namespace

FilletTable::FilletTable(double exponent, double lift) {
    m_steepest = 0;
    for (int k = 0; k < 1000; ++k) {
        const double t0 = k / 1000.0, t1 = (k + 1) / 1000.0;
        m_steepest = std::max(m_steepest, (std::pow(turned(t1), exponent) - std::pow(turned(t0), exponent)) * 1000.0);
    }
    const double max_alpha = MAX_WALL_DEG * PI / 180.0;
    for (int a = 0; a <= ALPHA_STEPS; ++a) {
        const double alpha = std::atan(lift * std::tan(max_alpha * a / ALPHA_STEPS));
        double sum = 0;
        m_table[index(a, 0)] = 0;
        for (int k = 0; k <= XI_STEPS; ++k)
            m_slope[index(a, k)] =
                static_cast<float>(std::tan(alpha * std::pow(turned(double(k) / XI_STEPS), exponent)) / lift);
        constexpr int SUB = 16; // Simpson's rule on each ξ step
        for (int k = 0; k < XI_STEPS; ++k) {
            const double x0 = double(k) / XI_STEPS, h = 1.0 / XI_STEPS / SUB;
            for (int s = 0; s < SUB; ++s) {
                const double t0 = x0 + s * h;
                auto f = [&](double t) { return std::tan(alpha * std::pow(turned(t), exponent)) / lift; };
                sum += h / 6 * (f(t0) + 4 * f(t0 + h / 2) + f(t0 + h));
            }
            m_table[index(a, k + 1)] = static_cast<float>(sum);
        }
    }
}

double Fillets::shown(double alpha) const {
    return std::atan(lift * std::tan(alpha));
}

} // namespace crackle::render
