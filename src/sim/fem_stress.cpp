/// @file FemModel stresses at the top Gauss points, rates, fracture ratio, strain energy (Federl 2002, §5.6.1).
#include "sim/fem_model_internal.hpp"

#include <algorithm>
#include <limits>

namespace crackle::sim {

// === Stress

TopStress FemModel::top_stress_of(std::size_t f, const wedge::Vec18& q) const {
    // B from the reference shape the stiffness was built with, so σ is consistent with K.
    const wedge::Nodes ref = reference_nodes_at(f, m_stiffness_s_top, m_stiffness_s_bot);
    const wedge::Mat6 D = element_elasticity(face_id(f));
    TopStress s;
    for (std::size_t k = 0; k < 3; ++k) {
        const auto& g = wedge::quadrature()[static_cast<std::size_t>(wedge::TOP_GAUSS_POINTS[k])];
        s[k] = wedge::stress(ref, D, q, g.xi, g.eta, g.zeta);
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

double FemModel::strain_energy() const {
    double e = 0;
    for (std::size_t f = 0; f < m_mesh.num_faces(); ++f) {
        if (!m_alive[f]) continue;
        const wedge::Nodes ref = reference_nodes_at(f, m_stiffness_s_top, m_stiffness_s_bot);
        const wedge::Vec18 q = displacement(f);
        e += 0.5 * q.dot(wedge::stiffness(ref, element_elasticity(face_id(f))) * q);
    }
    return e;
}

double FemModel::strain_energy(const std::vector<FaceId>& faces) const {
    double e = 0;
    for (FaceId f : faces) {
        const std::size_t fi = ix(f);
        if (!m_alive[fi]) continue;
        const wedge::Nodes ref = reference_nodes_at(fi, m_stiffness_s_top, m_stiffness_s_bot);
        const wedge::Vec18 q = displacement(fi);
        e += 0.5 * q.dot(wedge::stiffness(ref, element_elasticity(f)) * q);
    }
    return e;
}

} // namespace crackle::sim
