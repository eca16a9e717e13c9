#include "sim/reference_shape.hpp"

namespace crackle::sim {

WedgeNodes reference_shape(const std::array<Vec3, 3>& bottom0, const Vec3& n, double height, double s_top,
                           double s_bot) {
    return reference_shape(bottom0, {n, n, n}, {height, height, height}, s_top, s_bot);
}

WedgeNodes reference_shape(const std::array<Vec3, 3>& bottom0, const std::array<Vec3, 3>& normals,
                           const std::array<double, 3>& heights, double s_top, double s_bot) {
    // Federl 2002, §3.3.2, Fig. 3.10: scale about the bottom centroid, lift by h' = h(1 − ½(s_top + s_bot)).
    const Vec3 centroid = (bottom0[0] + bottom0[1] + bottom0[2]) / 3.0;
    const double height_scale = 1.0 - 0.5 * (s_top + s_bot);
    WedgeNodes nodes;
    for (std::size_t i = 0; i < 3; ++i) {
        const Vec3 r = bottom0[i] - centroid;
        nodes[i] = centroid + (1.0 - s_bot) * r;
        nodes[i + 3] = centroid + (1.0 - s_top) * r + height_scale * heights[i] * normals[i];
    }
    return nodes;
}

} // namespace crackle::sim
