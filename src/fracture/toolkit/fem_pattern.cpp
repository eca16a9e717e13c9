#include "fracture/toolkit/fem_pattern.hpp"

#include <algorithm>

namespace crackle::fracture {

using mesh::face_id;
using mesh::ix;

CrackPattern pattern_from_model(const sim::FemModel& model, const std::string& method, std::size_t elements_initial) {
    CrackPattern p;
    p.method = method;
    p.surface = model.surface();
    p.mesh = model.mesh();
    p.final_time = model.time();
    p.elements_initial = elements_initial;
    const std::size_t nv = p.mesh.num_vertices(), nf = p.mesh.num_faces();
    p.deformed.resize(nv);
    p.thickness.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        p.deformed[v] = model.top_position(mesh::vertex_id(v));
        p.thickness[v] = model.vertex_thickness(mesh::vertex_id(v));
    }
    for (int i = 0; i < 2; ++i)
        p.deformed_period[static_cast<std::size_t>(i)] =
            model.growth().period_shift(p.mesh.period_vectors[static_cast<std::size_t>(i)], model.time());
    p.removed.resize(nf);
    p.young_modulus.resize(nf);
    for (std::size_t f = 0; f < nf; ++f) {
        p.removed[f] = model.alive(face_id(f)) ? 0 : 1;
        p.young_modulus[f] = model.material(face_id(f)).young_modulus;
    }
    p.poisson_ratio = model.poisson_ratio();
    p.growth_map = Mat3::Identity() + model.time() * model.growth().tensor();
    label_fragments(p);
    // Crack lips: intact edges facing a removed element; the opening is the removed
    // element's deformed height over that edge, its depth the layer thickness.
    for (CrackEdge c : removal_crack_lips(p)) {
        const int k = c.edge;
        const mesh::FaceNeighbor nb = p.mesh.neighbor(c.face, k);
        const Vec3 a = p.deformed_corner(c.face, k), b = p.deformed_corner(c.face, (k + 1) % 3);
        if (nb.face != mesh::NO_FACE) {
            const Vec3 far = p.deformed_corner(nb.face, (nb.edge + 2) % 3);
            c.opening = (far - a).cross(b - a).norm() / std::max((b - a).norm(), 1e-300);
        }
        const auto& face = p.mesh.faces[c.face];
        c.depth = 0.5
                  * (p.thickness[ix(face.v[static_cast<std::size_t>(k)])]
                     + p.thickness[ix(face.v[static_cast<std::size_t>((k + 1) % 3)])]);
        p.cracks.push_back(c);
    }
    return p;
}

} // namespace crackle::fracture
