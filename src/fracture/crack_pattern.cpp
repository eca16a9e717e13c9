#include "fracture/crack_pattern.hpp"

namespace crackle::fracture {

Vec3 CrackPattern::deformed_corner(mesh::FaceId f, int k) const {
    const mesh::Face& face = mesh.faces[f];
    const Vec2i& o = face.offset[static_cast<std::size_t>(k)];
    return deformed[mesh::ix(face.v[static_cast<std::size_t>(k)])] + o.x() * deformed_period[0]
           + o.y() * deformed_period[1];
}

void label_fragments(CrackPattern& p) {
    const std::size_t nf = p.mesh.num_faces();
    p.fragment.assign(nf, -1);
    p.num_fragments = 0;
    std::vector<std::uint32_t> stack;
    for (std::size_t seed = 0; seed < nf; ++seed) {
        if (p.removed[seed] || p.fragment[seed] >= 0) continue;
        const int label = p.num_fragments++;
        p.fragment[seed] = label;
        stack.assign(1, static_cast<std::uint32_t>(seed));
        while (!stack.empty()) {
            const std::uint32_t f = stack.back();
            stack.pop_back();
            for (int k = 0; k < 3; ++k) {
                const mesh::FaceNeighbor nb = p.mesh.neighbor(mesh::face_id(f), k);
                if (nb.face == mesh::NO_FACE) continue;
                const std::size_t g = mesh::ix(nb.face);
                if (p.removed[g] || p.fragment[g] >= 0) continue;
                p.fragment[g] = label;
                stack.push_back(static_cast<std::uint32_t>(g));
            }
        }
    }
}

std::vector<CrackEdge> removal_crack_lips(const CrackPattern& p) {
    std::vector<CrackEdge> lips;
    for (std::size_t fi = 0; fi < p.mesh.num_faces(); ++fi) {
        if (p.removed[fi]) continue;
        for (int k = 0; k < 3; ++k) {
            const mesh::FaceNeighbor nb = p.mesh.neighbor(mesh::face_id(fi), k);
            if (nb.face != mesh::NO_FACE && !p.removed[mesh::ix(nb.face)]) continue;
            CrackEdge c;
            c.face = mesh::face_id(fi);
            c.edge = k;
            lips.push_back(c);
        }
    }
    return lips;
}

} // namespace crackle::fracture
