#include "mesh/refine.hpp"

#include "core/error.hpp"

namespace crackle::mesh {

namespace {

/// The offset that places canonical domain point `canonical` at `unwrapped` in a face frame.
Vec2i offset_of(const Vec2& unwrapped, const Vec2& canonical, const Vec2& period) {
    return Vec2i(static_cast<int>(std::lround((unwrapped.x() - canonical.x()) / period.x())),
                 static_cast<int>(std::lround((unwrapped.y() - canonical.y()) / period.y())));
}

/// Splits one face across its edge k at the new vertex m (already appended); returns the new face.
FaceId split_face(SurfaceMesh& mesh, FaceId f, int k, VertexId m) {
    const auto a = static_cast<std::size_t>(k), b = static_cast<std::size_t>((k + 1) % 3);
    const Face old = mesh.faces[f];
    Vec2i om = Vec2i::Zero();
    if (mesh.periodic) {
        const Vec2 mid =
            0.5 * (mesh.corner_domain(f, static_cast<int>(a)) + mesh.corner_domain(f, static_cast<int>(b)));
        om = offset_of(mid, mesh.domain[m], mesh.period);
    }
    Face first = old, second = old;
    first.v[b] = m; // (a, m, c)
    first.offset[b] = om;
    second.v[a] = m; // (m, b, c)
    second.offset[a] = om;
    mesh.faces[f] = first;
    mesh.faces.push_back(second);
    return face_id(mesh.faces.size() - 1);
}

} // namespace

EdgeSplit split_edge(SurfaceMesh& mesh, FaceId f, int edge, const NewVertex& nv) {
    const FaceNeighbor nb = mesh.neighbor(f, edge);
    EdgeSplit split;
    split.vertex = vertex_id(mesh.positions.size());
    mesh.positions.push_back(nv.position);
    if (mesh.periodic) mesh.domain.push_back(nv.domain);
    split.children.emplace_back(f, split_face(mesh, f, edge, split.vertex));
    if (nb.face != NO_FACE) split.children.emplace_back(nb.face, split_face(mesh, nb.face, nb.edge, split.vertex));
    std::vector<FaceId> changed;
    for (const auto& [parent, child] : split.children) {
        changed.push_back(parent);
        changed.push_back(child);
    }
    mesh.update_adjacency(changed);
    return split;
}

FaceId flip_edge(SurfaceMesh& mesh, FaceId f, int edge) {
    const FaceNeighbor nb = mesh.neighbor(f, edge);
    if (nb.face == NO_FACE || nb.face == f) return NO_FACE;
    const Face F = mesh.faces[f], G = mesh.faces[nb.face];
    const auto ka = static_cast<std::size_t>(edge), kc = static_cast<std::size_t>((edge + 2) % 3);
    const auto gb = static_cast<std::size_t>(nb.edge), ga = static_cast<std::size_t>((nb.edge + 1) % 3),
               gd = static_cast<std::size_t>((nb.edge + 2) % 3);
    // Offsets: g's frame differs from f's by the shift of the shared edge's ends.
    const Vec2i g_to_f = F.offset[ka] - G.offset[ga];
    Face first, second;
    first.v = {F.v[ka], G.v[gd], F.v[kc]}; // (a, d, c) in f's frame
    first.offset = {F.offset[ka], G.offset[gd] + g_to_f, F.offset[kc]};
    second.v = {G.v[gd], G.v[gb], F.v[kc]}; // (d, b, c) in g's frame
    second.offset = {G.offset[gd], G.offset[gb], F.offset[kc] - g_to_f};
    mesh.faces[f] = first;
    mesh.faces[nb.face] = second;
    mesh.update_adjacency({f, nb.face});
    return nb.face;
}

int longest_edge(const SurfaceMesh& mesh, FaceId f) {
    const auto p = mesh.face_positions(f);
    const Face& face = mesh.faces[f];
    int best = 0;
    double best_len = -1;
    std::pair<std::uint32_t, std::uint32_t> best_key{0, 0};
    for (int k = 0; k < 3; ++k) {
        const auto a = static_cast<std::size_t>(k), b = static_cast<std::size_t>((k + 1) % 3);
        const double len = (p[b] - p[a]).squaredNorm();
        const auto va = static_cast<std::uint32_t>(face.v[a]), vb = static_cast<std::uint32_t>(face.v[b]);
        const std::pair<std::uint32_t, std::uint32_t> key{std::min(va, vb), std::max(va, vb)};
        // Lengths equal to round-off count as a tie; the vertex ids decide.
        const bool longer = len > best_len * (1 + 1e-12);
        const bool tie = !longer && len >= best_len * (1 - 1e-12);
        if (longer || (tie && key < best_key)) {
            best = k;
            best_len = len;
            best_key = key;
        }
    }
    return best;
}

void rivara_bisect(SurfaceMesh& mesh, FaceId f, const MidpointRule& midpoint, std::vector<EdgeSplit>& splits) {
    const int k = longest_edge(mesh, f);
    for (int guard = 0; guard < 64; ++guard) {
        const FaceNeighbor nb = mesh.neighbor(f, k);
        if (nb.face == NO_FACE || longest_edge(mesh, nb.face) == nb.edge) {
            splits.push_back(split_edge(mesh, f, k, midpoint(mesh, f, k)));
            return;
        }
        // The neighbour's own longest edge is elsewhere: bisect it first (Alg. 9). Afterwards
        // a child of it lies across our edge k; look again.
        rivara_bisect(mesh, nb.face, midpoint, splits);
    }
    CRACKLE_ASSERT(false, "Rivara bisection did not terminate at face " << ix(f));
}

MidpointRule domain_midpoint(const std::function<Vec3(const Vec2&)>& position_of_domain) {
    return [position_of_domain](const SurfaceMesh& mesh, FaceId f, int edge) {
        const Vec2 mid = 0.5 * (mesh.corner_domain(f, edge) + mesh.corner_domain(f, (edge + 1) % 3));
        NewVertex nv;
        nv.domain = Vec2(wrap(mid.x(), mesh.period.x()), wrap(mid.y(), mesh.period.y()));
        nv.position = position_of_domain(nv.domain);
        return nv;
    };
}

MidpointRule projected_midpoint(const std::function<Vec3(const Vec3&)>& project) {
    return [project](const SurfaceMesh& mesh, FaceId f, int edge) {
        NewVertex nv;
        nv.position = project(0.5 * (mesh.corner_position(f, edge) + mesh.corner_position(f, (edge + 1) % 3)));
        return nv;
    };
}

} // namespace crackle::mesh
