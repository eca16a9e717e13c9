#include "mesh/cut.hpp"

#include "core/error.hpp"

namespace crackle::mesh {

std::vector<VertexId> cut_along(SurfaceMesh& mesh, const std::vector<std::array<char, 3>>& cut) {
    CRACKLE_ASSERT(cut.size() == mesh.num_faces(), "one cut mark triple per face");
    const std::size_t nv = mesh.num_vertices();
    std::vector<VertexId> origin(nv);
    for (std::size_t v = 0; v < nv; ++v)
        origin[v] = vertex_id(v);

    // Every corner, grouped by vertex: (face, corner index).
    std::vector<std::vector<std::pair<std::uint32_t, int>>> corners(nv);
    for (std::size_t f = 0; f < mesh.num_faces(); ++f)
        for (int k = 0; k < 3; ++k)
            corners[ix(mesh.faces[face_id(f)].v[static_cast<std::size_t>(k)])].emplace_back(
                static_cast<std::uint32_t>(f), k);

    std::vector<int> group; // per corner of the current vertex
    for (std::size_t v = 0; v < nv; ++v) {
        auto& cs = corners[v];
        if (cs.size() < 2) continue;
        bool touches_cut = false;
        for (const auto& [f, k] : cs) {
            const auto& marks = cut[f];
            // The two edges at corner k: k (outgoing) and k+2 (incoming).
            touches_cut =
                touches_cut || marks[static_cast<std::size_t>(k)] || marks[static_cast<std::size_t>((k + 2) % 3)];
        }
        if (!touches_cut) continue;
        // Union the corners across unmarked edges: flood fill over the fan.
        group.assign(cs.size(), -1);
        auto corner_of = [&](std::uint32_t f) {
            for (std::size_t i = 0; i < cs.size(); ++i)
                if (cs[i].first == f) return static_cast<int>(i);
            return -1;
        };
        int groups = 0;
        for (std::size_t start = 0; start < cs.size(); ++start) {
            if (group[start] >= 0) continue;
            std::vector<std::size_t> stack{start};
            group[start] = groups;
            while (!stack.empty()) {
                const std::size_t c = stack.back();
                stack.pop_back();
                const auto [f, k] = cs[c];
                for (int e : {k, (k + 2) % 3}) {
                    if (cut[f][static_cast<std::size_t>(e)]) continue;
                    const FaceNeighbor nb = mesh.neighbor(face_id(f), e);
                    if (nb.face == NO_FACE) continue;
                    const int other = corner_of(static_cast<std::uint32_t>(ix(nb.face)));
                    if (other >= 0 && group[static_cast<std::size_t>(other)] < 0) {
                        group[static_cast<std::size_t>(other)] = groups;
                        stack.push_back(static_cast<std::size_t>(other));
                    }
                }
            }
            ++groups;
        }
        // Group 0 keeps the vertex; every other group gets a copy.
        for (int g = 1; g < groups; ++g) {
            const VertexId copy = vertex_id(mesh.positions.size());
            mesh.positions.push_back(mesh.positions[vertex_id(v)]);
            if (mesh.periodic) mesh.domain.push_back(mesh.domain[vertex_id(v)]);
            origin.push_back(vertex_id(v));
            for (std::size_t i = 0; i < cs.size(); ++i)
                if (group[i] == g) mesh.faces[face_id(cs[i].first)].v[static_cast<std::size_t>(cs[i].second)] = copy;
        }
    }
    mesh.rebuild_adjacency();
    return origin;
}

} // namespace crackle::mesh
