#include "mesh/cut.hpp"

#include "core/error.hpp"

#include <algorithm>

namespace crackle::mesh {

namespace {

using Corner = std::pair<std::uint32_t, int>; // (face, corner index)

/// Splits the fan of corners `cs` around vertex v into the groups that stay connected across
/// unmarked edges; group 0 keeps v, every other group gets a copy (appended to the mesh, its
/// origin to `origin`).
template <class IsCut>
void split_fan(SurfaceMesh& mesh, VertexId v, const std::vector<Corner>& cs, IsCut&& is_cut,
               std::vector<VertexId>& origin) {
    if (cs.size() < 2) return;
    bool touches_cut = false;
    for (const auto& [f, k] : cs)
        touches_cut = touches_cut || is_cut(f, k) || is_cut(f, (k + 2) % 3); // the two edges at corner k
    if (!touches_cut) return;
    // Union the corners across unmarked edges: flood fill over the fan.
    std::vector<int> group(cs.size(), -1);
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
                if (is_cut(f, e)) continue;
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
    for (int g = 1; g < groups; ++g) {
        const VertexId copy = vertex_id(mesh.positions.size());
        mesh.positions.push_back(mesh.positions[v]);
        if (mesh.periodic) mesh.domain.push_back(mesh.domain[v]);
        origin.push_back(v);
        for (std::size_t i = 0; i < cs.size(); ++i)
            if (group[i] == g) mesh.faces[face_id(cs[i].first)].v[static_cast<std::size_t>(cs[i].second)] = copy;
    }
}

} // namespace

std::vector<VertexId> cut_along(SurfaceMesh& mesh, const std::vector<std::array<char, 3>>& cut) {
    CRACKLE_ASSERT(cut.size() == mesh.num_faces(), "one cut mark triple per face");
    const std::size_t nv = mesh.num_vertices();
    std::vector<VertexId> origin(nv);
    for (std::size_t v = 0; v < nv; ++v)
        origin[v] = vertex_id(v);
    std::vector<std::vector<Corner>> corners(nv);
    for (std::size_t f = 0; f < mesh.num_faces(); ++f)
        for (int k = 0; k < 3; ++k)
            corners[ix(mesh.faces[face_id(f)].v[static_cast<std::size_t>(k)])].emplace_back(
                static_cast<std::uint32_t>(f), k);
    auto is_cut = [&](std::uint32_t f, int e) { return cut[f][static_cast<std::size_t>(e)] != 0; };
    for (std::size_t v = 0; v < nv; ++v)
        split_fan(mesh, vertex_id(v), corners[v], is_cut, origin);
    mesh.rebuild_adjacency();
    return origin;
}

std::vector<std::pair<VertexId, VertexId>>
cut_edges(SurfaceMesh& mesh, const std::vector<std::pair<FaceId, int>>& edges,
          const std::function<const std::vector<std::uint32_t>&(VertexId)>& faces_at) {
    // Both sides of every edge, sorted for lookup.
    std::vector<Corner> marked;
    for (const auto& [f, e] : edges) {
        marked.emplace_back(static_cast<std::uint32_t>(ix(f)), e);
        const FaceNeighbor nb = mesh.neighbor(f, e);
        if (nb.face != NO_FACE) marked.emplace_back(static_cast<std::uint32_t>(ix(nb.face)), nb.edge);
    }
    std::sort(marked.begin(), marked.end());
    auto is_cut = [&](std::uint32_t f, int e) {
        return std::binary_search(marked.begin(), marked.end(), Corner{f, e});
    };
    std::vector<VertexId> ends;
    for (const auto& [f, e] : edges)
        for (int k : {e, (e + 1) % 3})
            ends.push_back(mesh.faces[f].v[static_cast<std::size_t>(k)]);
    std::sort(ends.begin(), ends.end());
    ends.erase(std::unique(ends.begin(), ends.end()), ends.end());
    // Gather every fan before changing any face: the copies move corners between vertices.
    std::vector<std::vector<Corner>> fans;
    std::vector<FaceId> changed;
    for (VertexId v : ends) {
        std::vector<Corner> cs;
        for (std::uint32_t f : faces_at(v)) {
            const Face& face = mesh.faces[face_id(f)];
            for (int k = 0; k < 3; ++k)
                if (face.v[static_cast<std::size_t>(k)] == v) cs.emplace_back(f, k);
            changed.push_back(face_id(f));
        }
        fans.push_back(std::move(cs));
    }
    std::vector<VertexId> origin;
    const std::size_t nv = mesh.num_vertices();
    for (std::size_t i = 0; i < ends.size(); ++i)
        split_fan(mesh, ends[i], fans[i], is_cut, origin);
    std::sort(changed.begin(), changed.end());
    changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
    // The marked edges whose ends kept their ids (a slit inside intact material) must not
    // re-pair: update_adjacency pairs by vertex ids, which is exactly what opening needs.
    mesh.update_adjacency(changed);
    std::vector<std::pair<VertexId, VertexId>> copies;
    for (std::size_t i = 0; i < origin.size(); ++i)
        copies.emplace_back(vertex_id(nv + i), origin[i]);
    return copies;
}

} // namespace crackle::mesh
