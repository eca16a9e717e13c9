/// @file FemModel construction, material and rest positions, node positions (Federl 2002, §5.3, §5.9).
#include "core/budget.hpp"
#include "core/error.hpp"
#include "sim/fem_model_internal.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace crackle::sim {

// === Construction

FemModel::FemModel(mesh::SurfaceMesh mesh, const mesh::Surface& surface, const GrowthField& growth,
                   const ShrinkageOptions& shrinkage, const LayerFields& fields, const FemOptions& options)
    : m_mesh(std::move(mesh)), m_surface(surface), m_growth(growth), m_shrinkage(shrinkage), m_fields(fields),
      m_options(options), m_order(options.thickness_order), m_solver(options.solver) {
    CRACKLE_ASSERT(
        (fields.thickness || fields.vertex_thickness)
            && ((fields.young_modulus && fields.threshold_stress && fields.toughness) || fields.face_material),
        "every layer field must be given");
    CRACKLE_ASSERT(m_order >= 1 && m_order <= wedge::MAX_THICKNESS_ORDER, "thickness order " << m_order);
    const std::size_t nv = m_mesh.num_vertices(), nf = m_mesh.num_faces();
    m_normal.resize(nv);
    m_thickness.resize(nv);
    m_x.values.assign(slot(nv), Vec3::Zero());
    m_xdot.values.assign(slot(nv), Vec3::Zero());
    m_last_update.assign(nv, 0.0);
    for (std::size_t v = 0; v < nv; ++v)
        init_vertex(v);
    m_alive.assign(nf, 1);
    m_num_alive = nf;
    m_material.resize(nf);
    m_broken.assign(nf, 0);
    m_k_free.resize(nf * k_stride());
    for (std::size_t f = 0; f < nf; ++f) {
        if (f % 1024 == 0) budget_check(); // a big layer takes seconds to build (--max-time)
        init_element(f);
    }
    rebuild_incidence();
    assemble();
    budget_check();
    m_solver->update(m_K, true);
    double thr = 0, h = 0;
    for (const ElementMaterial& mat : m_material)
        thr += mat.threshold_stress;
    for (double t : m_thickness)
        h += t;
    const double edge = std::sqrt(m_mesh.total_area() / static_cast<double>(std::max<std::size_t>(nf, 1)));
    m_force_scale = thr / static_cast<double>(std::max<std::size_t>(nf, 1)) * h
                    / static_cast<double>(std::max<std::size_t>(nv, 1)) * edge;
}

FemModel::~FemModel() = default;

double FemModel::thickness_at(const Vec3& p, const Vec2& domain) const {
    const Vec2 uv = m_surface.periodic() ? m_surface.uv_of_domain(domain) : m_surface.uv(p);
    return m_fields.thickness->at(p, uv);
}

void FemModel::init_vertex(std::size_t v) {
    const Vec3& p = m_mesh.positions[vertex_id(v)];
    m_normal[v] = m_surface.normal(p);
    m_thickness[v] = m_fields.vertex_thickness
                         ? (*m_fields.vertex_thickness)[v]
                         : thickness_at(p, m_surface.periodic() ? m_mesh.domain[vertex_id(v)] : Vec2::Zero());
    CRACKLE_ASSERT(m_thickness[v] > 0, "non-positive layer thickness at vertex " << v);
    m_x.values[slot(v)] = rest_top(p, m_normal[v], m_thickness[v]);
}

Vec3 FemModel::rest_top(const Vec3& p0, const Vec3& n0, double h) const {
    // The grown surface's normal: normals map with the inverse transpose of I + tT.
    const Mat3 G = Mat3::Identity() + m_time * m_growth.tensor();
    const Vec3 n = G.inverse().transpose() * n0;
    const double s_bar = 0.5 * (m_shrinkage.top(m_time) + m_shrinkage.bottom(m_time));
    return m_growth.position(p0, m_time) + (1.0 - s_bar) * h * n.normalized();
}

Vec3 FemModel::rest_top_rate(const Vec3& p0, const Vec3& n0, double h) const {
    const Mat3& T = m_growth.tensor();
    const Mat3 G_inv_t = (Mat3::Identity() + m_time * T).inverse().transpose();
    const Vec3 m = G_inv_t * n0;
    const double len = m.norm();
    const Vec3 n = m / len;
    // ṁ = −G⁻ᵀ Tᵀ m, and the unit normal turns with the part of it across n.
    const Vec3 m_dot = -G_inv_t * (T.transpose() * m);
    const Vec3 n_dot = (m_dot - n * n.dot(m_dot)) / len;
    const double s_bar = 0.5 * (m_shrinkage.top(m_time) + m_shrinkage.bottom(m_time));
    const double s_bar_dot = 0.5 * (m_shrinkage.top_rate + m_shrinkage.bottom_rate);
    return m_growth.velocity(p0) - s_bar_dot * h * n + (1.0 - s_bar) * h * n_dot;
}

void FemModel::init_element(std::size_t f) {
    record_element(f);
    const FaceId id = face_id(f);
    ElementMaterial& mat = m_material[f];
    m_broken[f] = 0;
    if (m_fields.face_material) {
        mat = (*m_fields.face_material)[f];
        build_element_stiffness(f);
        return;
    }
    mat.young_modulus = m_fields.young_modulus->face_average(m_mesh, id, m_surface);
    if (m_trial.active && m_trial.stiffness_only) { // nothing reads them before the rollback
        mat.threshold_stress = m_fields.threshold_stress->min_value();
        mat.toughness = m_fields.toughness->min_value();
    } else {
        mat.threshold_stress = m_fields.threshold_stress->face_average(m_mesh, id, m_surface);
        mat.toughness = m_fields.toughness->face_average(m_mesh, id, m_surface);
    }
    build_element_stiffness(f);
}

void FemModel::build_element_stiffness(std::size_t f) {
    const wedge::Nodes q = reference_nodes_at(f, m_stiffness_s_top, m_stiffness_s_bot);
    if (const double det = wedge::min_det_j(q); !(det > 0)) refuse_inverted(f, q, det);
    if (m_order == 1) {
        const wedge::Mat18 K = wedge::stiffness(q, element_elasticity(face_id(f)));
        k_free(f) = K.bottomRows<9>();
    } else {
        k_free(f) = wedge::stiffness(q, element_elasticity(face_id(f)), m_order).bottomRows(9 * m_order);
    }
}

MatX FemModel::element_stiffness(std::size_t f) const {
    const wedge::Nodes ref = reference_nodes_at(f, m_stiffness_s_top, m_stiffness_s_bot);
    if (m_order == 1) return wedge::stiffness(ref, element_elasticity(face_id(f)));
    return wedge::stiffness(ref, element_elasticity(face_id(f)), m_order);
}

void FemModel::refuse_inverted(std::size_t f, const wedge::Nodes& q, double det) const {
    const double edge = (q[1] - q[0]).norm(), height = (q[3] - q[0]).norm();
    std::ostringstream os;
    os << "an element of the layer turns inside out at rest (det J = " << det << ", element " << f << " at ("
       << q[0].x() << ", " << q[0].y() << ", " << q[0].z() << "), edge " << edge << " m, height " << height << " m";
    if (m_stiffness_builds == 0 && m_time == 0) {
        // Before any work: the layer's shape itself cannot be meshed (a layer thicker than the
        // curvature allows, or far thicker than its elements are wide).
        os << ")";
        throw InputError("material.thickness", os.str(),
                         "use a thinner layer, a larger surface or more elements (simulation.elements)");
    }
    os << ", at t = " << m_time << " with shrinkage top " << m_stiffness_s_top << ", bottom " << m_stiffness_s_bot
       << "): the top and bottom rest shapes differ too much for the wedges; lower material.shrinkage's difference "
          "or simulation.duration";
    throw NumericError(os.str());
}

wedge::Nodes FemModel::reference_nodes_at(std::size_t f, double s_top, double s_bot) const {
    const FaceId id = face_id(f);
    const mesh::Face& face = m_mesh.faces[id];
    std::array<Vec3, 3> bottom0, normals;
    std::array<double, 3> heights{};
    for (std::size_t k = 0; k < 3; ++k) {
        bottom0[k] = m_mesh.corner_position(id, static_cast<int>(k));
        normals[k] = m_normal[ix(face.v[k])];
        heights[k] = m_thickness[ix(face.v[k])];
    }
    return reference_shape(bottom0, normals, heights, s_top, s_bot);
}

// === Positions

Vec3 FemModel::bottom_position(VertexId v) const {
    return m_growth.position(m_mesh.positions[v], m_time);
}

Vec3 FemModel::bottom_step(VertexId from, VertexId to) const {
    const Vec3 a = bottom_position(from), b = bottom_position(to);
    Vec3 best = b - a;
    if (!m_mesh.periodic) return best;
    for (int i = -1; i <= 1; ++i)
        for (int j = -1; j <= 1; ++j) {
            const Vec3 d = b + shift(Vec2i(i, j), m_time) - a;
            if (d.squaredNorm() < best.squaredNorm()) best = d;
        }
    return best;
}

wedge::Nodes FemModel::current_nodes(FaceId f) const {
    const mesh::Face& face = m_mesh.faces[f];
    wedge::Nodes p;
    for (std::size_t k = 0; k < 3; ++k) {
        const Vec3 s = shift(face.offset[k], m_time);
        p[k] = m_growth.position(m_mesh.positions[face.v[k]], m_time) + s;
        p[k + 3] = m_x.values[slot(ix(face.v[k]))] + s;
    }
    return p;
}

wedge::Nodes FemModel::reference_nodes(FaceId f) const {
    return reference_nodes_at(ix(f), m_shrinkage.top(m_time), m_shrinkage.bottom(m_time));
}

VecX FemModel::displacement(std::size_t f) const {
    // q = P − Q, differences of nearby positions: accurate to round-off of the positions. The
    // modes' amplitudes are displacements already (0 at rest).
    VecX q(wedge::element_dofs(m_order));
    q.head<18>() = wedge::flatten(current_nodes(face_id(f))) - wedge::flatten(reference_nodes(face_id(f)));
    const mesh::Face& face = m_mesh.faces[face_id(f)];
    for (int j = 1; j < m_order; ++j)
        for (std::size_t k = 0; k < 3; ++k)
            q.segment<3>(9 + 9 * j + 3 * static_cast<Eigen::Index>(k)) = m_x.values[slot(ix(face.v[k]), j)];
    return q;
}

VecX FemModel::displacement_rate(std::size_t f) const {
    // q̇ = Ṗ − Q̇. Q is affine in (s_top, s_bot), which are linear in t: Q̇ = Q(s + rate) − Q(s).
    const mesh::Face& face = m_mesh.faces[face_id(f)];
    wedge::Nodes p_dot;
    for (std::size_t k = 0; k < 3; ++k) {
        const Vec3 s_dot = shift_rate(face.offset[k]);
        p_dot[k] = m_growth.velocity(m_mesh.positions[face.v[k]]) + s_dot;
        p_dot[k + 3] = m_xdot.values[slot(ix(face.v[k]))] + s_dot;
    }
    const double st = m_shrinkage.top(m_time), sb = m_shrinkage.bottom(m_time);
    VecX q(wedge::element_dofs(m_order));
    q.head<18>() = wedge::flatten(p_dot)
                   - (wedge::flatten(reference_nodes_at(f, st + m_shrinkage.top_rate, sb + m_shrinkage.bottom_rate))
                      - wedge::flatten(reference_nodes_at(f, st, sb)));
    for (int j = 1; j < m_order; ++j)
        for (std::size_t k = 0; k < 3; ++k)
            q.segment<3>(9 + 9 * j + 3 * static_cast<Eigen::Index>(k)) = m_xdot.values[slot(ix(face.v[k]), j)];
    return q;
}

void FemModel::push_vertex_slots() {
    for (int j = 0; j < m_order; ++j) {
        m_x.values.emplace_back(Vec3::Zero());
        m_xdot.values.emplace_back(Vec3::Zero());
    }
    for (Field* fd : {&m_x, &m_xdot})
        if (fd->residual_valid) {
            fd->residual.conservativeResize(fd->residual.size() + 3 * m_order);
            fd->residual.tail(3 * m_order).setZero();
        }
}

} // namespace crackle::sim
