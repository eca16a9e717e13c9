/// @file fem-split geometry helpers: node frames, stress projection, fan rays, crack tips (Federl 2002, §5.7.1–5.7.2).
#include "fracture/fem_split/splitter.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace crackle::fracture::split_detail {

int corner_of(const mesh::SurfaceMesh& m, std::size_t f, std::size_t v) {
    const mesh::Face& face = m.faces[face_id(f)];
    for (int k = 0; k < 3; ++k)
        if (ix(face.v[static_cast<std::size_t>(k)]) == v) return k;
    return -1;
}

NodeFrame node_frame(const sim::FemModel& model, std::size_t v) {
    const Mat3 G = Mat3::Identity() + model.time() * model.growth().tensor();
    return node_frame(model, v, G, G.inverse());
}

NodalStress principal_of(const sim::FemModel& model, std::size_t v, const Mat3& sigma, NodalStress means) {
    const NodeFrame fr = node_frame(model, v);
    Eigen::SelfAdjointEigenSolver<Mat2> eig(project(fr, sigma));
    const Vec2 d = eig.eigenvectors().col(1);
    const Vec3 normal_dir = d.x() * fr.e1 + d.y() * fr.e2;
    means.ratio = eig.eigenvalues()[1] / means.threshold;
    means.crack = (fr.G_inv * fr.n.cross(normal_dir)).normalized();
    return means;
}

NodeFrame node_frame(const sim::FemModel& model, std::size_t v, const Mat3& G, const Mat3& G_inv) {
    const Vec3& p0 = model.mesh().positions[vertex_id(v)];
    const mesh::TangentFrame fr = model.surface().frame(p0);
    NodeFrame out;
    out.G_inv = G_inv;
    out.n = (out.G_inv.transpose() * fr.n).normalized();
    const Vec3 e1 = G * fr.e_u;
    out.e1 = (e1 - e1.dot(out.n) * out.n).normalized();
    out.e2 = out.n.cross(out.e1);
    return out;
}

Mat2 project(const NodeFrame& fr, const Mat3& sigma) {
    Mat2 T;
    T << fr.e1.dot(sigma * fr.e1), fr.e1.dot(sigma * fr.e2), fr.e2.dot(sigma * fr.e1), fr.e2.dot(sigma * fr.e2);
    return T;
}

double max_eigenvalue(const Mat2& T) {
    const double mean = 0.5 * (T(0, 0) + T(1, 1)), half_diff = 0.5 * (T(0, 0) - T(1, 1));
    return mean + std::hypot(half_diff, 0.5 * (T(0, 1) + T(1, 0)));
}

std::array<Vec2, 3> local_corners(const sim::FemModel& model, std::size_t f, int k0, const mesh::TangentFrame& fr) {
    const mesh::SurfaceMesh& m = model.mesh();
    std::array<Vec2, 3> out;
    for (int k = 0; k < 3; ++k) {
        if (m.periodic) {
            out[static_cast<std::size_t>(k)] = m.corner_domain(face_id(f), k) - m.corner_domain(face_id(f), k0);
        } else {
            const Vec3 d = m.corner_position(face_id(f), k) - m.corner_position(face_id(f), k0);
            out[static_cast<std::size_t>(k)] = Vec2(d.dot(fr.e_u), d.dot(fr.e_v));
        }
    }
    return out;
}

double cross2(const Vec2& a, const Vec2& b) {
    return a.x() * b.y() - a.y() * b.x();
}

bool cast_ray(const sim::FemModel& model, std::size_t v, const Vec3& direction0, RayHit& hit) {
    const mesh::SurfaceMesh& m = model.mesh();
    const mesh::TangentFrame fr = model.surface().frame(m.positions[vertex_id(v)]);
    const Vec2 d = Vec2(direction0.dot(fr.e_u), direction0.dot(fr.e_v)).normalized();
    double best = std::numeric_limits<double>::infinity();
    bool found = false;
    for (std::uint32_t f : model.incident_faces(v)) {
        if (!model.alive(face_id(f))) continue;
        const int k = corner_of(m, f, v);
        const auto c = local_corners(model, f, k, fr);
        const Vec2 B = c[static_cast<std::size_t>((k + 1) % 3)], C = c[static_cast<std::size_t>((k + 2) % 3)];
        // s·d = B + τ(C − B): Cramer's rule.
        const Vec2 e = C - B;
        const double det = cross2(d, e);
        if (std::abs(det) < 1e-300) continue;
        const double s = cross2(B, e) / det; // distance along the ray
        const double tau = cross2(B, d) / det;
        if (s <= 0 || tau < -1e-9 || tau > 1 + 1e-9) continue;
        // Several faces can claim a ray through a shared vertex; keep the nearest exit.
        if (s < best) {
            best = s;
            hit.face = f;
            hit.edge = (k + 1) % 3;
            hit.t = std::clamp(tau, 0.0, 1.0);
            found = true;
        }
    }
    return found;
}

double min_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
    auto angle = [](const Vec3& p, const Vec3& q, const Vec3& r) {
        const Vec3 u = q - p, w = r - p;
        return std::atan2(u.cross(w).norm(), u.dot(w)) * RAD_TO_DEG;
    };
    return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)});
}

bool on_border(const sim::FemModel& model, std::size_t v) {
    const mesh::SurfaceMesh& m = model.mesh();
    for (std::uint32_t f : model.incident_faces(v)) {
        const int k = corner_of(m, f, v);
        for (int e : {k, (k + 2) % 3})
            if (m.neighbor(face_id(f), e).face == mesh::NO_FACE) return true;
    }
    return false;
}

bool is_tip(const sim::FemModel& model, std::size_t v) {
    const mesh::SurfaceMesh& m = model.mesh();
    // Called for every node at every time step: count the border edges first, and take
    // directions (no allocation) only when there are exactly two.
    std::array<std::pair<std::uint32_t, int>, 2> edges; // (face, far corner)
    int count = 0;
    for (std::uint32_t f : model.incident_faces(v)) {
        const int k = corner_of(m, f, v);
        for (const auto& [side, far] : {std::pair{k, (k + 1) % 3}, std::pair{(k + 2) % 3, (k + 2) % 3}})
            if (m.neighbor(face_id(f), side).face == mesh::NO_FACE) {
                if (count == 2) return false;
                edges[static_cast<std::size_t>(count++)] = {f, far};
            }
    }
    if (count != 2) return false;
    auto direction = [&](const std::pair<std::uint32_t, int>& e) {
        const Vec3 p = m.corner_position(face_id(e.first), corner_of(m, e.first, v));
        return Vec3((m.corner_position(face_id(e.first), e.second) - p).normalized());
    };
    return direction(edges[0]).dot(direction(edges[1])) > 1 - 1e-9;
}

} // namespace crackle::fracture::split_detail
