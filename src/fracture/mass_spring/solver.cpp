/// @file MassSpringModel's equilibrium: stiffness factor and downdates, Newton relax, anchor slides, ratios (§4.1).
#include "core/budget.hpp"
#include "core/error.hpp"
#include "fracture/mass_spring/mass_spring_internal.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <string>

namespace crackle::fracture {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;
using mesh::vertex_id;

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

bool MassSpringModel::slide_anchors(double force_tolerance) {
    if (m_options.anchor_slide <= 0) return false;
    const double max_len = m_options.anchor_slide * m_mean_spring;
    const Mat3 G_inv = (Mat3::Identity() + m_time * m_growth.tensor()).inverse();
    bool slid = false;
    for (std::size_t v = 0; v < num_vertices(); ++v) {
        const Vec3 a = anchor(v, m_time);
        const Vec3 d = m_x[v] - a;
        // A slide shorter than what the relaxation's force tolerance resolves is noise: chasing
        // it would repeat relaxations without end.
        if (d.norm() <= max_len + std::max(1e-9 * max_len, force_tolerance / m_anchor_k[v])) continue;
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
            budget_check(); // a layered lattice's Newton step can take seconds (issue 16)
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
                      "simulation.newton_iterations or lower the growth or shrinkage rates)";
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
        if (!slide_anchors(tol)) return;
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

} // namespace crackle::fracture
