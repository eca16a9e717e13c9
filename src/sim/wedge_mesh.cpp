#include "sim/wedge_mesh.hpp"

#include "core/error.hpp"

namespace crackle::sim {

WedgeMesh extrude_wedges(const mesh::SurfaceMesh& mesh, const mesh::Surface& surface, const PropertyField& thickness) {
    using mesh::face_id;
    const std::size_t nv = mesh.num_vertices();
    WedgeMesh w;
    w.num_bottom = nv;

    // === Thickness per vertex: area-weighted mean of the incident faces' averages
    std::vector<double> sum(nv, 0.0), weight(nv, 0.0);
    for (std::size_t fi = 0; fi < mesh.num_faces(); ++fi) {
        const mesh::FaceId f = face_id(fi);
        const double h = thickness.face_average(mesh, f, surface);
        CRACKLE_ASSERT(h > 0, "non-positive layer thickness " << h << " on face " << fi);
        const double a = mesh.face_area(f);
        for (mesh::VertexId v : mesh.faces[f].v) {
            sum[mesh::ix(v)] += a * h;
            weight[mesh::ix(v)] += a;
        }
    }
    w.vertex_thickness.resize(nv);
    for (std::size_t i = 0; i < nv; ++i)
        w.vertex_thickness[i] = weight[i] > 0 ? sum[i] / weight[i] : thickness.base();

    // === Bottom nodes on the background, top nodes along the surface normal
    w.nodes.resize(2 * nv);
    for (std::size_t i = 0; i < nv; ++i) {
        const Vec3& p = mesh.positions[mesh::vertex_id(i)];
        w.nodes[i] = p;
        w.nodes[nv + i] = p + surface.normal(p) * w.vertex_thickness[i];
    }
    w.wedges.resize(mesh.num_faces());
    for (std::size_t fi = 0; fi < mesh.num_faces(); ++fi) {
        const auto& face = mesh.faces[face_id(fi)];
        for (std::size_t k = 0; k < 3; ++k) {
            const auto v = static_cast<std::uint32_t>(mesh::ix(face.v[k]));
            w.wedges[fi][k] = v;
            w.wedges[fi][k + 3] = static_cast<std::uint32_t>(nv) + v;
        }
    }
    return w;
}

double WedgeMesh::wedge_volume(std::size_t wi, const mesh::SurfaceMesh& mesh) const {
    // Split the prism into three tetrahedra (bottom 0,1,2; top 3,4,5).
    const auto& wdg = wedges[wi];
    const auto f = mesh::face_id(wi);
    std::array<Vec3, 6> p;
    for (std::size_t k = 0; k < 3; ++k) {
        const Vec3 shift = mesh.corner_position(f, static_cast<int>(k)) - mesh.positions[mesh.faces[f].v[k]];
        p[k] = nodes[wdg[k]] + shift;
        p[k + 3] = nodes[wdg[k + 3]] + shift;
    }
    auto tet = [](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
        return (b - a).dot((c - a).cross(d - a)) / 6.0;
    };
    return tet(p[0], p[1], p[2], p[3]) + tet(p[1], p[2], p[3], p[4]) + tet(p[2], p[3], p[4], p[5]);
}

} // namespace crackle::sim
