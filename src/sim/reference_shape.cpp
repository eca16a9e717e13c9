#include "sim/reference_shape.hpp"

namespace crackle::sim {

WedgeNodes reference_shape(const std::array<Vec3, 3>& bottom0, const Vec3& n, double height, double s_top,
                           double s_bot) {
    return reference_shape(bottom0, {n, n, n}, {height, height, height}, s_top, s_bot);
}

WedgeNodes reference_shape(const std::array<Vec3, 3>& bottom0, const std::array<Vec3, 3>& normals,
                           const std::array<double, 3>& heights, double s_top, double s_bot) {
    // Federl 2002, §3.3.2, Fig. 3.10: scale about the bottom centroid, lift by h' = h(1 − ½(s_top + s_bot)).
    // With a normal and a height per corner the unshrunk top face is not the bottom face lifted:
    // on a curved background it is larger (its corners are h_i·n_i above the bottom ones, and the
    // normals spread). The top material shrinks by s_top about the top face's own centroid, so
    // its spread shrinks with it; only the mean lift t̄ takes the thickness' shrinkage. (Scaling
    // only the bottom triangle's offsets by 1 − s_top would shrink the top of a layer of radius
    // R + h by s_top·R/(R + h), not s_top: too little where the top shrinks faster.)
    const Vec3 centroid = (bottom0[0] + bottom0[1] + bottom0[2]) / 3.0;
    const double height_scale = 1.0 - 0.5 * (s_top + s_bot);
    const Vec3 lift = (heights[0] * normals[0] + heights[1] * normals[1] + heights[2] * normals[2]) / 3.0;
    WedgeNodes nodes;
    for (std::size_t i = 0; i < 3; ++i) {
        const Vec3 r = bottom0[i] - centroid;
        const Vec3 spread = heights[i] * normals[i] - lift;
        nodes[i] = centroid + (1.0 - s_bot) * r;
        nodes[i + 3] = centroid + (1.0 - s_top) * (r + spread) + height_scale * lift;
    }
    return nodes;
}

} // namespace crackle::sim
