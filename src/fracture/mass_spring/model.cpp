/// @file MassSpringModel's construction (masses, anchors, springs), loads, energy, gradient (§4.1–4.3, Eqs. 3.4, 3.6).
#include "core/error.hpp"
#include "fracture/mass_spring/mass_spring_internal.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::fracture {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;
using mesh::vertex_id;

namespace {

double cot(const Vec3& a, const Vec3& b) {
    return a.dot(b) / std::max(a.cross(b).norm(), 1e-300);
}

} // namespace

MassSpringModel::MassSpringModel(const mesh::SurfaceMesh& mesh, const mesh::Surface& surface,
                                 const sim::GrowthField& growth, const sim::ShrinkageOptions& shrinkage,
                                 const sim::LayerFields& fields, const MassSpringOptions& options, Rng& rng)
    : m_mesh(mesh), m_surface(surface), m_growth(growth), m_shrinkage(shrinkage), m_options(options),
      m_poisson(fields.poisson_ratio), m_solver(std::make_unique<Solver>()) {
    CRACKLE_ASSERT(options.layers >= 1, "at least one layer");
    const std::size_t nv = m_mesh.num_vertices();
    const int L = options.layers;

    // === Per vertex: fields, Voronoi area (the cotangent dual area of a Delaunay mesh)
    m_thickness.resize(nv);
    m_young.resize(nv);
    m_area.assign(nv, 0.0);
    std::vector<double> threshold(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        const Vec3& p = m_mesh.positions[vertex_id(v)];
        const Vec2 uv = surface.periodic() ? surface.uv_of_domain(m_mesh.domain[vertex_id(v)]) : surface.uv(p);
        m_thickness[v] = fields.thickness->at(p, uv);
        m_young[v] = fields.young_modulus->at(p, uv);
        threshold[v] = fields.threshold_stress->at(p, uv);
    }
    for (std::size_t fi = 0; fi < m_mesh.num_faces(); ++fi) {
        const FaceId f = face_id(fi);
        const auto p = m_mesh.face_positions(f);
        for (std::size_t k = 0; k < 3; ++k) {
            const std::size_t j = (k + 1) % 3, l = (k + 2) % 3;
            // Voronoi part of corner k: (|e_kj|² cot θ_l + |e_kl|² cot θ_j) / 8
            const double cot_l = cot(p[k] - p[l], p[j] - p[l]), cot_j = cot(p[k] - p[j], p[l] - p[j]);
            m_area[ix(m_mesh.faces[f].v[k])] +=
                ((p[j] - p[k]).squaredNorm() * cot_l + (p[l] - p[k]).squaredNorm() * cot_j) / 8.0;
        }
    }
    double h_mean = 0;
    for (double h : m_thickness)
        h_mean += h;
    h_mean /= static_cast<double>(nv);
    m_layer_thickness = h_mean / L;

    // === Masses: layer ℓ sits ℓ·h_l above the background (zero-rest-length anchors for layer 0)
    m_x.resize(static_cast<std::size_t>(L) * nv);
    m_anchor0.resize(nv);
    m_anchor_k.resize(nv);
    m_layer_k.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        const Vec3& p = m_mesh.positions[vertex_id(v)];
        const Vec3 n = surface.normal(p);
        const double hl = m_thickness[v] / L;
        for (int l = 0; l < L; ++l)
            m_x[static_cast<std::size_t>(l) * nv + v] = p + l * hl * n;
        m_anchor0[v] = p;
        // Shear coupling of a sub-layer (Hirota: ∝ cell area): G / h_l per unit area. With one
        // layer the shear-lag length √(K_S/K_A) = h√(2(1 + ν)) ≈ 1.6 h, as in the wedge FEM.
        const double G = m_young[v] / (2.0 * (1.0 + m_poisson));
        m_anchor_k[v] = G / hl * std::max(m_area[v], 0.0);
        m_layer_k[v] = m_anchor_k[v];
    }

    // === Material springs: Delaunay edges, k = E h_l · ½(cot α + cot β) (Hirota et al.)
    double k_sum = 0, l_sum = 0, eps_sum = 0;
    for (std::size_t fi = 0; fi < m_mesh.num_faces(); ++fi) {
        const FaceId f = face_id(fi);
        for (int k = 0; k < 3; ++k) {
            const mesh::FaceNeighbor nb = m_mesh.neighbor(f, k);
            if (nb.face != mesh::NO_FACE && ix(nb.face) < fi) continue; // each edge once
            const auto& face = m_mesh.faces[f];
            const auto ka = static_cast<std::size_t>(k), kb = static_cast<std::size_t>((k + 1) % 3),
                       kc = static_cast<std::size_t>((k + 2) % 3);
            const auto p = m_mesh.face_positions(f);
            double cots = cot(p[ka] - p[kc], p[kb] - p[kc]);
            if (nb.face != mesh::NO_FACE) {
                const auto q = m_mesh.face_positions(nb.face);
                const auto na = static_cast<std::size_t>(nb.edge), nbb = static_cast<std::size_t>((nb.edge + 1) % 3),
                           nc = static_cast<std::size_t>((nb.edge + 2) % 3);
                cots += cot(q[na] - q[nc], q[nbb] - q[nc]);
            }
            const std::size_t va = ix(face.v[ka]), vb = ix(face.v[kb]);
            const double E = 0.5 * (m_young[va] + m_young[vb]);
            // Break strain: the strain at which a plate of the same E, ν under the equal biaxial
            // strain that growth and shrinkage produce reaches threshold_stress (σ = E ε/(1 − ν)),
            // so a preset cracks at the same shrinkage with every method. [I]: the thesis gives
            // the springs' break strains directly (§4.1).
            const double eps_b = 0.5 * (threshold[va] + threshold[vb]) * (1.0 - m_poisson) / E;
            for (int l = 0; l < L; ++l) {
                Spring s;
                s.a = static_cast<std::uint32_t>(static_cast<std::size_t>(l) * nv + va);
                s.b = static_cast<std::uint32_t>(static_cast<std::size_t>(l) * nv + vb);
                s.offset = face.offset[kb] - face.offset[ka];
                s.layer = l;
                s.face = static_cast<std::uint32_t>(fi);
                s.edge = k;
                s.k = E * m_layer_thickness * std::max(0.0, 0.5 * cots);
                s.rest0 = (m_x[s.b] + shift(s.offset, 0.0) - m_x[s.a]).norm();
                s.break_strain = eps_b * (1.0 + options.break_jitter * rng.uniform(-1.0, 1.0));
                m_springs.push_back(s);
                k_sum += s.k;
                l_sum += s.rest0;
                eps_sum += s.break_strain;
            }
        }
    }
    const double ns = static_cast<double>(std::max<std::size_t>(m_springs.size(), 1));
    m_mean_spring = l_sum / ns;
    m_force_scale = (k_sum / ns) * m_mean_spring * (eps_sum / ns);
}

MassSpringModel::~MassSpringModel() = default;

Vec3 MassSpringModel::shift(const Vec2i& offset, double t) const {
    if (offset == Vec2i::Zero()) return Vec3::Zero();
    return m_growth.period_shift(m_surface.period_shift(offset), t);
}

Vec3 MassSpringModel::anchor(std::size_t v, double t) const {
    return m_growth.position(m_anchor0[v], t);
}

double MassSpringModel::rest_length(const Spring& s, double t) const {
    // Eq. 3.6: L(t) = L(0)(1 − s(t)); layers interpolate between the bottom and top rates.
    const double f = (s.layer + 0.5) / m_options.layers;
    const double shrink = m_shrinkage.bottom(t) + f * (m_shrinkage.top(t) - m_shrinkage.bottom(t));
    return s.rest0 * (1.0 - shrink);
}

void MassSpringModel::set_time(double t) {
    m_time = t;
}

void MassSpringModel::restore(const State& s) {
    m_time = s.time;
    m_x = s.x;
    m_anchor0 = s.anchor0;
    m_loads.valid = false; // the anchors are part of the loads
}

const MassSpringModel::Loads& MassSpringModel::loads(double t) const {
    Loads& L = m_loads;
    if (L.valid && L.t == t) return L;
    const std::size_t nv = num_vertices();
    L.t = t;
    L.valid = true;
    L.rest.resize(m_springs.size());
    L.shift.resize(m_springs.size());
    for (std::size_t si = 0; si < m_springs.size(); ++si) {
        L.rest[si] = rest_length(m_springs[si], t);
        L.shift[si] = shift(m_springs[si].offset, t);
    }
    L.anchor.resize(nv);
    for (std::size_t v = 0; v < nv; ++v)
        L.anchor[v] = anchor(v, t);
    L.layer_rest.clear();
    if (m_options.layers > 1) {
        // Inter-layer springs: rest vector h_l(t)·n(t), n the normal carried by the growth.
        const double hl_t = m_layer_thickness * (1.0 - 0.5 * (m_shrinkage.top(t) + m_shrinkage.bottom(t)));
        const Mat3 G_invT = (Mat3::Identity() + t * m_growth.tensor()).inverse().transpose();
        L.layer_rest.resize(nv);
        for (std::size_t v = 0; v < nv; ++v)
            L.layer_rest[v] = hl_t * (G_invT * m_surface.normal(m_mesh.positions[vertex_id(v)])).normalized();
    }
    return L;
}

double MassSpringModel::energy(const std::vector<Vec3>& x, double t) const {
    const Loads& L = loads(t);
    const std::size_t nv = num_vertices();
    double e = 0;
    for (std::size_t si = 0; si < m_springs.size(); ++si) {
        const Spring& s = m_springs[si];
        if (s.broken) continue;
        const double l = (x[s.b] + L.shift[si] - x[s.a]).norm();
        e += 0.5 * s.k * sqr(l - L.rest[si]);
    }
    for (std::size_t v = 0; v < nv; ++v)
        e += 0.5 * m_anchor_k[v] * (x[v] - L.anchor[v]).squaredNorm();
    for (int l = 0; l + 1 < m_options.layers; ++l)
        for (std::size_t v = 0; v < nv; ++v) {
            const std::size_t lo = static_cast<std::size_t>(l) * nv + v, hi = lo + nv;
            e += 0.5 * m_layer_k[v] * (x[hi] - x[lo] - L.layer_rest[v]).squaredNorm();
        }
    return e;
}

void MassSpringModel::gradient(const std::vector<Vec3>& x, double t, Eigen::VectorXd& g) const {
    const Loads& L = loads(t);
    const std::size_t nv = num_vertices();
    g.setZero(static_cast<Eigen::Index>(3 * x.size()));
    auto add = [&](std::size_t m, const Vec3& f) { g.segment<3>(static_cast<Eigen::Index>(3 * m)) += f; };
    for (std::size_t si = 0; si < m_springs.size(); ++si) {
        const Spring& s = m_springs[si];
        if (s.broken) continue;
        const Vec3 d = x[s.b] + L.shift[si] - x[s.a];
        const double l = d.norm();
        const Vec3 f = s.k * (l - L.rest[si]) * d / l;
        add(s.b, f);
        add(s.a, -f);
    }
    for (std::size_t v = 0; v < nv; ++v)
        add(v, m_anchor_k[v] * (x[v] - L.anchor[v]));
    for (int l = 0; l + 1 < m_options.layers; ++l)
        for (std::size_t v = 0; v < nv; ++v) {
            const std::size_t lo = static_cast<std::size_t>(l) * nv + v, hi = lo + nv;
            const Vec3 f = m_layer_k[v] * (x[hi] - x[lo] - L.layer_rest[v]);
            add(hi, f);
            add(lo, -f);
        }
}

} // namespace crackle::fracture
