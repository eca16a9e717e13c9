/// @file FemModel time: growth, stiffness refresh, affine advance, tracked residuals (Federl 2002, §3.3.2, Alg. 5).
#include "core/log.hpp"
#include "sim/fem_model_internal.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace crackle::sim {

// === Time

Vec3 FemModel::shift(const Vec2i& offset, double t) const {
    if (offset == Vec2i::Zero()) return Vec3::Zero();
    return m_growth.period_shift(m_surface.period_shift(offset), t);
}

Vec3 FemModel::shift_rate(const Vec2i& offset) const {
    if (offset == Vec2i::Zero()) return Vec3::Zero();
    return m_growth.tensor() * m_surface.period_shift(offset);
}

void FemModel::invalidate_residuals() {
    m_x.residual_valid = m_xdot.residual_valid = false;
    m_x.load_norm = m_xdot.load_norm = -1;
}

void FemModel::set_time(double t) {
    if (t != m_time) invalidate_residuals();
    m_time = t;
    const double dt_top = std::abs(m_shrinkage.top(t) - m_stiffness_s_top);
    const double dt_bot = std::abs(m_shrinkage.bottom(t) - m_stiffness_s_bot);
    // At the horizon itself the shrinkage has moved by the refresh tolerance up to round-off:
    // that counts as reached, or time would stop there with the old shapes for good.
    if (std::max(dt_top, dt_bot) >= m_options.stiffness_refresh * (1 - 1e-9) && std::max(dt_top, dt_bot) > 0) {
        m_stiffness_s_top = m_shrinkage.top(t);
        m_stiffness_s_bot = m_shrinkage.bottom(t);
        for (std::size_t f = 0; f < m_mesh.num_faces(); ++f)
            build_element_stiffness(f);
        assemble();
        m_solver->invalidate(false);
        invalidate_residuals();
        ++m_stiffness_builds;
        log::debug("stiffness rebuilt at t = ", t, " (shrinkage top ", m_stiffness_s_top, ", bottom ",
                   m_stiffness_s_bot, ")");
    }
}

void FemModel::advance_time(double t) {
    const double dt = t - m_time;
    if (dt == 0.0) return;
    const bool shrinking = m_shrinkage.top_rate != 0 || m_shrinkage.bottom_rate != 0;
    if ((shrinking && m_options.stiffness_refresh <= 0) || t >= stiffness_horizon()) {
        advance_along_rate(dt);
        set_time(t);
        return;
    }
    // r(t) = b(t) − K x(t): both move affinely, so r += dt·(ḃ − K ẋ) = dt·r_rate.
    ensure_residual(Unknown::Position);
    ensure_residual(Unknown::Rate);
    for (std::size_t v = 0; v < m_mesh.num_vertices(); ++v)
        if (m_alive_degree[v] > 0)
            for (int j = 0; j < m_order; ++j)
                m_x.values[slot(v, j)] += dt * m_xdot.values[slot(v, j)];
    m_x.residual += dt * m_xdot.residual;
    m_x.load_norm = -1;
    m_time = t;
}

double FemModel::stiffness_horizon() const {
    double horizon = std::numeric_limits<double>::infinity();
    auto limit = [&](double rate, double s_ref) {
        if (rate == 0) return;
        // |rate·t − s_ref| reaches the refresh tolerance
        for (double tc : {(s_ref + m_options.stiffness_refresh) / rate, (s_ref - m_options.stiffness_refresh) / rate})
            if (tc > m_time * (1 + 1e-12)) horizon = std::min(horizon, tc);
    };
    limit(m_shrinkage.top_rate, m_stiffness_s_top);
    limit(m_shrinkage.bottom_rate, m_stiffness_s_bot);
    return horizon;
}

void FemModel::advance_along_rate(double dt) {
    invalidate_residuals();
    for (std::size_t v = 0; v < m_mesh.num_vertices(); ++v)
        if (m_alive_degree[v] > 0)
            for (int j = 0; j < m_order; ++j)
                m_x.values[slot(v, j)] += dt * m_xdot.values[slot(v, j)];
}

// === Residuals

namespace {
/// K_free·q, with the linear wedge's fixed-size product (the same bits as before modes).
VecX free_force(const Eigen::Ref<const MatX>& K, const VecX& q) {
    if (K.rows() == 9) {
        const Eigen::Matrix<double, 9, 18> K9 = K;
        const wedge::Vec18 q18 = q;
        return K9 * q18;
    }
    return K * q;
}
} // namespace

VecX FemModel::element_force(std::size_t f, Unknown u) const {
    return free_force(k_free(f), u == Unknown::Position ? displacement(f) : displacement_rate(f));
}

void FemModel::subtract_element_force(std::size_t f, const VecX& force, Eigen::VectorXd& r,
                                      const std::vector<char>* only) const {
    const mesh::Face& face = m_mesh.faces[face_id(f)];
    for (std::size_t k = 0; k < 3; ++k) {
        const std::size_t v = ix(face.v[k]);
        if (only && !(*only)[v]) continue;
        for (int j = 0; j < m_order; ++j)
            r.segment<3>(static_cast<Eigen::Index>(3 * slot(v, j))) -=
                force.segment<3>(9 * j + static_cast<Eigen::Index>(3 * k));
    }
}

Eigen::VectorXd FemModel::full_residual(Unknown u) const {
    // r = b − K x = −Σ_e (K_e q_e)_free over the alive elements
    Eigen::VectorXd r = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(3 * slot(m_mesh.num_vertices())));
    for (std::size_t f = 0; f < m_mesh.num_faces(); ++f)
        if (m_alive[f]) subtract_element_force(f, element_force(f, u), r);
    return r;
}

void FemModel::ensure_residual(Unknown u) {
    Field& fd = field(u);
    if (fd.residual_valid) return;
    fd.residual = full_residual(u);
    fd.residual_valid = true;
}

void FemModel::recompute_residual_at(Unknown u, const std::vector<std::size_t>& vertices) {
    Field& fd = field(u);
    if (!fd.residual_valid) return; // recomputed in full when needed
    std::vector<char> mark(m_mesh.num_vertices(), 0);
    for (std::size_t v : vertices) {
        mark[v] = 1;
        fd.residual.segment(static_cast<Eigen::Index>(3 * slot(v)), 3 * m_order).setZero();
    }
    std::vector<std::uint32_t> faces;
    for (std::size_t v : vertices)
        for (std::uint32_t f : m_incident[v])
            if (m_alive[f]) faces.push_back(f);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    for (std::uint32_t f : faces)
        subtract_element_force(f, element_force(f, u), fd.residual, &mark);
}

double FemModel::load_norm(Unknown u) {
    Field& fd = field(u);
    if (fd.load_norm >= 0) return fd.load_norm;
    // The residual with every top node at rest above its bottom node (positions), or with
    // ẋ = 0 (rates): the size of the loads that growth and shrinkage create.
    Eigen::VectorXd r = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(3 * slot(m_mesh.num_vertices())));
    const double s_bar = 0.5 * (m_shrinkage.top(m_time) + m_shrinkage.bottom(m_time));
    for (std::size_t f = 0; f < m_mesh.num_faces(); ++f) {
        if (!m_alive[f]) continue;
        const FaceId id = face_id(f);
        const mesh::Face& face = m_mesh.faces[id];
        VecX q = VecX::Zero(wedge::element_dofs(m_order)); // the modes at rest
        if (u == Unknown::Position) {
            wedge::Nodes p = current_nodes(id);
            for (std::size_t k = 0; k < 3; ++k)
                p[k + 3] = p[k] + (1.0 - s_bar) * m_thickness[ix(face.v[k])] * m_normal[ix(face.v[k])];
            q.head<18>() = wedge::flatten(p) - wedge::flatten(reference_nodes(id));
        } else {
            q = displacement_rate(f);
            for (std::size_t k = 0; k < 3; ++k)
                q.segment<3>(static_cast<Eigen::Index>(9 + 3 * k)) -= m_xdot.values[slot(ix(face.v[k]))];
            q.tail(9 * (m_order - 1)).setZero();
        }
        subtract_element_force(f, free_force(k_free(f), q), r);
    }
    fd.load_norm = r.norm();
    return fd.load_norm;
}

double FemModel::max_residual_force() {
    return max_residual(Unknown::Position);
}

std::vector<std::size_t> FemModel::vertices_over_residual(double force) {
    ensure_residual(Unknown::Position);
    const Field& fd = field(Unknown::Position);
    std::vector<std::size_t> out;
    for (std::size_t v = 0; v < m_mesh.num_vertices(); ++v)
        if (vertex_force_squared(fd, v) > force * force) out.push_back(v);
    return out;
}

double FemModel::max_rate_residual_force() {
    return max_residual(Unknown::Rate);
}

double FemModel::max_residual(Unknown u) {
    ensure_residual(u);
    const Field& fd = field(u);
    double worst = 0;
    for (std::size_t v = 0; v < m_mesh.num_vertices(); ++v)
        worst = std::max(worst, vertex_force_squared(fd, v));
    return std::sqrt(worst);
}

} // namespace crackle::sim
