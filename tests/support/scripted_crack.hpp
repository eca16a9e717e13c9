#pragma once
/// @file Scripted cracks on a periodic FEM layer: a chain of mesh edges that follows a segment
/// of the domain, cut open with FemModel::cut. A slit keeps its two end vertices whole (they
/// are its tips); a chain that closes around the torus cuts the tile into a band.

#include "sim/fem_model.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <queue>
#include <tuple>
#include <utility>
#include <vector>

namespace crackle::test {

/// Distance from p to the segment [a, b].
inline double segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
    const Vec2 ab = b - a;
    const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
    return (p - (a + t * ab)).norm();
}

/// Index of the vertex nearest a domain point (minimum image), among vertices with elements.
inline std::size_t nearest_vertex(const sim::FemModel& model, const Vec2& point) {
    const mesh::SurfaceMesh& m = model.mesh();
    const Vec2 L = m.period;
    std::size_t best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t v = 0; v < m.num_vertices(); ++v) {
        if (model.incident_faces(v).empty()) continue;
        Vec2 d = m.domain[mesh::vertex_id(v)] - point;
        d.x() -= L.x() * std::round(d.x() / L.x());
        d.y() -= L.y() * std::round(d.y() / L.y());
        if (d.norm() < best_d) {
            best_d = d.norm();
            best = v;
        }
    }
    return best;
}

/// The shortest chain of mesh edges from the vertex nearest `a` to the vertex nearest `b`
/// (unrolled domain coordinates: b may lie outside the tile, so a chain can wrap around it),
/// staying within `band` (m) of the segment. Returns the vertex indices along the chain (the
/// first and last coincide for a chain that closes around the torus); empty if none exists.
inline std::vector<std::size_t> edge_path_within(const sim::FemModel& model, const Vec2& a, const Vec2& b,
                                                 double band) {
    const mesh::SurfaceMesh& m = model.mesh();
    const Vec2 L = m.period;
    using State = std::tuple<std::size_t, int, int>; // vertex, lattice copy (i, j)
    auto copy_of = [&](std::size_t v, const Vec2& unrolled) {
        const Vec2 c = (unrolled - m.domain[mesh::vertex_id(v)]).cwiseQuotient(L);
        return std::pair<int, int>(static_cast<int>(std::lround(c.x())), static_cast<int>(std::lround(c.y())));
    };
    auto unrolled = [&](const State& s) {
        return Vec2(m.domain[mesh::vertex_id(std::get<0>(s))] + Vec2(std::get<1>(s) * L.x(), std::get<2>(s) * L.y()));
    };
    const std::size_t sv = nearest_vertex(model, a), gv = nearest_vertex(model, b);
    const auto sc = copy_of(sv, a), gc = copy_of(gv, b);
    const State start{sv, sc.first, sc.second}, goal{gv, gc.first, gc.second};

    std::map<State, double> dist;
    std::map<State, State> prev;
    using Item = std::pair<double, State>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    dist[start] = 0;
    queue.emplace(0.0, start);
    while (!queue.empty()) {
        const auto [d, s] = queue.top();
        queue.pop();
        if (d > dist[s]) continue;
        if (s == goal) break;
        const std::size_t v = std::get<0>(s);
        const Vec2 p = unrolled(s);
        for (std::uint32_t f : model.incident_faces(v)) {
            if (!model.alive(mesh::face_id(f))) continue;
            const mesh::Face& face = m.faces[mesh::face_id(f)];
            int kv = -1;
            for (int k = 0; k < 3; ++k)
                if (mesh::ix(face.v[static_cast<std::size_t>(k)]) == v) kv = k;
            for (int k = 0; k < 3; ++k) {
                if (k == kv) continue;
                const std::size_t w = mesh::ix(face.v[static_cast<std::size_t>(k)]);
                const Vec2 q = p + m.corner_domain(mesh::face_id(f), k) - m.corner_domain(mesh::face_id(f), kv);
                if (segment_distance(q, a, b) > band) continue;
                const auto c = copy_of(w, q);
                const State t{w, c.first, c.second};
                const double nd = d + (q - p).norm();
                const auto it = dist.find(t);
                if (it == dist.end() || nd < it->second) {
                    dist[t] = nd;
                    prev[t] = s;
                    queue.emplace(nd, t);
                }
            }
        }
    }
    if (!dist.count(goal)) return {};
    std::vector<std::size_t> path{std::get<0>(goal)};
    for (State s = goal; s != start; s = prev.at(s))
        path.push_back(std::get<0>(prev.at(s)));
    std::reverse(path.begin(), path.end());
    return path;
}

/// edge_path_within a band of `band` mean edge lengths `h`, widened until a chain exists.
inline std::vector<std::size_t> edge_path(const sim::FemModel& model, const Vec2& a, const Vec2& b, double h,
                                          double band = 0.75) {
    for (double w = band; w < 4.0; w *= 1.5) {
        std::vector<std::size_t> path = edge_path_within(model, a, b, w * h);
        if (!path.empty()) return path;
    }
    FAIL("no edge chain along the segment");
    return {};
}

/// One side (face, edge) of every edge of a chain, for FemModel::cut.
inline std::vector<std::pair<mesh::FaceId, int>> path_sides(const sim::FemModel& model,
                                                            const std::vector<std::size_t>& path) {
    std::vector<std::pair<mesh::FaceId, int>> sides;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
        const std::size_t p = path[i], q = path[i + 1];
        bool found = false;
        for (std::uint32_t f : model.incident_faces(p)) {
            const mesh::Face& face = model.mesh().faces[mesh::face_id(f)];
            for (int k = 0; k < 3 && !found; ++k) {
                const std::size_t x = mesh::ix(face.v[static_cast<std::size_t>(k)]);
                const std::size_t y = mesh::ix(face.v[static_cast<std::size_t>((k + 1) % 3)]);
                if ((x == p && y == q) || (x == q && y == p)) {
                    sides.emplace_back(mesh::face_id(f), k);
                    found = true;
                }
            }
            if (found) break;
        }
        REQUIRE_MESSAGE(found, "no edge between consecutive chain vertices");
    }
    return sides;
}

/// Cuts the chain open (FemModel::cut); returns every vertex whose faces changed (the chain
/// and the new copies), the seeds of a local relaxation.
inline std::vector<std::size_t> cut_path(sim::FemModel& model, const std::vector<std::size_t>& path) {
    const auto copies = model.cut(path_sides(model, path));
    std::vector<std::size_t> seeds = path;
    for (const auto& [copy, origin] : copies)
        seeds.push_back(mesh::ix(copy));
    return seeds;
}

/// Vertices that share an alive element with v (its first ring), v excluded.
inline std::vector<std::size_t> ring_of(const sim::FemModel& model, std::size_t v) {
    std::vector<std::size_t> ring;
    for (std::uint32_t f : model.incident_faces(v)) {
        if (!model.alive(mesh::face_id(f))) continue;
        for (mesh::VertexId w : model.mesh().faces[mesh::face_id(f)].v)
            if (mesh::ix(w) != v && std::find(ring.begin(), ring.end(), mesh::ix(w)) == ring.end())
                ring.push_back(mesh::ix(w));
    }
    return ring;
}

/// Hop distance from the seeds along alive elements (the crack-aware distance of §5.8);
/// −1 where unreachable.
inline std::vector<int> hop_distance(const sim::FemModel& model, const std::vector<std::size_t>& seeds) {
    std::vector<int> hop(model.mesh().num_vertices(), -1);
    std::vector<std::size_t> queue;
    for (std::size_t s : seeds)
        if (hop[s] < 0) {
            hop[s] = 0;
            queue.push_back(s);
        }
    for (std::size_t head = 0; head < queue.size(); ++head)
        for (std::size_t w : ring_of(model, queue[head]))
            if (hop[w] < 0) {
                hop[w] = hop[queue[head]] + 1;
                queue.push_back(w);
            }
    return hop;
}

} // namespace crackle::test
