#include "io/mesh_export.hpp"

#include <limits>
#include <map>

namespace crackle::io {

namespace {

/// A group of the piece mesh's triangles with its own vertices, in the exchange frame.
struct Group {
    std::vector<std::uint32_t> source;                   ///< local vertex → piece vertex
    std::vector<Vec3> position, normal;                  ///< per local vertex, Y-up
    std::vector<std::array<std::uint32_t, 3>> triangles; ///< local indices
};

Group gather(const post::PieceMesh& pieces, const std::vector<std::size_t>& triangles) {
    Group g;
    std::vector<std::uint32_t> local(pieces.vertices.size(), std::numeric_limits<std::uint32_t>::max());
    for (std::size_t t : triangles) {
        std::array<std::uint32_t, 3> tri{};
        for (std::size_t k = 0; k < 3; ++k) {
            const std::uint32_t v = pieces.triangles[t][k];
            if (local[v] == std::numeric_limits<std::uint32_t>::max()) {
                local[v] = static_cast<std::uint32_t>(g.source.size());
                g.source.push_back(v);
                g.position.push_back(to_y_up(pieces.vertices[v].position));
                g.normal.push_back(to_y_up(pieces.vertices[v].world_normal));
            }
            tri[k] = local[v];
        }
        // post::build_pieces winds every triangle counter-clockwise seen from outside.
        g.triangles.push_back(tri);
    }
    return g;
}

/// glTF's texture coordinates: origin at the top left, so v flips.
Vec2 gltf_uv(const post::PieceVertex& v) {
    return {v.uv.x(), 1.0 - v.uv.y()};
}

ExportMesh flatten(const post::PieceMesh& pieces, const Group& g) {
    ExportMesh m;
    const std::size_t n = g.source.size();
    m.positions.reserve(3 * n);
    m.normals.reserve(3 * n);
    m.uvs.reserve(2 * n);
    m.min.fill(std::numeric_limits<float>::max());
    m.max.fill(std::numeric_limits<float>::lowest());
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t c = 0; c < 3; ++c) {
            const auto x = static_cast<float>(g.position[i][static_cast<Eigen::Index>(c)]);
            m.positions.push_back(x);
            m.min[c] = std::min(m.min[c], x);
            m.max[c] = std::max(m.max[c], x);
            m.normals.push_back(static_cast<float>(g.normal[i][static_cast<Eigen::Index>(c)]));
        }
        const Vec2 uv = gltf_uv(pieces.vertices[g.source[i]]);
        m.uvs.push_back(static_cast<float>(uv.x()));
        m.uvs.push_back(static_cast<float>(uv.y()));
    }
    // === Tangents: accumulate ∂P/∂u and ∂P/∂v per triangle, orthogonalise against the normal
    std::vector<Vec3> tan(n, Vec3::Zero()), bitan(n, Vec3::Zero());
    for (const auto& tri : g.triangles) {
        const Vec3 e1 = g.position[tri[1]] - g.position[tri[0]], e2 = g.position[tri[2]] - g.position[tri[0]];
        const Vec2 uv0 = gltf_uv(pieces.vertices[g.source[tri[0]]]);
        const Vec2 d1 = gltf_uv(pieces.vertices[g.source[tri[1]]]) - uv0;
        const Vec2 d2 = gltf_uv(pieces.vertices[g.source[tri[2]]]) - uv0;
        m.indices.insert(m.indices.end(), tri.begin(), tri.end());
        // Triangles too thin in UV to define a tangent still belong to the mesh.
        const double det = d1.x() * d2.y() - d2.x() * d1.y();
        if (std::abs(det) < 1e-20) continue;
        const Vec3 t = (e1 * d2.y() - e2 * d1.y()) / det;
        const Vec3 bt = (e2 * d1.x() - e1 * d2.x()) / det;
        for (std::uint32_t i : tri) {
            tan[i] += t;
            bitan[i] += bt;
        }
    }
    m.tangents.reserve(4 * n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 nrm = g.normal[i].normalized();
        Vec3 t = tan[i] - nrm * nrm.dot(tan[i]);
        if (t.norm() < 1e-12) {
            // No UV gradient here (a wall seen edge-on in texture space): any unit tangent.
            t = nrm.cross(std::abs(nrm.y()) < 0.9 ? Vec3::UnitY() : Vec3::UnitX());
        }
        t.normalize();
        // glTF rebuilds the bitangent as w·(N × T) and reads the normal map's green along it; in
        // the OpenGL convention it specifies ("+Y is up"), green points up the image, i.e. along
        // −∂P/∂v of glTF's flipped v (Blender's exporter keeps MikkTSpace's sign from its unflipped
        // UVs; three.js negates the sign it computes on glTF's UVs). w = +1 unless mirrored.
        const double w = nrm.cross(t).dot(bitan[i]) > 0 ? -1.0 : 1.0;
        for (Eigen::Index c = 0; c < 3; ++c)
            m.tangents.push_back(static_cast<float>(t[c]));
        m.tangents.push_back(static_cast<float>(w));
    }
    return m;
}

} // namespace

ExportMesh export_mesh(const post::PieceMesh& pieces) {
    std::vector<std::size_t> all(pieces.triangles.size());
    for (std::size_t t = 0; t < all.size(); ++t)
        all[t] = t;
    return flatten(pieces, gather(pieces, all));
}

std::vector<ExportMesh> export_meshes(const post::PieceMesh& pieces, bool split, const std::string& name) {
    if (!split) {
        ExportMesh m = export_mesh(pieces);
        m.name = name;
        return {std::move(m)};
    }
    // A triangle belongs to its first corner's fragment: a piece's top and walls carry its
    // label, the crack floor and ledges −1.
    std::map<int, std::vector<std::size_t>> by_fragment;
    for (std::size_t t = 0; t < pieces.triangles.size(); ++t)
        by_fragment[pieces.vertices[pieces.triangles[t][0]].fragment].push_back(t);
    std::vector<ExportMesh> meshes;
    for (const auto& [fragment, triangles] : by_fragment) {
        ExportMesh m = flatten(pieces, gather(pieces, triangles));
        m.name = fragment < 0 ? "crack_floor" : "piece_" + std::to_string(fragment);
        m.fragment = fragment;
        meshes.push_back(std::move(m));
    }
    return meshes;
}

} // namespace crackle::io
