#include "io/mesh_export.hpp"

namespace crackle::io {

ExportMesh export_mesh(const post::PieceMesh& pieces) {
    ExportMesh m;
    const std::size_t n = pieces.vertices.size();
    m.positions.reserve(3 * n);
    m.normals.reserve(3 * n);
    m.uvs.reserve(2 * n);
    for (int c = 0; c < 3; ++c) {
        m.min[static_cast<std::size_t>(c)] = std::numeric_limits<float>::max();
        m.max[static_cast<std::size_t>(c)] = std::numeric_limits<float>::lowest();
    }
    for (const post::PieceVertex& v : pieces.vertices) {
        for (int c = 0; c < 3; ++c) {
            const auto x = static_cast<float>(v.position[c]);
            m.positions.push_back(x);
            m.min[static_cast<std::size_t>(c)] = std::min(m.min[static_cast<std::size_t>(c)], x);
            m.max[static_cast<std::size_t>(c)] = std::max(m.max[static_cast<std::size_t>(c)], x);
            m.normals.push_back(static_cast<float>(v.world_normal[c]));
        }
        m.uvs.push_back(static_cast<float>(v.uv.x()));
        m.uvs.push_back(static_cast<float>(1.0 - v.uv.y())); // glTF and OBJ viewers: origin at the top
    }
    // === Tangents: accumulate ∂P/∂u per triangle, orthogonalise against the normal
    std::vector<Vec3> tan(n, Vec3::Zero()), bitan(n, Vec3::Zero());
    for (const auto& tri : pieces.triangles) {
        const post::PieceVertex &a = pieces.vertices[tri[0]], &b = pieces.vertices[tri[1]],
                                &c = pieces.vertices[tri[2]];
        const Vec3 e1 = b.position - a.position, e2 = c.position - a.position;
        const Vec2 d1(b.uv.x() - a.uv.x(), (1 - b.uv.y()) - (1 - a.uv.y()));
        const Vec2 d2(c.uv.x() - a.uv.x(), (1 - c.uv.y()) - (1 - a.uv.y()));
        const double det = d1.x() * d2.y() - d2.x() * d1.y();
        if (std::abs(det) < 1e-20) continue;
        const Vec3 t = (e1 * d2.y() - e2 * d1.y()) / det;
        const Vec3 bt = (e2 * d1.x() - e1 * d2.x()) / det;
        for (std::uint32_t i : tri) {
            tan[i] += t;
            bitan[i] += bt;
        }
        m.indices.insert(m.indices.end(), tri.begin(), tri.end());
    }
    // Triangles too thin in UV to define a tangent still belong to the mesh.
    if (m.indices.size() != 3 * pieces.triangles.size()) {
        m.indices.clear();
        for (const auto& tri : pieces.triangles)
            m.indices.insert(m.indices.end(), tri.begin(), tri.end());
    }
    m.tangents.reserve(4 * n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 nrm = pieces.vertices[i].world_normal.normalized();
        Vec3 t = tan[i] - nrm * nrm.dot(tan[i]);
        if (t.norm() < 1e-12) {
            // No UV gradient here (a wall seen edge-on in texture space): any unit tangent.
            t = nrm.cross(std::abs(nrm.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX());
        }
        t.normalize();
        const double w = nrm.cross(t).dot(bitan[i]) < 0 ? -1.0 : 1.0;
        for (int c = 0; c < 3; ++c)
            m.tangents.push_back(static_cast<float>(t[c]));
        m.tangents.push_back(static_cast<float>(w));
    }
    return m;
}

} // namespace crackle::io
