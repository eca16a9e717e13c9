/// @file FemModel stresses at the top Gauss points, rates, fracture ratio, strain energy (Federl 2002, §5.6.1).
#include "sim/fem_model_internal.hpp"

#include <algorithm>
#include <limits>

namespace crackle::sim {

// === Stress

TopStress FemModel::top_stress_of(std::size_t f, const VecX& q) const {
    // B from the reference shape the stiffness was built with, so σ is consistent with K.
    const wedge::Nodes ref = reference_nodes_at(f, m_stiffness_s_top, m_stiffness_s_bot);
    const wedge::Mat6 D = element_elasticity(face_id(f));
    TopStress s;
    for (std::size_t k = 0; k < 3; ++k) {
        const auto& g = wedge::quadrature()[static_cast<std::size_t>(wedge::TOP_GAUSS_POINTS[k])];
        // The linear wedge (§5.6.1): at the Gauss points nearest the top, where its stress is
        // most accurate. With modes the strain varies through the thickness as the layer's does,
        // and cracks start on the top face itself: the same points at ζ = 1.
        s[k] = m_order == 1 ? wedge::stress(ref, D, wedge::Vec18(q), g.xi, g.eta, g.zeta)
                            : wedge::stress(ref, D, q, m_order, g.xi, g.eta, 1.0);
    }
    return s;
}

TopStress FemModel::top_stress(FaceId f) const {
    return top_stress_of(ix(f), displacement(ix(f)));
}

TopStress FemModel::top_stress_rate(FaceId f) const {
    return top_stress_of(ix(f), displacement_rate(ix(f)));
}

double FemModel::stress_ratio(FaceId f) const {
    double best = -std::numeric_limits<double>::infinity();
    for (const wedge::Vec6& s : top_stress(f))
        best = std::max(best, wedge::max_principal(s).value);
    return best / m_material[ix(f)].threshold_stress;
}

namespace {
/// ½ qᵀ K q, with fixed-size products for the linear wedge.
double half_qkq(const VecX& q, const MatX& K) {
    return 0.5 * q.dot(K * q);
}
} // namespace

double FemModel::strain_energy() const {
    double e = 0;
    for (std::size_t f = 0; f < m_mesh.num_faces(); ++f)
        if (m_alive[f]) e += element_energy(f);
    return e;
}

double FemModel::strain_energy(const std::vector<FaceId>& faces) const {
    double e = 0;
    for (FaceId f : faces)
        if (m_alive[ix(f)]) e += element_energy(ix(f));
    return e;
}

double FemModel::element_energy(std::size_t f) const {
    const VecX q = displacement(f);
    if (m_order > 1) return half_qkq(q, element_stiffness(f));
    const wedge::Nodes ref = reference_nodes_at(f, m_stiffness_s_top, m_stiffness_s_bot);
    const wedge::Vec18 q18 = q;
    return 0.5 * q18.dot(wedge::stiffness(ref, element_elasticity(face_id(f))) * q18);
}

} // namespace crackle::sim
