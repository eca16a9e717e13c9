/// @file fem-split's mesh repair near cuts: sliver edge flips (§5.7.5) and angle-based smoothing (§5.7.9).
#include "core/timer.hpp"
#include "fracture/fem_split/splitter.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::fracture::split_detail {

std::vector<FaceId> Splitter::flip_slivers(const std::vector<FaceId>& faces) {
    Timer timer;
    const mesh::SurfaceMesh& m = m_model.mesh();
    auto worst = [&](const std::array<Vec3, 3>& p) { return min_angle(p[0], p[1], p[2]); };
    auto positive = [&](const std::array<Vec3, 3>& p) {
        const Vec3 c = (p[0] + p[1] + p[2]) / 3.0;
        return (p[1] - p[0]).cross(p[2] - p[0]).dot(m_model.surface().frame(c).n) > 0;
    };
    std::vector<FaceId> changed;
    for (FaceId f : faces) {
        if (ix(f) >= m.num_faces() || worst(m.face_positions(f)) >= m_split.min_angle_deg) continue;
        for (int k = 0; k < 3; ++k) {
            const mesh::FaceNeighbor nb = m.neighbor(f, k);
            if (nb.face == mesh::NO_FACE || nb.face == f) continue;
            // The quad a, d, b, c in f's frame; the flip gives (a, d, c) and (d, b, c).
            const Vec3 a = m.corner_position(f, k), b = m.corner_position(f, (k + 1) % 3),
                       c = m.corner_position(f, (k + 2) % 3);
            const Vec3 d =
                m.corner_position(nb.face, (nb.edge + 2) % 3) + (a - m.corner_position(nb.face, (nb.edge + 1) % 3));
            const std::array<Vec3, 3> n1{a, d, c}, n2{d, b, c};
            if (!positive(n1) || !positive(n2)) continue; // not convex
            const double before = std::min(worst(m.face_positions(f)), worst(m.face_positions(nb.face)));
            if (std::min(worst(n1), worst(n2)) <= before + 1.0) continue;
            const FaceId g = m_model.flip_edge(f, k);
            changed.push_back(f);
            changed.push_back(g);
            ++m_counts.flips;
            break; // f changed: its edges are new
        }
    }
    m_stats.topology_seconds += timer.seconds();
    return changed;
}

bool Splitter::smoothing_target(std::size_t v, std::size_t& face, Vec3& bary) const {
    const mesh::SurfaceMesh& m = m_model.mesh();
    if (on_border(m_model, v)) return false;
    const mesh::TangentFrame fr = m_model.surface().frame(m.positions[vertex_id(v)]);
    // The fan in the plane, v at the origin: per face, its other corners A, B (counter-clockwise).
    struct Wing {
        std::size_t face;
        int k;
        std::size_t a, b;
        Vec2 A, B;
    };
    std::vector<Wing> fan;
    for (std::uint32_t f : m_model.incident_faces(v)) {
        const int k = corner_of(m, f, v);
        const auto c = local_corners(m_model, f, k, fr);
        fan.push_back({f, k, ix(m.faces[face_id(f)].v[static_cast<std::size_t>((k + 1) % 3)]),
                       ix(m.faces[face_id(f)].v[static_cast<std::size_t>((k + 2) % 3)]),
                       c[static_cast<std::size_t>((k + 1) % 3)], c[static_cast<std::size_t>((k + 2) % 3)]});
    }
    auto angle = [](const Vec2& p, const Vec2& q) { return std::atan2(std::abs(cross2(p, q)), p.dot(q)); };
    // Each neighbour j proposes v rotated about j onto the bisector of its two angles in the
    // fan (Zhou & Shimada's torsion springs); the proposals are averaged.
    Vec2 sum = Vec2::Zero();
    int count = 0;
    for (const Wing& w1 : fan) {
        // j = w1's A; its other face has j as B.
        const auto w2 = std::find_if(fan.begin(), fan.end(), [&](const Wing& w) { return w.b == w1.a; });
        if (w2 == fan.end()) return false; // an open fan: not a free node
        const Vec2 j = w1.A, to_v = -j;
        const double next = angle(w1.B - j, to_v), prev = angle(w2->A - j, to_v);
        const double delta = 0.5 * (next - prev), sign = cross2(to_v, w1.B - j) > 0 ? 1.0 : -1.0;
        const double c = std::cos(sign * delta), s = std::sin(sign * delta);
        sum += j + Vec2(c * to_v.x() - s * to_v.y(), s * to_v.x() + c * to_v.y());
        ++count;
    }
    if (count == 0) return false;
    const Vec2 q = sum / count;
    // Only if it makes the worst angle of the fan better.
    auto tri_min = [](const Vec2& p0, const Vec2& p1, const Vec2& p2) {
        if (cross2(p1 - p0, p2 - p0) <= 0) return -1.0;
        auto at = [](const Vec2& a, const Vec2& b, const Vec2& c) {
            const Vec2 u = b - a, w = c - a;
            return std::atan2(std::abs(cross2(u, w)), u.dot(w));
        };
        return std::min({at(p0, p1, p2), at(p1, p2, p0), at(p2, p0, p1)});
    };
    double before = INFINITY, after = INFINITY;
    for (const Wing& w : fan) {
        before = std::min(before, tri_min(Vec2::Zero(), w.A, w.B));
        after = std::min(after, tri_min(q, w.A, w.B));
    }
    if (!(after > before + 1.0 * DEG_TO_RAD)) return false; // worth a re-assembly: at least 1°
    for (const Wing& w : fan) {
        const double area = cross2(w.A, w.B);
        const double la = cross2(q, w.B) / area, lb = cross2(w.A, q) / area, l0 = 1 - la - lb;
        if (l0 < -1e-12 || la < -1e-12 || lb < -1e-12) continue;
        face = w.face;
        bary[w.k] = l0;
        bary[(w.k + 1) % 3] = la;
        bary[(w.k + 2) % 3] = lb;
        return true;
    }
    return false;
}

void Splitter::smooth_near(std::size_t tip) {
    if (m_smoothing <= 0) return;
    Timer timer;
    const mesh::SurfaceMesh& m = m_model.mesh();
    const Vec3 centre = m.positions[vertex_id(tip)];
    // The nodes within the radius, reached through the elements around the tip.
    std::vector<std::size_t> near{tip}, frontier{tip};
    while (!frontier.empty()) {
        std::vector<std::size_t> next;
        for (std::size_t u : frontier)
            for (std::uint32_t f : m_model.incident_faces(u))
                for (VertexId w : m.faces[face_id(f)].v) {
                    const std::size_t x = ix(w);
                    if (m.nearest_step(centre, m.positions[w]).norm() > m_smoothing) continue;
                    if (std::find(near.begin(), near.end(), x) != near.end()) continue;
                    near.push_back(x);
                    next.push_back(x);
                }
        frontier.swap(next);
    }
    std::vector<FaceId> touched;
    for (int round = 0; round < 2; ++round)
        for (std::size_t v : near) {
            std::size_t f = 0;
            Vec3 bary = Vec3::Zero();
            if (!smoothing_target(v, f, bary)) continue;
            Vec3 top, rate;
            const mesh::NewVertex target = m_model.face_point(face_id(f), bary, &top, &rate);
            m_model.move_vertex(vertex_id(v), target, top, rate);
            for (std::uint32_t g : m_model.incident_faces(v))
                touched.push_back(face_id(g));
            ++m_counts.smoothed;
        }
    m_stats.topology_seconds += timer.seconds();
    if (touched.empty()) return;
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    refresh_after(touched, relax_near(touched));
}

} // namespace crackle::fracture::split_detail
