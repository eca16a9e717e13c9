/// @file fem-split's nonlocal initiation stress: neighbourhoods along the surface, not across cracks.
#include "fracture/fem_split/nonlocal.hpp"

#include <algorithm>
#include <cmath>
#include <queue>

namespace crackle::fracture::split_detail {

NonlocalStress::NonlocalStress(const sim::FemModel& model, std::function<double(std::size_t)> radius,
                               std::function<bool(std::size_t, int)> intact)
    : m_model(model), m_radius(std::move(radius)), m_intact(std::move(intact)) {}

sim::wedge::Vec6 NonlocalStress::turned(std::size_t f, std::size_t v, const sim::wedge::Vec6& stress) const {
    const mesh::SurfaceMesh& m = m_model.mesh();
    const auto p = m.face_positions(mesh::face_id(f));
    const Vec3 a = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
    const Vec3 b = m_model.surface().normal(m.positions[mesh::vertex_id(v)]);
    // Rodrigues: the smallest rotation taking a to b (faces within R of v face nearly its way).
    const Vec3 k = a.cross(b);
    const double c = a.dot(b);
    Mat3 K;
    K << 0, -k.z(), k.y(), k.z(), 0, -k.x(), -k.y(), k.x(), 0;
    const Mat3 R = Mat3::Identity() + K + K * K / (1 + c);
    const Mat3 S = R * sim::wedge::tensor(stress) * R.transpose();
    sim::wedge::Vec6 out;
    out << S(0, 0), S(1, 1), S(2, 2), S(1, 2), S(0, 2), S(0, 1);
    return out;
}

void NonlocalStress::rebuild_all() {
    const std::size_t nv = m_model.mesh().num_vertices();
    m_hood.assign(nv, {});
    m_readers.assign(m_model.mesh().num_faces(), {});
    for (std::size_t v = 0; v < nv; ++v)
        build(v);
}

const std::vector<std::uint32_t>& NonlocalStress::readers(std::size_t f) const {
    static const std::vector<std::uint32_t> none;
    return f < m_readers.size() ? m_readers[f] : none;
}

void NonlocalStress::forget(std::size_t v) {
    for (const auto& [f, w] : m_hood[v]) {
        auto& list = m_readers[f];
        list.erase(std::remove(list.begin(), list.end(), static_cast<std::uint32_t>(v)), list.end());
    }
    m_hood[v].clear();
}

void NonlocalStress::build(std::size_t v) {
    const mesh::SurfaceMesh& m = m_model.mesh();
    m_hood.resize(std::max(m_hood.size(), m.num_vertices()));
    m_readers.resize(std::max(m_readers.size(), m.num_faces()));
    forget(v);
    const double R = m_radius(v);
    if (!(R > 0)) return;
    // A leg from a face's centroid to a point of it, in the face's own frame.
    auto centroid = [&](std::size_t g) {
        const auto p = m.face_positions(mesh::face_id(g));
        return Vec3((p[0] + p[1] + p[2]) / 3.0);
    };
    auto leg = [&](std::size_t g, int k) {
        const auto p = m.face_positions(mesh::face_id(g));
        return (0.5 * (p[static_cast<std::size_t>(k)] + p[static_cast<std::size_t>((k + 1) % 3)]) - centroid(g)).norm();
    };
    using Item = std::pair<double, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    m_stamp_of.resize(std::max(m_stamp_of.size(), m.num_faces()), 0);
    ++m_stamp;
    // Where R does not reach past the node's own faces, the thesis' average stands (an empty hood).
    double own = 0;
    for (std::uint32_t g : m_model.incident_faces(v)) {
        if (!m_model.alive(mesh::face_id(g))) continue;
        const int k = corner_of(m, g, v);
        const double d = (m.corner_position(mesh::face_id(g), k) - centroid(g)).norm();
        own = std::max(own, d);
        queue.emplace(d, g);
    }
    if (queue.empty() || R <= own) return;
    std::vector<std::pair<std::uint32_t, double>> hood;
    while (!queue.empty()) {
        const auto [d, g] = queue.top();
        queue.pop();
        if (m_stamp_of[g] == m_stamp) continue;
        m_stamp_of[g] = m_stamp;
        const double x = d / R;
        hood.emplace_back(g, m.face_area(mesh::face_id(g)) * sqr(1 - x * x));
        for (int k = 0; k < 3; ++k) {
            if (m_intact && !m_intact(g, k)) continue;
            const mesh::FaceNeighbor nb = m.neighbor(mesh::face_id(g), k);
            if (nb.face == mesh::NO_FACE) continue;
            const std::size_t h = mesh::ix(nb.face);
            if (m_stamp_of[h] == m_stamp || !m_model.alive(nb.face)) continue;
            const double next = d + leg(g, k) + leg(h, nb.edge);
            if (next < R) queue.emplace(next, static_cast<std::uint32_t>(h));
        }
    }
    std::sort(hood.begin(), hood.end());
    double total = 0;
    for (const auto& [g, w] : hood)
        total += w;
    for (auto& [g, w] : hood) {
        w /= total;
        m_readers[g].push_back(static_cast<std::uint32_t>(v));
    }
    m_hood[v] = std::move(hood);
}

std::vector<std::size_t> NonlocalStress::rebuild_around(const std::vector<mesh::FaceId>& faces) {
    const mesh::SurfaceMesh& m = m_model.mesh();
    m_hood.resize(std::max(m_hood.size(), m.num_vertices()));
    m_readers.resize(std::max(m_readers.size(), m.num_faces()));
    std::vector<std::size_t> vertices;
    for (mesh::FaceId f : faces) {
        for (std::uint32_t v : m_readers[mesh::ix(f)])
            vertices.push_back(v);
        for (mesh::VertexId w : m.faces[f].v)
            vertices.push_back(mesh::ix(w));
    }
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    for (std::size_t v : vertices)
        build(v);
    return vertices;
}

} // namespace crackle::fracture::split_detail
