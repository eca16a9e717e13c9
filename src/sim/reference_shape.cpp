#include "sim/reference_shape.hpp"

namespace crackle::sim {

WedgeNodes reference_shape(const std::array<Vec3, 3>& bottom0, const Vec3& n, double height, double s_top,
                           double s_bot) {
    const Vec3 centroid = (bottom0[0] + bottom0[1] + bottom0[2]) / 3.0;
    const double top_scale = 1.0 - s_top;
    const double bottom_scale = 1.0 - s_bot;
    const double h = height * (1.0 - 0.5 * (s_top + s_bot));
    WedgeNodes nodes;
    for (std::size_t i = 0; i < 3; ++i) {
        const Vec3 r = bottom0[i] - centroid;
        nodes[i] = centroid + bottom_scale * r;
        nodes[i + 3] = centroid + h * n + top_scale * r;
    }
    return nodes;
}

} // namespace crackle::sim
