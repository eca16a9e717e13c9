/// @file FemModel edge damage: graph-fem's broken edges on the wedge layer (graph-fem digest §1.6–1.7, §7.2–7.5).
#include "sim/fem_model_internal.hpp"

#include <algorithm>

namespace crackle::sim {

wedge::Mat6 FemModel::element_elasticity(FaceId f) const {
    const std::size_t fi = ix(f);
    const wedge::Mat6 D = wedge::elasticity(m_material[fi].young_modulus, m_fields.poisson_ratio);
    if (m_broken[fi] == 0) return D;
    // The projector is built on the reference shape the stiffness uses, so K, σ and the
    // criterion's edge directions agree.
    const wedge::Nodes ref = reference_nodes_at(fi, m_stiffness_s_top, m_stiffness_s_bot);
    return wedge::damaged_elasticity(D, wedge::edge_projector(ref, m_broken[fi]));
}

void FemModel::break_edges(const std::vector<std::pair<FaceId, int>>& sides) {
    std::vector<std::size_t> faces, vertices;
    auto mark = [&](FaceId f, int k) {
        CRACKLE_ASSERT(k >= 0 && k < 3, "edge index " << k);
        record_element(ix(f));
        m_broken[ix(f)] = static_cast<std::uint8_t>(m_broken[ix(f)] | (1u << k));
        faces.push_back(ix(f));
    };
    for (const auto& [f, k] : sides) {
        mark(f, k);
        const mesh::FaceNeighbor nb = m_mesh.neighbor(f, k);
        if (nb.face != mesh::NO_FACE) mark(nb.face, nb.edge);
    }
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    for (std::size_t f : faces) {
        build_element_stiffness(f);
        for (VertexId v : m_mesh.faces[face_id(f)].v)
            vertices.push_back(ix(v));
    }
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    update_around(vertices);
}

} // namespace crackle::sim
