#include "fracture/mass_spring/mass_spring.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/progress.hpp"
#include "core/timer.hpp"
#include "fracture/toolkit/pick.hpp"
#include "mesh/cut.hpp"
#include "mesh/lattice.hpp"
#include "mesh/sampling.hpp"
#include "mesh/triangulate.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

#include <algorithm>
#include <limits>
#include <map>
#include <sstream>

namespace crackle::fracture {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;
using mesh::vertex_id;

// === Discretization

mesh::SurfaceMesh mass_spring_mesh(const mesh::Surface& surface, std::size_t masses, Lattice lattice,
                                   const mesh::SamplingOptions& sampling, Rng& rng) {
    if (lattice == Lattice::Regular) {
        if (surface.periodic()) {
            // Columns along v: springs run along v and ±30° from u. So growth along v, which
            // the lattice has springs for, shows the failure of Fig. 4.6 (cracks follow the
            // lattice, not the load); growth around a trunk (u) happens to suit it.
            double stretch = 1;
            const Vec2 period = surface.period();
            auto pts = mesh::triangular_lattice(Vec2(period.y(), period.x()), masses, &stretch);
            for (Vec2& q : pts)
                q = Vec2(q.y(), q.x());
            if (std::abs(stretch - 1) > 0.05)
                log::warn("the regular lattice is stretched by ", 100 * (stretch - 1),
                          " % along u to fit the tile; cracks will favour its directions even more");
            return mesh::triangulate_periodic(pts, surface);
        }
        return mesh::triangulate_sphere(mesh::icosphere_points(surface.radius(), mesh::icosphere_level(masses)),
                                        surface);
    }
    mesh::SamplingOptions o = sampling;
    o.count = masses;
    if (surface.periodic())
        return mesh::triangulate_periodic(mesh::sample_periodic(surface.period(), o, {}, rng), surface);
    return mesh::triangulate_sphere(mesh::sample_sphere(surface.radius(), o, {}, rng), surface);
}

// === The linear solver: modified Newton with a Cholesky factor of the (projected) Hessian
// M = Σ k(uuᵀ + g(I − uuᵀ)) + anchors + layer links, frozen when factored (u the spring
// direction, g = max(0, 1 − L/l) its geometric factor). M drifts from the true Hessian only as
// the strains change, so x ← x − M⁻¹∇E contracts fast. A broken spring is a rank-1 (or rank-3,
// with its geometric part) downdate of the factor (CHOLMOD updown, Davis & Hager) instead of a
// refactorization; the factor is rebuilt only when the iteration slows.

namespace {

/// Exposes the factor held by Eigen's CHOLMOD wrapper, for cholmod_updown.
struct CholmodFactor : Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> {
    cholmod_factor* factor() { return m_cholmodFactor; }
};

} // namespace

struct MassSpringModel::Solver {
    CholmodFactor llt;
    Eigen::SparseMatrix<double> M; // lower triangle
    std::vector<Eigen::Triplet<double>> triplets;
    std::vector<int> pinv;         // inverse of the factor's fill-reducing permutation
    std::vector<Vec3> direction;   // per spring: u held in the factor
    std::vector<double> geometric; // per spring: the geometric factor max(0, 1 − L/l) held in it
    bool analyzed = false, factored = false;
    std::size_t factorizations = 0, downdates = 0;
};

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

void MassSpringModel::factorize() {
    const std::size_t nv = num_vertices();
    Solver& S = *m_solver;
    auto& trip = S.triplets;
    trip.clear();
    auto block = [&](std::size_t r, std::size_t c, const Mat3& m) {
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                const auto row = static_cast<Eigen::Index>(3 * r) + i, col = static_cast<Eigen::Index>(3 * c) + j;
                if (row >= col) trip.emplace_back(row, col, m(i, j));
            }
    };
    const Loads& now = loads(m_time);
    S.direction.resize(m_springs.size());
    S.geometric.resize(m_springs.size());
    for (std::size_t si = 0; si < m_springs.size(); ++si) {
        const Spring& s = m_springs[si];
        // Broken springs keep zero entries: the pattern never changes, so it is analysed once.
        const Vec3 d = m_x[s.b] + now.shift[si] - m_x[s.a];
        const double l = d.norm();
        const Vec3 u = d / l;
        S.direction[si] = u;
        S.geometric[si] = std::max(0.0, 1.0 - now.rest[si] / l);
        const Mat3 uu = u * u.transpose();
        const Mat3 K = s.broken ? Mat3::Zero() : Mat3(s.k * (uu + S.geometric[si] * (Mat3::Identity() - uu)));
        block(s.a, s.a, K);
        block(s.b, s.b, K);
        block(std::max(s.a, s.b), std::min(s.a, s.b), -K);
    }
    for (std::size_t v = 0; v < nv; ++v)
        block(v, v, m_anchor_k[v] * Mat3::Identity());
    for (int l = 0; l + 1 < m_options.layers; ++l)
        for (std::size_t v = 0; v < nv; ++v) {
            const std::size_t lo = static_cast<std::size_t>(l) * nv + v, hi = lo + nv;
            const Mat3 K = m_layer_k[v] * Mat3::Identity();
            block(lo, lo, K);
            block(hi, hi, K);
            block(hi, lo, -K);
        }
    const auto n = static_cast<Eigen::Index>(3 * m_x.size());
    S.M.resize(n, n);
    S.M.setFromTriplets(trip.begin(), trip.end());
    if (!S.analyzed) {
        // Small systems: simplicial LDLᵀ directly (supernodal BLAS calls cost more than they
        // save there); large ones: supernodal, converted to LDLᵀ for the updates.
        S.llt.setMode(n < 30000 ? Eigen::CholmodLDLt : Eigen::CholmodSupernodalLLt);
        S.llt.analyzePattern(S.M);
        S.analyzed = true;
    }
    S.llt.factorize(S.M);
    if (S.llt.info() != Eigen::Success)
        throw NumericError("mass-spring: the stiffness matrix is not positive definite at t = "
                           + std::to_string(m_time));
    cholmod_factor* L = S.llt.factor();
    if (L->is_super || L->is_ll) cholmod_change_factor(CHOLMOD_REAL, 0, 0, 1, 1, L, &S.llt.cholmod());
    S.pinv.resize(L->n);
    const int* perm = static_cast<const int*>(L->Perm);
    for (std::size_t k = 0; k < L->n; ++k)
        S.pinv[static_cast<std::size_t>(perm[k])] = static_cast<int>(k);
    S.factored = true;
    ++S.factorizations;
}

void MassSpringModel::break_spring(std::size_t si) {
    Spring& s = m_springs[si];
    CRACKLE_ASSERT(!s.broken, "a spring breaks once");
    s.broken = true;
    Solver& S = *m_solver;
    if (!S.factored) return;
    // M − C Cᵀ with the spring's block k(uuᵀ + g(I − uuᵀ)) = Σ c cᵀ: c = √k u and, when the
    // geometric factor g > 0, √(kg) p for the two unit vectors p ⟂ u; each column −c at a, +c at
    // b, rows in the factor's order and sorted.
    const Vec3 u = S.direction[si];
    std::vector<Vec3> columns{std::sqrt(s.k) * u};
    if (S.geometric[si] > 0) {
        const Vec3 p1 = u.unitOrthogonal(), p2 = u.cross(p1);
        columns.push_back(std::sqrt(s.k * S.geometric[si]) * p1);
        columns.push_back(std::sqrt(s.k * S.geometric[si]) * p2);
    }
    cholmod_common& cm = S.llt.cholmod();
    const std::size_t ncol = columns.size();
    cholmod_sparse* C = cholmod_allocate_sparse(S.pinv.size(), ncol, 6 * ncol, 1, 1, 0, CHOLMOD_REAL, &cm);
    auto* Cp = static_cast<int*>(C->p);
    auto* Ci = static_cast<int*>(C->i);
    auto* Cx = static_cast<double*>(C->x);
    for (std::size_t j = 0; j < ncol; ++j) {
        std::array<std::pair<int, double>, 6> entries;
        for (std::size_t i = 0; i < 3; ++i) {
            entries[i] = {S.pinv[3 * s.a + i], -columns[j][static_cast<Eigen::Index>(i)]};
            entries[3 + i] = {S.pinv[3 * s.b + i], columns[j][static_cast<Eigen::Index>(i)]};
        }
        std::sort(entries.begin(), entries.end());
        Cp[j] = static_cast<int>(6 * j);
        for (std::size_t k = 0; k < 6; ++k) {
            Ci[6 * j + k] = entries[k].first;
            Cx[6 * j + k] = entries[k].second;
        }
    }
    Cp[ncol] = static_cast<int>(6 * ncol);
    const int ok = cholmod_updown(0, C, S.llt.factor(), &cm);
    cholmod_free_sparse(&C, &cm);
    ++S.downdates;
    // A failed downdate (lost positive definiteness to round-off) just means refactoring.
    if (!ok || cm.status != CHOLMOD_OK) S.factored = false;
}

Eigen::VectorXd MassSpringModel::solve_stiffness(const Eigen::VectorXd& b) {
    if (!m_solver->factored) factorize();
    return m_solver->llt.solve(b);
}

void MassSpringModel::hessian_times(const Eigen::VectorXd& v, double t, Eigen::VectorXd& out) const {
    // The projected Hessian (geometric term kept when stretched, so it stays PSD), matrix-free.
    const std::size_t nv = num_vertices();
    out.setZero(v.size());
    auto seg = [](const Eigen::VectorXd& w, std::size_t m) { return w.segment<3>(static_cast<Eigen::Index>(3 * m)); };
    for (const Spring& s : m_springs) {
        if (s.broken) continue;
        const Vec3 d = m_x[s.b] + shift(s.offset, t) - m_x[s.a];
        const double l = d.norm();
        const Vec3 u = d / l;
        const Vec3 dv = seg(v, s.b) - seg(v, s.a);
        const double geo = std::max(0.0, 1.0 - rest_length(s, t) / l);
        const Vec3 f = s.k * (u * u.dot(dv) + geo * (dv - u * u.dot(dv)));
        out.segment<3>(static_cast<Eigen::Index>(3 * s.b)) += f;
        out.segment<3>(static_cast<Eigen::Index>(3 * s.a)) -= f;
    }
    for (std::size_t v_ = 0; v_ < nv; ++v_)
        out.segment<3>(static_cast<Eigen::Index>(3 * v_)) += m_anchor_k[v_] * seg(v, v_);
    for (int l = 0; l + 1 < m_options.layers; ++l)
        for (std::size_t w = 0; w < nv; ++w) {
            const std::size_t lo = static_cast<std::size_t>(l) * nv + w, hi = lo + nv;
            const Vec3 f = m_layer_k[w] * (seg(v, hi) - seg(v, lo));
            out.segment<3>(static_cast<Eigen::Index>(3 * hi)) += f;
            out.segment<3>(static_cast<Eigen::Index>(3 * lo)) -= f;
        }
}

std::size_t MassSpringModel::factorizations() const {
    return m_solver->factorizations;
}
std::size_t MassSpringModel::downdates() const {
    return m_solver->downdates;
}

double MassSpringModel::max_force() const {
    Eigen::VectorXd g;
    gradient(m_x, m_time, g);
    double worst = 0;
    for (Eigen::Index i = 0; i < g.size(); i += 3)
        worst = std::max(worst, g.segment<3>(i).norm());
    return worst;
}

bool MassSpringModel::slide_anchors() {
    if (m_options.anchor_slide <= 0) return false;
    const double max_len = m_options.anchor_slide * m_mean_spring;
    const Mat3 G_inv = (Mat3::Identity() + m_time * m_growth.tensor()).inverse();
    bool slid = false;
    for (std::size_t v = 0; v < num_vertices(); ++v) {
        const Vec3 a = anchor(v, m_time);
        const Vec3 d = m_x[v] - a;
        if (d.norm() <= max_len * (1 + 1e-9)) continue;
        // Drag the anchor so the anchor spring is max_len long (§4.1); store it pulled back.
        const Vec3 moved = m_x[v] - max_len * d.normalized();
        m_anchor0[v] = G_inv * moved;
        slid = true;
    }
    if (slid) m_loads.valid = false;
    return slid;
}

void MassSpringModel::relax(MassSpringStats* stats) {
    const double tol = m_options.tolerance * m_force_scale;
    for (int round = 0; round < 50; ++round) {
        Eigen::VectorXd g;
        int it = 0, slow = 0;
        double residual = 0, previous = 0;
        double e0 = energy(m_x, m_time);
        std::vector<Vec3> trial(m_x.size());
        for (;; ++it) {
            gradient(m_x, m_time, g);
            residual = 0;
            for (Eigen::Index i = 0; i < g.size(); i += 3)
                residual = std::max(residual, g.segment<3>(i).norm());
            if (!std::isfinite(residual))
                throw NumericError("mass-spring relaxation produced NaN at t = " + std::to_string(m_time));
            if (residual <= tol) break;
            if (it >= m_options.max_newton_iterations) {
                std::ostringstream os;
                os << "mass-spring relaxation did not converge: " << it << " Newton iterations, largest force "
                   << residual << " N (wanted " << tol << " N) at t = " << m_time
                   << "; the time step or the strains are too large for the springs (raise "
                      "simulation.solver_max_iterations or lower the growth or shrinkage rates)";
                throw NumericError(os.str());
            }
            // Refactor when the contraction is poor: the frozen directions drifted too far.
            if (it > 0 && residual > 0.25 * previous) {
                if (++slow >= 2) m_solver->factored = false;
            }
            previous = residual;
            const Eigen::VectorXd dx = solve_stiffness(-g);
            if (stats) stats->factorizations = m_solver->factorizations;
            // Backtracking line search on the energy (Armijo); round-off-level increases pass.
            const double slope = g.dot(dx);
            double alpha = 1.0, e = e0;
            for (int ls = 0; ls < 40; ++ls, alpha *= 0.5) {
                for (std::size_t m = 0; m < m_x.size(); ++m)
                    trial[m] = m_x[m] + alpha * dx.segment<3>(static_cast<Eigen::Index>(3 * m));
                e = energy(trial, m_time);
                if (e <= e0 + 1e-4 * alpha * slope + 1e-12 * std::abs(e0)) break;
            }
            m_x.swap(trial);
            e0 = e;
            if (stats) ++stats->newton_iterations;
        }
        if (stats) ++stats->newton_solves;
        if (!slide_anchors()) return;
        if (stats) ++stats->slides;
    }
    throw NumericError("mass-spring anchors kept sliding after 50 relaxations at t = " + std::to_string(m_time));
}

double MassSpringModel::ratio(std::size_t si) const {
    const Spring& s = m_springs[si];
    if (s.broken) return 0.0;
    const Loads& loads_now = loads(m_time);
    const double l = (m_x[s.b] + loads_now.shift[si] - m_x[s.a]).norm();
    return (l / loads_now.rest[si] - 1.0) / s.break_strain;
}

std::vector<double> MassSpringModel::ratio_rates() {
    // The gradient is affine in t at fixed positions (anchors, shifts and rest lengths all
    // move linearly): ġ exactly from two evaluations. Then the tangent-linear rate H ẋ = −ġ.
    const double dt = 1.0;
    Eigen::VectorXd g0, g1;
    gradient(m_x, m_time, g0);
    gradient(m_x, m_time + dt, g1);
    // M ẋ = −ġ, then two Richardson refinements with the true (projected) Hessian H.
    const Eigen::VectorXd gdot = (g1 - g0) / dt;
    Eigen::VectorXd xdot = solve_stiffness(-gdot), Hx;
    for (int k = 0; k < 2; ++k) {
        hessian_times(xdot, m_time, Hx);
        xdot += solve_stiffness(-gdot - Hx);
    }
    std::vector<double> rates(m_springs.size(), 0.0);
    for (std::size_t si = 0; si < m_springs.size(); ++si) {
        const Spring& s = m_springs[si];
        if (s.broken) continue;
        const Vec3 d = m_x[s.b] + shift(s.offset, m_time) - m_x[s.a];
        const double l = d.norm();
        const Vec3 ddot = xdot.segment<3>(static_cast<Eigen::Index>(3 * s.b))
                          + (shift(s.offset, m_time + dt) - shift(s.offset, m_time)) / dt
                          - xdot.segment<3>(static_cast<Eigen::Index>(3 * s.a));
        const double ldot = d.dot(ddot) / l;
        const double L = rest_length(s, m_time);
        const double Ldot = (rest_length(s, m_time + dt) - L) / dt;
        rates[si] = (ldot / L - l * Ldot / (L * L)) / s.break_strain;
    }
    return rates;
}

// === The crack pattern: Voronoi cells of the masses, cut along broken top springs

namespace {

/// The point standing for a Delaunay face in its dual: the circumcentre if it lies inside the
/// triangle (then the cells are exactly Voronoi), else the centroid (obtuse triangles, whose
/// circumcentre would fold the cells over).
Vec3 dual_point(const std::array<Vec3, 3>& p) {
    const Vec3 a = p[1] - p[0], b = p[2] - p[0];
    const Vec3 axb = a.cross(b);
    const Vec3 cc =
        p[0] + (b.squaredNorm() * axb.cross(a) + a.squaredNorm() * b.cross(axb)) / (2.0 * axb.squaredNorm());
    // Barycentric coordinates of cc.
    const double area = axb.norm();
    auto sub = [&](const Vec3& u, const Vec3& v, const Vec3& w) {
        return (v - u).cross(w - u).dot(axb) / (area * area);
    };
    const double w0 = sub(cc, p[1], p[2]), w1 = sub(p[0], cc, p[2]), w2 = 1.0 - w0 - w1;
    // Well inside: exact Voronoi. Near an edge (right triangles) the kites would be slivers.
    if (std::min({w0, w1, w2}) >= 0.05) return cc;
    return (p[0] + p[1] + p[2]) / 3.0;
}

} // namespace

CrackPattern run_mass_spring(MassSpringModel& model, const FractureOptions& options, Rng& rng, RunStats* run_out,
                             MassSpringStats* stats_out) {
    RunStats run;
    MassSpringStats stats;
    Timer total;
    EventLog events(options);
    const double dt_min = options.time_tolerance * options.duration;
    auto relax = [&]() {
        Timer t;
        model.relax(&stats);
        run.solve_seconds += t.seconds();
        ++run.solves;
    };
    relax();
    Progress progress("mass-spring", options.duration);
    const auto& springs = model.springs();

    auto max_ratio = [&]() {
        double r = 0;
        for (std::size_t s = 0; s < springs.size(); ++s)
            r = std::max(r, model.ratio(s));
        return r;
    };

    while (true) {
        progress.update(model.time());
        double ratio = 0;
        std::size_t s = 0;
        // The spring most over its break strain, ties drawn from the seed.
        if (pick_most_over(
                springs.size(), [&](std::size_t i) { return model.ratio(i); },
                [&](std::size_t i) { return !springs[i].broken; }, rng, s, ratio)) {
            if (events.full(model.time())) break;
            const auto& sp = springs[s];
            Event ev;
            ev.time = model.time();
            const auto& mesh = model.mesh();
            const auto p = mesh.face_positions(face_id(sp.face));
            ev.position = 0.5 * (p[static_cast<std::size_t>(sp.edge)] + p[static_cast<std::size_t>((sp.edge + 1) % 3)]);
            ev.kind = "break";
            ev.ratio = ratio;
            model.break_spring(s);
            ++stats.breaks;
            relax();
            events.add(ev);
            continue;
        }
        if (model.time() >= options.duration) break;

        // === The time of the next break (Alg. 5): predict it from the tangent-linear rates,
        // solve there, and bisect if the prediction overshot.
        Timer stress_timer;
        const std::vector<double> rates = model.ratio_rates();
        const double t0 = model.time();
        double step = options.duration - t0;
        for (std::size_t si = 0; si < springs.size(); ++si) {
            if (springs[si].broken || rates[si] <= 0) continue;
            step = std::min(step, (1.0 - model.ratio(si)) / rates[si]);
        }
        step = std::clamp(step, dt_min, std::max(dt_min, 0.25 * options.duration));
        run.stress_seconds += stress_timer.seconds();
        double t_hi = std::min(options.duration, t0 + step);
        // Anchors slide plastically (§4.1): a probe past the break must not leave its slides
        // behind, so every probe starts from the last state known to lie before the break.
        MassSpringModel::State below = model.state();
        model.set_time(t_hi);
        relax();
        ++stats.time_steps;
        ++run.time_steps;
        double r = max_ratio();
        if (r > 1.0 + 1e-6) {
            // Overshot: bisect between t0 (no break) and t_hi.
            double t_lo = t0;
            bool at_hi = true;
            while (t_hi - t_lo > dt_min && r > 1.0 + 1e-6) {
                const double mid = 0.5 * (t_lo + t_hi);
                model.restore(below);
                model.set_time(mid);
                relax();
                const double rm = max_ratio();
                if (rm > 1.0) {
                    t_hi = mid;
                    r = rm;
                    at_hi = true;
                } else {
                    t_lo = mid;
                    below = model.state();
                    at_hi = false;
                }
                ++stats.time_steps;
                ++run.time_steps;
            }
            if (!at_hi) {
                model.restore(below);
                model.set_time(t_hi);
                relax();
            }
        }
    }
    progress.finish();

    // === Pattern: kites of the Voronoi dual (one per Delaunay edge side), cut along the
    // Voronoi edges of broken top-layer springs
    const auto& dm = model.mesh();
    const mesh::Surface& surface = model.surface();
    const std::size_t nv = dm.num_vertices(), nf = dm.num_faces();
    const int L = model.layers();
    const double t_end = model.time();
    const Mat3 G = Mat3::Identity() + t_end * model.growth().tensor();

    CrackPattern p;
    p.method = "mass-spring";
    p.surface = surface;
    p.final_time = t_end;
    p.elements_initial = springs.size() / static_cast<std::size_t>(L);
    p.growth_map = G;
    p.poisson_ratio = model.poisson_ratio();
    mesh::SurfaceMesh& km = p.mesh;
    km.periodic = dm.periodic;
    km.period = dm.period;
    km.period_vectors = dm.period_vectors;
    // Vertices: the masses, then one dual point per Delaunay face.
    std::vector<Vec2i> dual_offset(nf, Vec2i::Zero());
    for (std::size_t v = 0; v < nv; ++v) {
        km.positions.push_back(dm.positions[vertex_id(v)]);
        if (dm.periodic) km.domain.push_back(dm.domain[vertex_id(v)]);
    }
    for (std::size_t fi = 0; fi < nf; ++fi) {
        const FaceId f = face_id(fi);
        const Vec3 d3 = dual_point(dm.face_positions(f));
        if (dm.periodic) {
            // The same point in the unrolled domain: barycentric weights carry over.
            const Vec2 a = dm.corner_domain(f, 0), b = dm.corner_domain(f, 1), c = dm.corner_domain(f, 2);
            const auto pos = dm.face_positions(f);
            const Vec3 n = (pos[1] - pos[0]).cross(pos[2] - pos[0]);
            const double w0 = (pos[1] - d3).cross(pos[2] - d3).dot(n) / n.squaredNorm();
            const double w1 = (pos[2] - d3).cross(pos[0] - d3).dot(n) / n.squaredNorm();
            const Vec2 unwrapped = w0 * a + w1 * b + (1 - w0 - w1) * c;
            const Vec2 canonical(wrap(unwrapped.x(), dm.period.x()), wrap(unwrapped.y(), dm.period.y()));
            dual_offset[fi] = Vec2i(static_cast<int>(std::lround((unwrapped.x() - canonical.x()) / dm.period.x())),
                                    static_cast<int>(std::lround((unwrapped.y() - canonical.y()) / dm.period.y())));
            km.domain.push_back(canonical);
            km.positions.push_back(surface.position(canonical));
        } else {
            km.positions.push_back(surface.project(d3));
        }
    }
    // Kites: for Delaunay edge a → b of face T (neighbour T'), cell a gets (a, d_T', d_T) and
    // cell b gets (b, d_T, d_T'); the Voronoi edge d_T–d_T' separates them.
    std::vector<std::array<char, 3>> cut;
    std::vector<std::size_t> kite_spring; // top-layer spring of each kite's Voronoi edge
    std::map<std::pair<std::uint32_t, int>, std::size_t> spring_index;
    for (std::size_t si = 0; si < springs.size(); ++si)
        if (springs[si].layer == L - 1) spring_index[{springs[si].face, springs[si].edge}] = si;
    for (const auto& [key, si] : spring_index) {
        const FaceId T = face_id(key.first);
        const int k = key.second;
        const mesh::FaceNeighbor nb = dm.neighbor(T, k);
        if (nb.face == mesh::NO_FACE) continue;
        const mesh::Face& ft = dm.faces[T];
        const mesh::Face& fn = dm.faces[nb.face];
        const auto ka = static_cast<std::size_t>(k), kb = static_cast<std::size_t>((k + 1) % 3);
        // d_T' in T's frame: shift by the offset difference of the shared corner a.
        const Vec2i shift_n = ft.offset[ka] - fn.offset[static_cast<std::size_t>((nb.edge + 1) % 3)];
        const mesh::VertexId dT = vertex_id(nv + ix(T)), dN = vertex_id(nv + ix(nb.face));
        const Vec2i oT = dual_offset[ix(T)], oN = dual_offset[ix(nb.face)] + shift_n;
        mesh::Face cell_a, cell_b;
        cell_a.v = {ft.v[ka], dN, dT};
        cell_a.offset = {ft.offset[ka], oN, oT};
        cell_b.v = {ft.v[kb], dT, dN};
        cell_b.offset = {ft.offset[kb], oT, oN};
        const bool broken = springs[si].broken;
        km.faces.push_back(cell_a);
        km.faces.push_back(cell_b);
        // The Voronoi edge is edge 1 of both kites (corner 1 → corner 2).
        cut.push_back({0, static_cast<char>(broken), 0});
        cut.push_back({0, static_cast<char>(broken), 0});
        kite_spring.push_back(si);
        kite_spring.push_back(si);
    }
    km.rebuild_adjacency();
    const std::vector<mesh::VertexId> origin = mesh::cut_along(km, cut);

    // === Deformed positions: the top of the layer moved with its masses; dual points take
    // the mean displacement of their face's masses.
    std::vector<Vec3> displacement(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        const Vec3 bottom = G * dm.positions[vertex_id(v)];
        const Vec3 n = (G.inverse().transpose() * surface.normal(dm.positions[vertex_id(v)])).normalized();
        displacement[v] =
            model.position(static_cast<std::size_t>(L - 1) * nv + v) - bottom - (L - 1) * model.layer_thickness() * n;
    }
    const std::size_t nk = km.num_vertices();
    p.deformed.resize(nk);
    p.thickness.resize(nk);
    for (std::size_t k = 0; k < nk; ++k) {
        const std::size_t o = ix(origin[k]);
        const Vec3 P0 = km.positions[vertex_id(k)];
        const Vec3 n = (G.inverse().transpose() * surface.normal(P0)).normalized();
        Vec3 u = Vec3::Zero();
        double h = 0;
        if (o < nv) {
            u = displacement[o];
            h = model.vertex_thickness(o);
        } else {
            for (mesh::VertexId w : dm.faces[face_id(o - nv)].v) {
                u += displacement[ix(w)] / 3.0;
                h += model.vertex_thickness(ix(w)) / 3.0;
            }
        }
        p.thickness[k] = h;
        p.deformed[k] = G * P0 + u + h * n;
    }
    for (int i = 0; i < 2; ++i)
        p.deformed_period[static_cast<std::size_t>(i)] = G * km.period_vectors[static_cast<std::size_t>(i)];
    p.removed.assign(km.num_faces(), 0);
    p.young_modulus.resize(km.num_faces());
    for (std::size_t f = 0; f < km.num_faces(); ++f)
        p.young_modulus[f] = model.young_modulus(ix(origin[ix(km.faces[face_id(f)].v[0])]));
    label_fragments(p);

    // === Crack lips: depth = broken layers counted down from the top
    std::map<std::pair<std::uint32_t, int>, std::vector<std::size_t>> layers_of_edge;
    for (std::size_t si = 0; si < springs.size(); ++si)
        layers_of_edge[{springs[si].face, springs[si].edge}].push_back(si);
    // A crack lip per kite whose Voronoi edge opened. A spring broken alone (both its Voronoi
    // vertices crack tips, e.g. the ladders of parallel breaks a load along a lattice direction
    // makes) is micro-damage: the cells stay joined around it, nothing opens, and it is neither
    // drawn nor counted.
    for (std::size_t f = 0; f < km.num_faces(); ++f) {
        const auto& top = springs[kite_spring[f]];
        if (!top.broken || km.neighbor(face_id(f), 1).face != mesh::NO_FACE) continue;
        const auto& column = layers_of_edge[{top.face, top.edge}];
        int depth_layers = 0;
        for (int l = L - 1; l >= 0; --l) {
            const auto it =
                std::find_if(column.begin(), column.end(), [&](std::size_t si) { return springs[si].layer == l; });
            if (it == column.end() || !springs[*it].broken) break;
            ++depth_layers;
        }
        CrackEdge c;
        c.face = face_id(f);
        c.edge = 1;
        const Vec3 d = model.position(top.b)
                       + G * (top.offset.x() * dm.period_vectors[0] + top.offset.y() * dm.period_vectors[1])
                       - model.position(top.a);
        c.opening = std::max(0.0, d.norm() - top.rest0);
        c.depth = depth_layers * model.layer_thickness();
        p.cracks.push_back(c);
        if (f % 2 == 0) stats.crack_depth_layers.push_back(depth_layers);
    }
    stats.factorizations = model.factorizations();
    stats.downdates = model.downdates();
    p.events_capped = events.capped();
    p.events = events.take();
    run.total_seconds = total.seconds();
    if (run_out) *run_out = run;
    if (stats_out) *stats_out = stats;
    return p;
}

} // namespace crackle::fracture
