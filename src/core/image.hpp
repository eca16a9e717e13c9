#pragma once
/// @file Plain image buffers shared between stages (io reads/writes them, render fills them).

#include "core/math.hpp"

#include <cstdint>
#include <vector>

namespace crackle {

/// A single-channel floating-point image, row-major, row 0 at the top (v = 0 at the top edge,
/// matching how PNGs are stored and viewed).
struct GrayImage {
    int width = 0;
    int height = 0;
    std::vector<float> pixels; ///< width·height values, usually in [0, 1]

    float at(int x, int y) const {
        return pixels[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
    }
    float& at(int x, int y) {
        return pixels[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)];
    }

    /// Bilinear sample at texture coordinates (u, v) ∈ [0,1]², wrapping around both borders.
    double sample_wrapped(double u, double v) const;
};

inline double GrayImage::sample_wrapped(double u, double v) const {
    const double x = wrap(u, 1.0) * width - 0.5;
    const double y = wrap(v, 1.0) * height - 0.5;
    const double fx = std::floor(x), fy = std::floor(y);
    const double tx = x - fx, ty = y - fy;
    auto px = [&](double xi, double yi) {
        const int xw = static_cast<int>(wrap(xi, width));
        const int yw = static_cast<int>(wrap(yi, height));
        return static_cast<double>(at(xw, yw));
    };
    return (1 - tx) * (1 - ty) * px(fx, fy) + tx * (1 - ty) * px(fx + 1, fy) + (1 - tx) * ty * px(fx, fy + 1)
           + tx * ty * px(fx + 1, fy + 1);
}

} // namespace crackle
