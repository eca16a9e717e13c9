#pragma once
/// @file Central finite differences for checking derivatives (ipc-toolkit: fd::finite_jacobian).

#include "core/math.hpp"

#include <functional>

namespace crackle::test {

/// Numerical Jacobian J_ij = ∂f_i/∂x_j of a map R³ → R³ by central differences.
inline Mat3 finite_jacobian(const std::function<Vec3(const Vec3&)>& f, const Vec3& x, double h = 1e-6) {
    Mat3 J;
    for (int j = 0; j < 3; ++j) {
        Vec3 e = Vec3::Zero();
        e[j] = h;
        J.col(j) = (f(x + e) - f(x - e)) / (2 * h);
    }
    return J;
}

} // namespace crackle::test
