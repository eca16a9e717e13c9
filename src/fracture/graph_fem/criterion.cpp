/// @file graph-fem's graph and breaking criterion (graph-fem digest §1.5, Eqs. 13–14; errata E2, E3; §7.5).
#include "fracture/graph_fem/graph_fem.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace crackle::fracture {

using mesh::face_id;
using mesh::ix;

EdgeGraph::EdgeGraph(const mesh::SurfaceMesh& mesh) {
    constexpr std::size_t none = std::numeric_limits<std::size_t>::max();
    m_of_face.assign(mesh.num_faces(), {none, none, none});
    for (std::size_t f = 0; f < mesh.num_faces(); ++f)
        for (int k = 0; k < 3; ++k) {
            if (m_of_face[f][static_cast<std::size_t>(k)] != none) continue;
            Edge e;
            e.side[0] = {static_cast<std::uint32_t>(f), k};
            const mesh::FaceNeighbor nb = mesh.neighbor(face_id(f), k);
            if (nb.face != mesh::NO_FACE) {
                e.side[1] = {static_cast<std::uint32_t>(ix(nb.face)), nb.edge};
                e.sides = 2;
                m_of_face[ix(nb.face)][static_cast<std::size_t>(nb.edge)] = m_edges.size();
            }
            m_of_face[f][static_cast<std::size_t>(k)] = m_edges.size();
            m_edges.push_back(e);
        }
}

EdgeCriterion::EdgeCriterion(const sim::FemModel& model, const StressCache& cache, const EdgeGraph& graph,
                             double radius)
    : m_model(model), m_cache(cache), m_graph(graph), m_radius(radius) {
    const std::size_t nf = model.mesh().num_faces();
    m_dir.resize(nf);
    for (std::size_t f = 0; f < nf; ++f)
        m_dir[f] = sim::wedge::edge_frame(model.reference_nodes(face_id(f))).edge;
    m_mean.assign(nf, sim::wedge::Vec6::Zero());
    m_mean_rate.assign(nf, sim::wedge::Vec6::Zero());
    m_a.assign(nf, {0, 0, 0});
    m_b.assign(nf, {0, 0, 0});
    m_hood.resize(nf);
    m_stamp_of.assign(nf, 0);
    for (std::size_t f = 0; f < nf; ++f)
        build_hood(f);
}

void EdgeCriterion::build_hood(std::size_t f) {
    auto& hood = m_hood[f];
    hood.clear();
    if (m_radius <= 0) {
        hood.emplace_back(static_cast<std::uint32_t>(f), 1.0);
        return;
    }
    // Dijkstra over faces; a step goes centroid → shared edge midpoint → centroid, each leg
    // measured in its own face (periodic frames need no shifts), never across a broken edge.
    const mesh::SurfaceMesh& m = m_model.mesh();
    auto leg = [&](std::size_t g, int k) {
        const auto p = m.face_positions(face_id(g));
        const Vec3 c = (p[0] + p[1] + p[2]) / 3.0;
        return (0.5 * (p[static_cast<std::size_t>(k)] + p[static_cast<std::size_t>((k + 1) % 3)]) - c).norm();
    };
    using Item = std::pair<double, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    std::vector<std::pair<std::uint32_t, double>> settled; // (face, distance)
    ++m_stamp;
    queue.emplace(0.0, static_cast<std::uint32_t>(f));
    while (!queue.empty()) {
        const auto [d, g] = queue.top();
        queue.pop();
        if (m_stamp_of[g] == m_stamp) continue;
        m_stamp_of[g] = m_stamp;
        settled.emplace_back(g, d);
        const unsigned broken = m_model.broken_edges(face_id(g));
        for (int k = 0; k < 3; ++k) {
            if ((broken >> k) & 1u) continue;
            const mesh::FaceNeighbor nb = m.neighbor(face_id(g), k);
            if (nb.face == mesh::NO_FACE || m_stamp_of[ix(nb.face)] == m_stamp) continue;
            const double next = d + leg(g, k) + leg(ix(nb.face), nb.edge);
            if (next <= m_radius) queue.emplace(next, static_cast<std::uint32_t>(ix(nb.face)));
        }
    }
    std::sort(settled.begin(), settled.end());
    double total = 0;
    for (const auto& [g, d] : settled)
        total += m.face_area(face_id(g));
    for (const auto& [g, d] : settled)
        hood.emplace_back(g, m.face_area(face_id(g)) / total);
}

void EdgeCriterion::update_face(std::size_t f) {
    sim::wedge::Vec6 s = sim::wedge::Vec6::Zero(), r = sim::wedge::Vec6::Zero();
    for (const auto& [g, w] : m_hood[f]) {
        s += w * m_mean[g];
        r += w * m_mean_rate[g];
    }
    const Mat3 S = sim::wedge::tensor(s), R = sim::wedge::tensor(r);
    const double thr = m_model.material(face_id(f)).threshold_stress;
    for (std::size_t k = 0; k < 3; ++k) {
        const Vec3& d = m_dir[f][k];
        m_a[f][k] = d.dot(S * d) / thr;
        m_b[f][k] = d.dot(R * d) / thr;
    }
}

void EdgeCriterion::refresh_all() {
    for (std::size_t f = 0; f < m_mean.size(); ++f) {
        const sim::TopStress& s = m_cache.stress(f);
        const sim::TopStress& r = m_cache.rate(f);
        m_mean[f] = (s[0] + s[1] + s[2]) / 3.0;
        m_mean_rate[f] = (r[0] + r[1] + r[2]) / 3.0;
    }
    for (std::size_t f = 0; f < m_mean.size(); ++f)
        update_face(f);
}

void EdgeCriterion::refresh(const std::vector<std::uint32_t>& faces) {
    for (std::uint32_t g : faces) {
        const sim::TopStress& s = m_cache.stress(g);
        const sim::TopStress& r = m_cache.rate(g);
        m_mean[g] = (s[0] + s[1] + s[2]) / 3.0;
        m_mean_rate[g] = (r[0] + r[1] + r[2]) / 3.0;
    }
    // Neighbourhoods are symmetric: the faces averaging g are those g averages.
    ++m_stamp;
    for (std::uint32_t g : faces)
        for (const auto& [f, w] : m_hood[g])
            if (m_stamp_of[f] != m_stamp) {
                m_stamp_of[f] = m_stamp;
                update_face(f);
            }
}

void EdgeCriterion::broke(std::size_t e) {
    if (m_radius <= 0) return;
    // Every neighbourhood whose paths could cross e contains one of its faces.
    std::vector<std::uint32_t> affected;
    const EdgeGraph::Edge& edge = m_graph.edge(e);
    for (int i = 0; i < edge.sides; ++i)
        for (const auto& [f, w] : m_hood[edge.side[static_cast<std::size_t>(i)].face])
            affected.push_back(f);
    std::sort(affected.begin(), affected.end());
    affected.erase(std::unique(affected.begin(), affected.end()), affected.end());
    for (std::uint32_t f : affected)
        build_hood(f);
    for (std::uint32_t f : affected)
        update_face(f);
}

double EdgeCriterion::ratio_at(std::size_t e, double tau) const {
    const EdgeGraph::Edge& edge = m_graph.edge(e);
    double best = -std::numeric_limits<double>::infinity();
    for (int i = 0; i < edge.sides; ++i) {
        const EdgeGraph::Side& s = edge.side[static_cast<std::size_t>(i)];
        const auto k = static_cast<std::size_t>(s.edge);
        best = std::max(best, m_a[s.face][k] + tau * m_b[s.face][k]);
    }
    return best;
}

double EdgeCriterion::next_crossing(const std::vector<double>& level, std::size_t* which) const {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t e = 0; e < m_graph.size(); ++e) {
        if (m_graph.broken(m_model, e)) continue;
        const double target = level.empty() ? 1.0 : level[e];
        const EdgeGraph::Edge& edge = m_graph.edge(e);
        for (int i = 0; i < edge.sides; ++i) {
            const EdgeGraph::Side& s = edge.side[static_cast<std::size_t>(i)];
            const auto k = static_cast<std::size_t>(s.edge);
            const double a = m_a[s.face][k], b = m_b[s.face][k];
            // A ratio that is not rising never crosses (one exactly at 1 and flat included).
            const double tau = b > 0 ? std::max(0.0, (target - a) / b) : std::numeric_limits<double>::infinity();
            if (tau < best) {
                best = tau;
                if (which) *which = e;
            }
        }
    }
    return best;
}

} // namespace crackle::fracture
