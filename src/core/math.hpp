#pragma once
/// @file Eigen aliases, small numeric helpers and constants shared by every stage.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace crackle {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec2i = Eigen::Vector2i;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;

constexpr double PI = std::numbers::pi;
constexpr double TWO_PI = 2.0 * std::numbers::pi;
constexpr double DEG_TO_RAD = std::numbers::pi / 180.0;
constexpr double RAD_TO_DEG = 180.0 / std::numbers::pi;

template <typename T> constexpr T sqr(T x) {
    return x * x;
}

/// √max(x, 0): guards against tiny negative round-off (pbrt's SafeSqrt).
inline double safe_sqrt(double x) {
    return std::sqrt(std::max(x, 0.0));
}

/// Wraps x into [0, period).
inline double wrap(double x, double period) {
    double r = std::fmod(x, period);
    if (r < 0) r += period;
    if (r >= period) r = 0.0; // fmod round-off can land exactly on period
    return r;
}

inline double clamp01(double x) {
    return std::clamp(x, 0.0, 1.0);
}

} // namespace crackle
