#include "sim/fem_model.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/timer.hpp"
#include "mesh/cut.hpp"
#include "mesh/refine.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>

#include <limits>
#include <sstream>

namespace crackle::sim {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;
using mesh::vertex_id;
using mesh::VertexId;
using SpMatR = Eigen::SparseMatrix<double, Eigen::RowMajor>;

namespace {
/// An absolute floor for the residual: forces that move nodes by 1e-13 of an element.
double residual_floor(const SpMatR& K, const mesh::SurfaceMesh& mesh) {
    const double k_max = K.diagonal().cwiseAbs().maxCoeff();
    const double length =
        std::sqrt(mesh.total_area() / static_cast<double>(std::max<std::size_t>(mesh.num_faces(), 1)));
    return 1e-13 * k_max * length * std::sqrt(static_cast<double>(K.rows()));
}
} // namespace

// === Linear solvers

struct FemModel::Solver {
    SolverKind kind = SolverKind::Cg;
    Eigen::ConjugateGradient<SpMatR, Eigen::Lower | Eigen::Upper, Eigen::DiagonalPreconditioner<double>> cg;
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> cholmod;
    Eigen::SparseMatrix<double> lower; // CHOLMOD wants column-major lower storage
    bool analyzed = false;
    bool factorized = false;
    bool ready = false;         ///< update() has seen the current K (false in a fresh copy)
    bool pattern_dirty = false; ///< K's pattern changed since the last update()

    /// K changed: set up again before the next solve (lazily: local solves do not need it).
    void invalidate(bool pattern_changed) {
        ready = false;
        pattern_dirty = pattern_dirty || pattern_changed;
    }

    /// Called whenever K's values (or pattern) change.
    void update(const SpMatR& K, bool pattern_changed) {
        ready = true;
        if (kind == SolverKind::Cg) {
            cg.compute(K); // diagonal preconditioner: O(n)
            return;
        }
        if (pattern_changed) analyzed = false;
        factorized = false;
        lower = K.triangularView<Eigen::Lower>();
    }

    void factorize() {
        if (factorized) return;
        if (!analyzed) {
            cholmod.analyzePattern(lower);
            analyzed = true;
        }
        cholmod.factorize(lower);
        if (cholmod.info() != Eigen::Success)
            throw NumericError("sparse Cholesky factorization failed: the stiffness matrix is not positive definite");
        factorized = true;
    }
};

FemModel::SolverSlot::SolverSlot(SolverKind kind) : solver(std::make_unique<Solver>()) {
    solver->kind = kind;
}
FemModel::SolverSlot::SolverSlot(const SolverSlot& other) : SolverSlot(other.solver->kind) {}
FemModel::SolverSlot& FemModel::SolverSlot::operator=(const SolverSlot& other) {
    if (this != &other) {
        solver = std::make_unique<Solver>();
        solver->kind = other.solver->kind;
    }
    return *this;
}
FemModel::SolverSlot::SolverSlot(SolverSlot&& other) noexcept : SolverSlot(other.solver->kind) {}
FemModel::SolverSlot& FemModel::SolverSlot::operator=(SolverSlot&& other) noexcept {
    // The moved matrix lives at a new address: the solver must be set up again.
    if (this != &other) {
        solver = std::make_unique<Solver>();
        solver->kind = other.solver->kind;
    }
    return *this;
}
FemModel::SolverSlot::~SolverSlot() = default;

// === Trials (undoable changes)

struct FemModel::Trial {
    std::size_t faces = 0, vertices = 0;
    mesh::SurfaceMesh mesh;
    std::vector<Vec3> normal;
    std::vector<double> thickness, last_update;
    Field x, xdot;
    std::vector<std::size_t> updated;
    std::vector<std::vector<std::uint32_t>> incident;
    std::vector<int> alive_degree;
    std::vector<char> alive;
    std::size_t num_alive = 0;
    bool stiffness_dirty = false;
    // Recorded on first change: existing elements and matrix rows.
    std::vector<char> element_recorded;
    std::vector<std::pair<std::size_t, std::pair<ElementMaterial, Eigen::Matrix<double, 9, 18>>>> elements;
    std::vector<char> row_recorded;
    std::vector<std::pair<Eigen::Index, std::vector<std::pair<Eigen::Index, double>>>> rows;
};

FemModel::TrialSlot::TrialSlot() = default;
FemModel::TrialSlot::TrialSlot(const TrialSlot&) {}
FemModel::TrialSlot& FemModel::TrialSlot::operator=(const TrialSlot&) {
    active = false;
    return *this;
}
FemModel::TrialSlot::TrialSlot(TrialSlot&&) noexcept {}
FemModel::TrialSlot& FemModel::TrialSlot::operator=(TrialSlot&&) noexcept {
    active = false;
    return *this;
}
FemModel::TrialSlot::~TrialSlot() = default;

namespace {
/// Sets K(row, col) in an uncompressed matrix whose row has room. Eigen's own insert()
/// re-reserves every row (O(nnz)) whenever the storage has spare capacity, which geometric
/// growth always leaves; this never reallocates.
void set_entry(SpMatR& K, Eigen::Index row, Eigen::Index col, double value) {
    int* idx = K.innerIndexPtr();
    const int begin = K.outerIndexPtr()[row];
    const int end = begin + K.innerNonZeroPtr()[row];
    int* pos = std::lower_bound(idx + begin, idx + end, static_cast<int>(col));
    const auto p = static_cast<Eigen::Index>(pos - idx);
    if (pos != idx + end && *pos == col) {
        K.valuePtr()[p] = value;
        return;
    }
    CRACKLE_ASSERT(end < K.outerIndexPtr()[row + 1], "row " << row << " of K has no room (reserve first)");
    for (Eigen::Index q = end; q > p; --q) {
        idx[q] = idx[q - 1];
        K.valuePtr()[q] = K.valuePtr()[q - 1];
    }
    idx[p] = static_cast<int>(col);
    K.valuePtr()[p] = value;
    ++K.innerNonZeroPtr()[row];
}
} // namespace

void FemModel::begin_trial() {
    CRACKLE_ASSERT(!m_trial.active, "trials do not nest");
    if (!m_trial.trial) m_trial.trial = std::make_unique<Trial>();
    Trial& t = *m_trial.trial;
    // Copy-assigned into the same buffers every time: no allocation once they are big enough.
    t.faces = m_mesh.num_faces();
    t.vertices = m_mesh.num_vertices();
    t.mesh = m_mesh;
    t.normal = m_normal;
    t.thickness = m_thickness;
    t.last_update = m_last_update;
    t.x = m_x;
    t.xdot = m_xdot;
    t.updated = m_updated;
    t.incident = m_incident;
    t.alive_degree = m_alive_degree;
    t.alive = m_alive;
    t.num_alive = m_num_alive;
    t.stiffness_dirty = m_stiffness_dirty_for_x;
    t.element_recorded.assign(t.faces, 0);
    t.elements.clear();
    t.row_recorded.assign(static_cast<std::size_t>(m_K.rows()), 0);
    t.rows.clear();
    m_trial.active = true;
}

void FemModel::record_element(std::size_t f) {
    if (!m_trial.active) return;
    Trial& t = *m_trial.trial;
    if (f >= t.faces || t.element_recorded[f]) return;
    t.element_recorded[f] = 1;
    t.elements.push_back({f, {m_material[f], m_k_top[f]}});
}

void FemModel::record_row(Eigen::Index row) {
    if (!m_trial.active) return;
    Trial& t = *m_trial.trial;
    if (row >= static_cast<Eigen::Index>(t.row_recorded.size()) || t.row_recorded[static_cast<std::size_t>(row)])
        return;
    t.row_recorded[static_cast<std::size_t>(row)] = 1;
    std::vector<std::pair<Eigen::Index, double>> entries;
    for (SpMatR::InnerIterator it(m_K, row); it; ++it)
        entries.emplace_back(it.col(), it.value());
    t.rows.emplace_back(row, std::move(entries));
}

void FemModel::rollback() {
    CRACKLE_ASSERT(m_trial.active, "rollback() without begin_trial()");
    Trial& t = *m_trial.trial;
    m_mesh = t.mesh;
    m_normal = t.normal;
    m_thickness = t.thickness;
    m_last_update = t.last_update;
    m_x = t.x;
    m_xdot = t.xdot;
    m_updated = t.updated;
    m_incident = t.incident;
    m_alive_degree = t.alive_degree;
    m_alive = t.alive;
    m_num_alive = t.num_alive;
    m_stiffness_dirty_for_x = t.stiffness_dirty;
    m_material.resize(t.faces);
    m_k_top.resize(t.faces);
    for (const auto& [f, saved] : t.elements) {
        m_material[f] = saved.first;
        m_k_top[f] = saved.second;
    }
    // Recorded rows get their old values back; entries added since (the pattern only grows)
    // go to zero, and rows and columns of new vertices are cut off.
    for (const auto& [row, entries] : t.rows) {
        for (SpMatR::InnerIterator it(m_K, row); it; ++it)
            it.valueRef() = 0.0;
        for (const auto& [col, value] : entries)
            set_entry(m_K, row, col, value);
    }
    const auto n = static_cast<Eigen::Index>(3 * t.vertices);
    if (m_K.rows() > n) m_K.conservativeResize(n, n);
    m_solver->invalidate(true);
    m_trial.active = false;
}

void FemModel::commit() {
    CRACKLE_ASSERT(m_trial.active, "commit() without begin_trial()");
    m_trial.active = false;
}

// === Construction

FemModel::FemModel(mesh::SurfaceMesh mesh, const mesh::Surface& surface, const GrowthField& growth,
                   const ShrinkageOptions& shrinkage, const LayerFields& fields, const FemOptions& options)
    : m_mesh(std::move(mesh)), m_surface(surface), m_growth(growth), m_shrinkage(shrinkage), m_fields(fields),
      m_options(options), m_solver(options.solver) {
    CRACKLE_ASSERT(
        (fields.thickness || fields.vertex_thickness)
            && ((fields.young_modulus && fields.threshold_stress && fields.toughness) || fields.face_material),
        "every layer field must be given");
    const std::size_t nv = m_mesh.num_vertices(), nf = m_mesh.num_faces();
    m_normal.resize(nv);
    m_thickness.resize(nv);
    m_x.values.resize(nv);
    m_xdot.values.assign(nv, Vec3::Zero());
    m_last_update.assign(nv, 0.0);
    for (std::size_t v = 0; v < nv; ++v)
        init_vertex(v);
    m_alive.assign(nf, 1);
    m_num_alive = nf;
    m_material.resize(nf);
    m_k_top.resize(nf);
    for (std::size_t f = 0; f < nf; ++f)
        init_element(f);
    rebuild_incidence();
    assemble();
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
    m_x.values[v] = rest_top(p, m_normal[v], m_thickness[v]);
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
    if (m_fields.face_material) {
        mat = (*m_fields.face_material)[f];
        build_element_stiffness(f);
        return;
    }
    mat.young_modulus = m_fields.young_modulus->face_average(m_mesh, id, m_surface);
    mat.threshold_stress = m_fields.threshold_stress->face_average(m_mesh, id, m_surface);
    mat.toughness = m_fields.toughness->face_average(m_mesh, id, m_surface);
    build_element_stiffness(f);
}

void FemModel::build_element_stiffness(std::size_t f) {
    const wedge::Nodes q = reference_nodes_at(f, m_stiffness_s_top, m_stiffness_s_bot);
    const wedge::Mat18 K = wedge::stiffness(q, m_material[f].young_modulus, m_fields.poisson_ratio);
    m_k_top[f] = K.bottomRows<9>();
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

void FemModel::rebuild_incidence() {
    const std::size_t nv = m_mesh.num_vertices();
    m_incident.assign(nv, {});
    m_alive_degree.assign(nv, 0);
    for (std::size_t f = 0; f < m_mesh.num_faces(); ++f) {
        const mesh::Face& face = m_mesh.faces[face_id(f)];
        for (std::size_t k = 0; k < 3; ++k) {
            auto& list = m_incident[ix(face.v[k])];
            if (list.empty() || list.back() != f) list.push_back(static_cast<std::uint32_t>(f));
            if (m_alive[f]) ++m_alive_degree[ix(face.v[k])];
        }
    }
}

// === Assembly (§5.4, Alg. 4, with the bottom DOFs eliminated)

SpMatR FemModel::assemble_from_scratch() const {
    const auto n = static_cast<Eigen::Index>(3 * m_mesh.num_vertices());
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(81 * m_mesh.num_faces() + 3 * m_mesh.num_vertices());
    for (std::size_t f = 0; f < m_mesh.num_faces(); ++f) {
        const mesh::Face& face = m_mesh.faces[face_id(f)];
        const bool on = m_alive[f] != 0;
        for (std::size_t a = 0; a < 3; ++a)
            for (std::size_t b = 0; b < 3; ++b) {
                const auto ra = static_cast<Eigen::Index>(3 * ix(face.v[a]));
                const auto cb = static_cast<Eigen::Index>(3 * ix(face.v[b]));
                for (int i = 0; i < 3; ++i)
                    for (int j = 0; j < 3; ++j)
                        // Dead elements keep their (zero) entries so the pattern never shrinks.
                        triplets.emplace_back(ra + i, cb + j,
                                              on ? m_k_top[f](static_cast<Eigen::Index>(3 * a) + i,
                                                              9 + static_cast<Eigen::Index>(3 * b) + j)
                                                 : 0.0);
            }
    }
    // A top node with no element left keeps its place: identity rows, zero right-hand side.
    for (std::size_t v = 0; v < m_mesh.num_vertices(); ++v)
        if (m_alive_degree[v] == 0)
            for (int i = 0; i < 3; ++i)
                triplets.emplace_back(static_cast<Eigen::Index>(3 * v) + i, static_cast<Eigen::Index>(3 * v) + i, 1.0);
    SpMatR K(n, n);
    K.setFromTriplets(triplets.begin(), triplets.end());
    return K;
}

void FemModel::assemble() {
    m_K = assemble_from_scratch();
    // Room for three more neighbours per row: splitting and cutting add entries locally.
    m_K.reserve(Eigen::VectorXi::Constant(m_K.outerSize(), 27));
    m_stiffness_dirty_for_x = true;
    m_residual_floor = residual_floor(m_K, m_mesh);
    // Below ~60k unknowns a parallel mat-vec costs more in thread hand-offs than it saves
    // (measured: half the CG time went to libgomp's spin-wait at 6k unknowns).
    Eigen::setNbThreads(m_K.rows() < 60000 ? 1 : 0);
}

void FemModel::refresh_incidence(const std::vector<FaceId>& faces, const std::vector<std::size_t>& vertices) {
    const std::size_t nv = m_mesh.num_vertices();
    m_incident.resize(nv);
    m_alive_degree.resize(nv, 0);
    auto has = [&](std::uint32_t f, std::size_t v) {
        for (VertexId w : m_mesh.faces[face_id(f)].v)
            if (ix(w) == v) return true;
        return false;
    };
    for (std::size_t v : vertices) {
        auto& list = m_incident[v];
        list.erase(std::remove_if(list.begin(), list.end(), [&](std::uint32_t f) { return !has(f, v); }), list.end());
    }
    for (FaceId f : faces)
        for (VertexId w : m_mesh.faces[f].v) {
            auto& list = m_incident[ix(w)];
            if (std::find(list.begin(), list.end(), static_cast<std::uint32_t>(ix(f))) == list.end())
                list.push_back(static_cast<std::uint32_t>(ix(f)));
        }
    for (FaceId f : faces)
        for (VertexId w : m_mesh.faces[f].v) {
            int degree = 0;
            for (std::uint32_t g : m_incident[ix(w)])
                degree += m_alive[g] != 0;
            m_alive_degree[ix(w)] = degree;
        }
    for (std::size_t v : vertices) {
        int degree = 0;
        for (std::uint32_t g : m_incident[v])
            degree += m_alive[g] != 0;
        m_alive_degree[v] = degree;
    }
}

void FemModel::reassemble_around(const std::vector<std::size_t>& vertices) {
    // The rows (and, by symmetry, columns) of these vertices are rebuilt from their current
    // elements (Alg. 7 generalised): exact, O(changed), no full assembly. The pattern only grows.
    grow_rows(static_cast<Eigen::Index>(3 * m_mesh.num_vertices()));
    // The new blocks: (a, b, K_ab) summed over the faces a and b share.
    struct Block {
        std::size_t a, b;
        Mat3 K;
    };
    std::vector<Block> blocks;
    for (std::size_t a : vertices) {
        const std::size_t first = blocks.size();
        for (std::uint32_t f : m_incident[a]) {
            if (!m_alive[f]) continue;
            const mesh::Face& face = m_mesh.faces[face_id(f)];
            std::size_t ka = 3;
            for (std::size_t k = 0; k < 3; ++k)
                if (ix(face.v[k]) == a) ka = k;
            for (std::size_t kb = 0; kb < 3; ++kb) {
                const std::size_t b = ix(face.v[kb]);
                const Mat3 K =
                    m_k_top[f].block<3, 3>(static_cast<Eigen::Index>(3 * ka), 9 + static_cast<Eigen::Index>(3 * kb));
                auto it = std::find_if(blocks.begin() + static_cast<std::ptrdiff_t>(first), blocks.end(),
                                       [&](const Block& e) { return e.b == b; });
                if (it == blocks.end())
                    blocks.push_back({a, b, K});
                else
                    it->K += K;
            }
        }
        if (m_alive_degree[a] == 0) blocks.push_back({a, a, Mat3::Identity()});
    }
    // Make room first, in one move: Eigen's one-at-a-time insertion reallocates everything.
    // The matrix stays uncompressed with slack in every row, so most changes fit where they
    // are; a short row moves the rows after it (O(nnz)), so it gets generous slack.
    {
        constexpr int slack = 18;          // six new neighbour vertices
        std::vector<Eigen::Index> missing; // rows, one entry per missing 3-column block
        auto has = [&](Eigen::Index row, Eigen::Index col) {
            for (SpMatR::InnerIterator it(m_K, row); it; ++it)
                if (it.col() == col) return true;
            return false;
        };
        for (const Block& bl : blocks)
            for (int i = 0; i < 3; ++i) {
                const auto ra = static_cast<Eigen::Index>(3 * bl.a) + i, rb = static_cast<Eigen::Index>(3 * bl.b) + i;
                if (!has(ra, static_cast<Eigen::Index>(3 * bl.b))) missing.push_back(ra);
                if (!has(rb, static_cast<Eigen::Index>(3 * bl.a))) missing.push_back(rb);
            }
        std::sort(missing.begin(), missing.end());
        bool short_of_room = false;
        for (std::size_t i = 0; i < missing.size() && !short_of_room;) {
            std::size_t j = i;
            while (j < missing.size() && missing[j] == missing[i])
                ++j;
            const Eigen::Index r = missing[i];
            const Eigen::Index room = m_K.outerIndexPtr()[r + 1] - m_K.outerIndexPtr()[r] - m_K.innerNonZeroPtr()[r];
            short_of_room = static_cast<Eigen::Index>(3 * (j - i)) > room;
            i = j;
        }
        if (short_of_room) {
            Eigen::VectorXi need = Eigen::VectorXi::Zero(m_K.outerSize());
            for (Eigen::Index r : missing)
                need[r] += 3;
            for (Eigen::Index r = 0; r < need.size(); ++r)
                if (need[r] > 0) need[r] += slack;
            // Grow the storage geometrically, and only when it is full.
            if (m_K.data().size() + need.sum() > m_K.data().allocatedSize())
                m_K.data().reserve(std::max<Eigen::Index>(need.sum(), m_K.data().size() / 2));
            m_K.reserve(need);
        }
    }
    if (m_trial.active) {
        // Every row this touches: the vertices' own, their old and new neighbours'.
        for (std::size_t a : vertices)
            for (int i = 0; i < 3; ++i) {
                const auto row = static_cast<Eigen::Index>(3 * a) + i;
                if (row >= m_K.rows()) continue;
                record_row(row);
                for (SpMatR::InnerIterator it(m_K, row); it; ++it)
                    record_row(it.col());
            }
        for (const Block& bl : blocks)
            for (int i = 0; i < 3; ++i) {
                record_row(static_cast<Eigen::Index>(3 * bl.a) + i);
                record_row(static_cast<Eigen::Index>(3 * bl.b) + i);
            }
    }
    for (std::size_t a : vertices)
        for (int i = 0; i < 3; ++i) {
            const auto row = static_cast<Eigen::Index>(3 * a) + i;
            for (SpMatR::InnerIterator it(m_K, row); it; ++it) {
                it.valueRef() = 0.0;
                set_entry(m_K, it.col(), row, 0.0);
            }
        }
    for (const Block& bl : blocks) {
        set_block(bl.a, bl.b, bl.K);
        set_block(bl.b, bl.a, bl.K.transpose());
    }
    m_stiffness_dirty_for_x = true;
    m_solver->invalidate(true);
}

void FemModel::update_around(const std::vector<std::size_t>& vertices) {
    reassemble_around(vertices);
    recompute_residual_at(Unknown::Position, vertices);
    recompute_residual_at(Unknown::Rate, vertices);
    m_x.load_norm = m_xdot.load_norm = -1;
}

void FemModel::grow_rows(Eigen::Index n) {
    constexpr int slack = 18, room = 36; // per old row, per new row (12 neighbour vertices)
    if (m_K.isCompressed()) m_K.reserve(Eigen::VectorXi::Constant(m_K.outerSize(), slack));
    const Eigen::Index old = m_K.rows();
    if (old >= n) return;
    m_K.conservativeResize(n, n);
    // New rows come last: give them room at the end of the storage by hand (Eigen's reserve
    // would walk every row), growing the storage geometrically.
    int* outer = m_K.outerIndexPtr();
    const Eigen::Index base = outer[old], add = (n - old) * room;
    if (base + add > m_K.data().allocatedSize())
        m_K.data().reserve(std::max<Eigen::Index>(base + add - m_K.data().size(), m_K.data().size() / 2));
    m_K.data().resize(base + add);
    for (Eigen::Index r = old; r <= n; ++r) {
        outer[r] = static_cast<int>(base + (r - old) * room);
        if (r < n) m_K.innerNonZeroPtr()[r] = 0;
    }
}

void FemModel::set_block(std::size_t a, std::size_t b, const Mat3& block) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            set_entry(m_K, static_cast<Eigen::Index>(3 * a) + i, static_cast<Eigen::Index>(3 * b) + j, block(i, j));
}

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
        if (m_alive_degree[v] > 0) m_x.values[v] += dt * m_xdot.values[v];
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
        if (m_alive_degree[v] > 0) m_x.values[v] += dt * m_xdot.values[v];
}

// === Positions

Vec3 FemModel::bottom_position(VertexId v) const {
    return m_growth.position(m_mesh.positions[v], m_time);
}

wedge::Nodes FemModel::current_nodes(FaceId f) const {
    const mesh::Face& face = m_mesh.faces[f];
    wedge::Nodes p;
    for (std::size_t k = 0; k < 3; ++k) {
        const Vec3 s = shift(face.offset[k], m_time);
        p[k] = m_growth.position(m_mesh.positions[face.v[k]], m_time) + s;
        p[k + 3] = m_x.values[ix(face.v[k])] + s;
    }
    return p;
}

wedge::Nodes FemModel::reference_nodes(FaceId f) const {
    return reference_nodes_at(ix(f), m_shrinkage.top(m_time), m_shrinkage.bottom(m_time));
}

wedge::Vec18 FemModel::displacement(std::size_t f) const {
    // q = P − Q, differences of nearby positions: accurate to round-off of the positions.
    return wedge::flatten(current_nodes(face_id(f))) - wedge::flatten(reference_nodes(face_id(f)));
}

wedge::Vec18 FemModel::displacement_rate(std::size_t f) const {
    // q̇ = Ṗ − Q̇. Q is affine in (s_top, s_bot), which are linear in t: Q̇ = Q(s + rate) − Q(s).
    const mesh::Face& face = m_mesh.faces[face_id(f)];
    wedge::Nodes p_dot;
    for (std::size_t k = 0; k < 3; ++k) {
        const Vec3 s_dot = shift_rate(face.offset[k]);
        p_dot[k] = m_growth.velocity(m_mesh.positions[face.v[k]]) + s_dot;
        p_dot[k + 3] = m_xdot.values[ix(face.v[k])] + s_dot;
    }
    const double st = m_shrinkage.top(m_time), sb = m_shrinkage.bottom(m_time);
    return wedge::flatten(p_dot)
           - (wedge::flatten(reference_nodes_at(f, st + m_shrinkage.top_rate, sb + m_shrinkage.bottom_rate))
              - wedge::flatten(reference_nodes_at(f, st, sb)));
}

// === Residuals

Eigen::Matrix<double, 9, 1> FemModel::element_force(std::size_t f, Unknown u) const {
    return m_k_top[f] * (u == Unknown::Position ? displacement(f) : displacement_rate(f));
}

Eigen::VectorXd FemModel::full_residual(Unknown u) const {
    // r = b − K x = −Σ_e (K_e q_e)_top over the alive elements
    Eigen::VectorXd r = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(3 * m_mesh.num_vertices()));
    for (std::size_t f = 0; f < m_mesh.num_faces(); ++f) {
        if (!m_alive[f]) continue;
        const Eigen::Matrix<double, 9, 1> force = element_force(f, u);
        const mesh::Face& face = m_mesh.faces[face_id(f)];
        for (std::size_t k = 0; k < 3; ++k)
            r.segment<3>(static_cast<Eigen::Index>(3 * ix(face.v[k]))) -=
                force.segment<3>(static_cast<Eigen::Index>(3 * k));
    }
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
        fd.residual.segment<3>(static_cast<Eigen::Index>(3 * v)).setZero();
    }
    std::vector<std::uint32_t> faces;
    for (std::size_t v : vertices)
        for (std::uint32_t f : m_incident[v])
            if (m_alive[f]) faces.push_back(f);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    for (std::uint32_t f : faces) {
        const Eigen::Matrix<double, 9, 1> force = element_force(f, u);
        const mesh::Face& face = m_mesh.faces[face_id(f)];
        for (std::size_t k = 0; k < 3; ++k)
            if (mark[ix(face.v[k])])
                fd.residual.segment<3>(static_cast<Eigen::Index>(3 * ix(face.v[k]))) -=
                    force.segment<3>(static_cast<Eigen::Index>(3 * k));
    }
}

double FemModel::load_norm(Unknown u) {
    Field& fd = field(u);
    if (fd.load_norm >= 0) return fd.load_norm;
    // The residual with every top node at rest above its bottom node (positions), or with
    // ẋ = 0 (rates): the size of the loads that growth and shrinkage create.
    Eigen::VectorXd r = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(3 * m_mesh.num_vertices()));
    const double s_bar = 0.5 * (m_shrinkage.top(m_time) + m_shrinkage.bottom(m_time));
    for (std::size_t f = 0; f < m_mesh.num_faces(); ++f) {
        if (!m_alive[f]) continue;
        const FaceId id = face_id(f);
        const mesh::Face& face = m_mesh.faces[id];
        wedge::Vec18 q;
        if (u == Unknown::Position) {
            wedge::Nodes p = current_nodes(id);
            for (std::size_t k = 0; k < 3; ++k)
                p[k + 3] = p[k] + (1.0 - s_bar) * m_thickness[ix(face.v[k])] * m_normal[ix(face.v[k])];
            q = wedge::flatten(p) - wedge::flatten(reference_nodes(id));
        } else {
            q = displacement_rate(f);
            for (std::size_t k = 0; k < 3; ++k)
                q.segment<3>(static_cast<Eigen::Index>(9 + 3 * k)) -= m_xdot.values[ix(face.v[k])];
        }
        const Eigen::Matrix<double, 9, 1> force = m_k_top[f] * q;
        for (std::size_t k = 0; k < 3; ++k)
            r.segment<3>(static_cast<Eigen::Index>(3 * ix(face.v[k]))) -=
                force.segment<3>(static_cast<Eigen::Index>(3 * k));
    }
    fd.load_norm = r.norm();
    return fd.load_norm;
}

double FemModel::max_residual_force() {
    return max_residual(Unknown::Position);
}

double FemModel::max_rate_residual_force() {
    return max_residual(Unknown::Rate);
}

double FemModel::max_residual(Unknown u) {
    ensure_residual(u);
    const Field& fd = field(u);
    double worst = 0;
    for (std::size_t v = 0; v < m_mesh.num_vertices(); ++v)
        worst = std::max(worst, fd.residual.segment<3>(static_cast<Eigen::Index>(3 * v)).squaredNorm());
    return std::sqrt(worst);
}

// === Equilibrium

SolveStats FemModel::solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x, double abs_tolerance) {
    Timer timer;
    SolveStats stats;
    const double rhs_norm = rhs.norm();
    x.setZero(rhs.size());
    if (rhs_norm <= abs_tolerance) {
        stats.seconds = timer.seconds();
        return stats;
    }
    if (!m_solver->ready) {
        m_solver->update(m_K, m_solver->pattern_dirty);
        m_solver->pattern_dirty = false;
    }
    if (m_solver->kind == SolverKind::Direct) {
        m_solver->factorize();
        x = m_solver->cholmod.solve(rhs);
        stats.iterations = 1;
        stats.residual = (rhs - m_K * x).norm() / rhs_norm;
    } else {
        auto& cg = m_solver->cg;
        cg.setTolerance(abs_tolerance / rhs_norm);
        cg.setMaxIterations(m_options.max_iterations);
        x = cg.solveWithGuess(rhs, x);
        stats.iterations = static_cast<int>(cg.iterations());
        stats.residual = cg.error();
        if (cg.info() != Eigen::Success) {
            std::ostringstream os;
            os << "conjugate gradient did not converge: " << cg.iterations() << " iterations, residual " << cg.error()
               << " of the right-hand side (wanted " << abs_tolerance / rhs_norm << ") at t = " << m_time
               << "; raise simulation.solver_max_iterations or use simulation.solver = \"direct\"";
            throw NumericError(os.str());
        }
    }
    if (!x.allFinite())
        throw NumericError("the equilibrium solve produced NaN or infinity at t = " + std::to_string(m_time));
    stats.seconds = timer.seconds();
    return stats;
}

SolveStats FemModel::relax_field(Unknown u) {
    Field& fd = field(u);
    ensure_residual(u);
    const double tol = std::max(m_options.tolerance * load_norm(u), m_residual_floor);
    Eigen::VectorXd dx;
    SolveStats stats = solve(fd.residual, dx, tol);
    if (stats.iterations > 0) stats.energy_release = 0.5 * fd.residual.dot(dx);
    const std::size_t nv = m_mesh.num_vertices();
    m_updated.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        const Vec3 d = dx.segment<3>(static_cast<Eigen::Index>(3 * v));
        fd.values[v] += d;
        m_last_update[v] = d.norm();
        m_updated[v] = v;
    }
    stats.nodes = nv;
    // The new residual without touching the elements: r − K·Δx.
    if (stats.iterations > 0) fd.residual.noalias() -= m_K * dx;
    return stats;
}

SolveStats FemModel::relax() {
    SolveStats s = relax_field(Unknown::Position);
    m_stiffness_dirty_for_x = false;
    return s;
}

SolveStats FemModel::solve_rate() {
    return relax_field(Unknown::Rate);
}

SolveStats FemModel::relax_local(const std::vector<std::size_t>& seeds, double& radius,
                                 const LocalRelaxOptions& options) {
    SolveStats s = relax_field_local(Unknown::Position, seeds, radius, options);
    m_stiffness_dirty_for_x = false;
    return s;
}

SolveStats FemModel::relax_rate_local(const std::vector<std::size_t>& seeds, double& radius,
                                      const LocalRelaxOptions& options) {
    return relax_field_local(Unknown::Rate, seeds, radius, options);
}

SolveStats FemModel::relax_field_local(Unknown u, const std::vector<std::size_t>& seeds, double& radius,
                                       const LocalRelaxOptions& options) {
    Timer timer;
    Field& fd = field(u);
    ensure_residual(u);
    const std::size_t nv = m_mesh.num_vertices();
    auto force = [&](std::size_t v) { return fd.residual.segment<3>(static_cast<Eigen::Index>(3 * v)).norm(); };
    double change = 0;
    for (std::size_t v : seeds)
        change = std::max(change, force(v));
    // Forces below `tolerance` of a threshold-level nodal force (threshold × thickness × edge)
    // do not matter for cracking; per unit time for rates, with the run's time scale 1.
    const double floor =
        std::max(m_options.tolerance * m_force_scale, m_residual_floor / std::sqrt(static_cast<double>(nv)));
    const double tol = std::max(options.tolerance * change, floor);

    SolveStats stats;
    for (std::size_t v : m_updated)
        m_last_update[v] = 0.0;
    m_updated.clear();
    if (change <= tol) {
        stats.seconds = timer.seconds();
        return stats;
    }
    constexpr double MAX_RADIUS = 256.0; // hops; beyond this the global solve is cheaper anyway
    radius = std::clamp(radius, static_cast<double>(options.min_radius), MAX_RADIUS);
    const double start_radius = radius;
    std::vector<std::size_t> sources = seeds;
    // Scratch marks, kept between calls and reset only where used: O(local) per call.
    std::vector<int>& hop = m_scratch_hop;
    std::vector<int>& local_index = m_scratch_index;
    std::vector<char>& touched = m_scratch_touched;
    std::vector<Vec3>& pushed = m_scratch_pushed;
    hop.resize(nv, -1);
    local_index.resize(nv, -1);
    touched.resize(nv, 0);
    bool first_try = true;

    while (true) {
        // === The set: a breadth-first ball along intact elements (crack-aware distance)
        std::vector<std::size_t> set;
        for (std::size_t v : sources)
            if (hop[v] < 0 && m_alive_degree[v] > 0) {
                hop[v] = 0;
                set.push_back(v);
            }
        const int max_hop = static_cast<int>(std::lround(radius));
        for (std::size_t head = 0; head < set.size(); ++head) {
            const std::size_t v = set[head];
            if (hop[v] >= max_hop) continue;
            for (std::uint32_t f : m_incident[v]) {
                if (!m_alive[f]) continue;
                for (VertexId w : m_mesh.faces[face_id(f)].v)
                    if (hop[ix(w)] < 0) {
                        hop[ix(w)] = hop[v] + 1;
                        set.push_back(ix(w));
                    }
            }
        }
        if (static_cast<double>(set.size()) > options.max_fraction * static_cast<double>(nv)) {
            log::debug("local ", u == Unknown::Position ? "x" : "v", " fallback: ", set.size(), " nodes at radius ",
                       radius, " from ", sources.size(), " sources");
            for (std::size_t v : set)
                hop[v] = -1;
            for (std::size_t v : m_updated)
                touched[v] = 0;
            SolveStats global = relax_field(u);
            global.fell_back = true;
            global.seconds = timer.seconds();
            radius = start_radius; // this change was unusual; the next starts where this one did
            return global;
        }

        // === K_SS Δ = r_S with the rest held (the thesis' elimination method, §5.5)
        const auto m = static_cast<Eigen::Index>(3 * set.size());
        for (std::size_t i = 0; i < set.size(); ++i)
            local_index[set[i]] = static_cast<int>(i);
        std::vector<Eigen::Triplet<double>> triplets;
        triplets.reserve(static_cast<std::size_t>(m) * 21);
        Eigen::VectorXd rhs(m);
        for (std::size_t i = 0; i < set.size(); ++i) {
            const std::size_t v = set[i];
            rhs.segment<3>(static_cast<Eigen::Index>(3 * i)) = fd.residual.segment<3>(static_cast<Eigen::Index>(3 * v));
            for (int d = 0; d < 3; ++d) {
                const auto row = static_cast<Eigen::Index>(3 * v) + d;
                for (SpMatR::InnerIterator it(m_K, row); it; ++it) {
                    const int lj = local_index[static_cast<std::size_t>(it.col() / 3)];
                    if (lj >= 0)
                        triplets.emplace_back(static_cast<Eigen::Index>(3 * i) + d,
                                              static_cast<Eigen::Index>(3 * lj) + it.col() % 3, it.value());
                }
            }
        }
        Eigen::SparseMatrix<double> Kss(m, m);
        Kss.setFromTriplets(triplets.begin(), triplets.end());
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Kss);
        if (ldlt.info() != Eigen::Success) throw NumericError("local stiffness matrix is not positive definite");
        const Eigen::VectorXd dx = ldlt.solve(rhs);
        stats.iterations += 1;
        stats.energy_release += 0.5 * rhs.dot(dx);
        stats.nodes = std::max(stats.nodes, set.size());

        // === Apply: x_S += Δ; r −= K[:, S] Δ (K symmetric: walk the rows of S). The force
        // this pushes onto the nodes just outside the set is what is left to resolve.
        std::vector<std::size_t> outside;
        for (std::size_t i = 0; i < set.size(); ++i) {
            const std::size_t v = set[i];
            const Vec3 d = dx.segment<3>(static_cast<Eigen::Index>(3 * i));
            fd.values[v] += d;
            m_last_update[v] += d.norm();
            if (!touched[v]) {
                touched[v] = 1;
                m_updated.push_back(v);
            }
            for (int c = 0; c < 3; ++c) {
                const auto row = static_cast<Eigen::Index>(3 * v) + c;
                for (SpMatR::InnerIterator it(m_K, row); it; ++it) {
                    const auto w = static_cast<std::size_t>(it.col() / 3);
                    fd.residual[it.col()] -= it.value() * d[c];
                    if (local_index[w] < 0) {
                        if (pushed.size() < nv) pushed.resize(nv, Vec3::Zero());
                        if (pushed[w] == Vec3::Zero()) outside.push_back(w);
                        pushed[w][it.col() % 3] -= it.value() * d[c];
                    }
                }
            }
        }
        for (std::size_t v : set)
            local_index[v] = -1;

        // === Radius control (§5.8.3): grow while the pushed-out forces are not negligible
        // next to the change (the thesis checks the residual; forces left over from earlier
        // events are not this change's to resolve).
        std::vector<std::size_t> unresolved;
        for (std::size_t w : outside) {
            if (m_alive_degree[w] > 0 && pushed[w].norm() > tol) unresolved.push_back(w);
            pushed[w] = Vec3::Zero();
        }
        for (std::size_t v : set)
            hop[v] = -1;
        log::debug("local ", u == Unknown::Position ? "x" : "v", " round ", stats.iterations, ": ", set.size(),
                   " nodes, radius ", radius, ", ", unresolved.size(), " unresolved");
        if (unresolved.empty()) {
            if (first_try) radius = std::max(static_cast<double>(options.min_radius), 0.9 * radius);
            break;
        }
        first_try = false;
        radius = std::min(1.5 * radius, MAX_RADIUS);
        std::sort(unresolved.begin(), unresolved.end());
        unresolved.erase(std::unique(unresolved.begin(), unresolved.end()), unresolved.end());
        sources = seeds;
        sources.insert(sources.end(), unresolved.begin(), unresolved.end());
    }
    for (std::size_t v : m_updated)
        touched[v] = 0;
    stats.residual = tol / std::max(change, 1e-300);
    stats.seconds = timer.seconds();
    return stats;
}

// === Stress

TopStress FemModel::top_stress(FaceId f) const {
    const std::size_t fi = ix(f);
    // B from the reference shape the stiffness was built with, so σ is consistent with K.
    const wedge::Nodes ref = reference_nodes_at(fi, m_stiffness_s_top, m_stiffness_s_bot);
    const wedge::Mat6 D = wedge::elasticity(m_material[fi].young_modulus, m_fields.poisson_ratio);
    const wedge::Vec18 q = displacement(fi);
    TopStress s;
    for (std::size_t k = 0; k < 3; ++k) {
        const auto& g = wedge::quadrature()[static_cast<std::size_t>(wedge::TOP_GAUSS_POINTS[k])];
        s[k] = wedge::stress(ref, D, q, g.xi, g.eta, g.zeta);
    }
    return s;
}

TopStress FemModel::top_stress_rate(FaceId f) const {
    const std::size_t fi = ix(f);
    const wedge::Nodes ref = reference_nodes_at(fi, m_stiffness_s_top, m_stiffness_s_bot);
    const wedge::Mat6 D = wedge::elasticity(m_material[fi].young_modulus, m_fields.poisson_ratio);
    const wedge::Vec18 q_dot = displacement_rate(fi);
    TopStress s;
    for (std::size_t k = 0; k < 3; ++k) {
        const auto& g = wedge::quadrature()[static_cast<std::size_t>(wedge::TOP_GAUSS_POINTS[k])];
        s[k] = wedge::stress(ref, D, q_dot, g.xi, g.eta, g.zeta);
    }
    return s;
}

double FemModel::stress_ratio(FaceId f) const {
    double best = -std::numeric_limits<double>::infinity();
    for (const wedge::Vec6& s : top_stress(f))
        best = std::max(best, wedge::max_principal(s).value);
    return best / m_material[ix(f)].threshold_stress;
}

double FemModel::strain_energy() const {
    double e = 0;
    for (std::size_t f = 0; f < m_mesh.num_faces(); ++f) {
        if (!m_alive[f]) continue;
        const wedge::Nodes ref = reference_nodes_at(f, m_stiffness_s_top, m_stiffness_s_bot);
        const wedge::Vec18 q = displacement(f);
        e += 0.5 * q.dot(wedge::stiffness(ref, m_material[f].young_modulus, m_fields.poisson_ratio) * q);
    }
    return e;
}

double FemModel::strain_energy(const std::vector<FaceId>& faces) const {
    double e = 0;
    for (FaceId f : faces) {
        const std::size_t fi = ix(f);
        if (!m_alive[fi]) continue;
        const wedge::Nodes ref = reference_nodes_at(fi, m_stiffness_s_top, m_stiffness_s_bot);
        const wedge::Vec18 q = displacement(fi);
        e += 0.5 * q.dot(wedge::stiffness(ref, m_material[fi].young_modulus, m_fields.poisson_ratio) * q);
    }
    return e;
}

// === Topology

void FemModel::remove_element(FaceId f) {
    const std::size_t fi = ix(f);
    CRACKLE_ASSERT(m_alive[fi], "element " << fi << " is already removed");
    const mesh::Face& face = m_mesh.faces[f];
    // The element's forces leave the sums r = −Σ_alive f_e, for positions and rates alike.
    for (Unknown u : {Unknown::Position, Unknown::Rate}) {
        Field& fd = field(u);
        if (!fd.residual_valid) continue;
        const Eigen::Matrix<double, 9, 1> force = element_force(fi, u);
        for (std::size_t k = 0; k < 3; ++k)
            fd.residual.segment<3>(static_cast<Eigen::Index>(3 * ix(face.v[k]))) +=
                force.segment<3>(static_cast<Eigen::Index>(3 * k));
    }
    m_alive[fi] = 0;
    --m_num_alive;
    for (VertexId v : face.v) {
        // A node left without elements feels no force: it stays where it is.
        if (--m_alive_degree[ix(v)] == 0)
            for (Field* fd : {&m_x, &m_xdot})
                if (fd->residual_valid) fd->residual.segment<3>(static_cast<Eigen::Index>(3 * ix(v))).setZero();
    }
    // Alg. 7: every block (a, b) between nodes of the removed element is rebuilt from the
    // alive elements that still share both nodes: exact, no subtraction round-off (F12).
    for (std::size_t a = 0; a < 3; ++a)
        for (std::size_t b = 0; b < 3; ++b) {
            const std::size_t va = ix(face.v[a]), vb = ix(face.v[b]);
            Mat3 block = Mat3::Zero();
            for (std::uint32_t g : m_incident[va]) {
                if (!m_alive[g]) continue;
                const mesh::Face& other = m_mesh.faces[face_id(g)];
                for (std::size_t i = 0; i < 3; ++i)
                    for (std::size_t j = 0; j < 3; ++j)
                        if (ix(other.v[i]) == va && ix(other.v[j]) == vb)
                            block += m_k_top[g].block<3, 3>(static_cast<Eigen::Index>(3 * i),
                                                            9 + static_cast<Eigen::Index>(3 * j));
            }
            if (va == vb && m_alive_degree[va] == 0) block = Mat3::Identity();
            set_block(va, vb, block);
        }
    m_solver->invalidate(false);
    m_stiffness_dirty_for_x = true;
}

double FemModel::element_size(FaceId f) const {
    const auto p = m_mesh.face_positions(f);
    return std::max({(p[1] - p[0]).norm(), (p[2] - p[1]).norm(), (p[0] - p[2]).norm()});
}

mesh::NewVertex FemModel::point_on_edge(const mesh::SurfaceMesh& m, FaceId face, int edge, double t, NewNode& node,
                                        const std::vector<NewNode>* pending) const {
    Vec3 bary = Vec3::Zero();
    bary[edge] = 1 - t;
    bary[(edge + 1) % 3] = t;
    return point_in_face(m, face, bary, node, pending);
}

mesh::NewVertex FemModel::point_in_face(const mesh::SurfaceMesh& m, FaceId face, const Vec3& bary, NewNode& node,
                                        const std::vector<NewNode>* pending) const {
    const mesh::Face& fc = m.faces[face];
    mesh::NewVertex nv;
    if (m.periodic) {
        // In the unrolled domain, mapped onto the surface.
        Vec2 d = Vec2::Zero();
        for (int k = 0; k < 3; ++k)
            d += bary[k] * m.corner_domain(face, k);
        nv.domain = Vec2(wrap(d.x(), m.period.x()), wrap(d.y(), m.period.y()));
        nv.position = m_surface.position(nv.domain);
    } else {
        Vec3 p = Vec3::Zero();
        for (int k = 0; k < 3; ++k)
            p += bary[k] * m.corner_position(face, k);
        nv.position = m_surface.project(p);
    }
    // The top node and its rate: the corners' displacements from rest are interpolated, not
    // their positions. On a curved surface the chord between two top nodes runs inside the
    // layer by (R + h)·θ²/8, and a resampled thickness differs from the interpolated one:
    // either would give the new node a misfit that relaxing releases as if a crack had.
    // (Displacements do not depend on the periodic frame: a shift moves a node and its rest
    // alike.)
    node.thickness = m_fields.vertex_thickness ? 0.0 : thickness_at(nv.position, nv.domain);
    node.normal = m_surface.normal(nv.position);
    node.top = rest_top(nv.position, node.normal, node.thickness);
    node.rate = rest_top_rate(nv.position, node.normal, node.thickness);
    const std::size_t adopted = m_normal.size();
    for (std::size_t k = 0; k < 3; ++k) {
        const auto w = static_cast<Eigen::Index>(k);
        const std::size_t c = ix(fc.v[k]);
        const Vec3& p0 = m.positions[fc.v[k]];
        if (c < adopted) {
            node.top += bary[w] * (m_x.values[c] - rest_top(p0, m_normal[c], m_thickness[c]));
            node.rate += bary[w] * (m_xdot.values[c] - rest_top_rate(p0, m_normal[c], m_thickness[c]));
        } else {
            // A midpoint an earlier bisection of the same Rivara cascade made.
            CRACKLE_ASSERT(pending && c - adopted < pending->size(), "interpolating from unknown vertex " << c);
            const NewNode& q = (*pending)[c - adopted];
            node.top += bary[w] * (q.top - rest_top(p0, q.normal, q.thickness));
            node.rate += bary[w] * (q.rate - rest_top_rate(p0, q.normal, q.thickness));
        }
    }
    return nv;
}

mesh::NewVertex FemModel::face_point(FaceId f, const Vec3& bary, Vec3* top, Vec3* rate) const {
    NewNode node;
    const mesh::NewVertex nv = point_in_face(m_mesh, f, bary, node);
    if (top) *top = node.top;
    if (rate) *rate = node.rate;
    return nv;
}

std::vector<FaceId> FemModel::subdivide(FaceId f) {
    std::vector<NewNode> nodes; // per new vertex, in split order
    const mesh::MidpointRule rule = [&](const mesh::SurfaceMesh& m, FaceId face, int edge) {
        NewNode node;
        const mesh::NewVertex nv = point_on_edge(m, face, edge, 0.5, node, &nodes);
        nodes.push_back(node);
        return nv;
    };
    std::vector<mesh::EdgeSplit> splits;
    mesh::rivara_bisect(m_mesh, f, rule, splits);
    return adopt_splits(splits, nodes);
}

std::pair<VertexId, std::vector<FaceId>> FemModel::split_edge(FaceId f, int edge, double t) {
    CRACKLE_ASSERT(t > 0 && t < 1, "split parameter " << t << " outside (0, 1)");
    std::vector<NewNode> nodes(1);
    const mesh::NewVertex nv = point_on_edge(m_mesh, f, edge, t, nodes[0]);
    const std::vector<mesh::EdgeSplit> splits{mesh::split_edge(m_mesh, f, edge, nv)};
    std::vector<FaceId> touched = adopt_splits(splits, nodes);
    return {splits[0].vertex, std::move(touched)};
}

std::vector<FaceId> FemModel::adopt_splits(const std::vector<mesh::EdgeSplit>& splits,
                                           const std::vector<NewNode>& nodes) {
    CRACKLE_ASSERT(nodes.size() == splits.size(), "one new vertex per split");
    std::vector<FaceId> touched;
    for (std::size_t i = 0; i < splits.size(); ++i) {
        const mesh::EdgeSplit& split = splits[i];
        const std::size_t v = ix(split.vertex);
        CRACKLE_ASSERT(v == m_x.values.size(), "split order and vertex ids disagree");
        m_normal.emplace_back();
        m_thickness.emplace_back();
        m_x.values.emplace_back();
        m_xdot.values.emplace_back();
        m_last_update.emplace_back(0.0);
        for (Field* fd : {&m_x, &m_xdot})
            if (fd->residual_valid) {
                fd->residual.conservativeResize(fd->residual.size() + 3);
                fd->residual.tail<3>().setZero();
            }
        init_vertex(v);
        m_x.values[v] = nodes[i].top;
        m_xdot.values[v] = nodes[i].rate;
        // Children: the kept id keeps the parent's status, the new id copies it.
        for (const auto& [kid, nid] : split.children) {
            const char status = m_alive[ix(kid)];
            m_alive.push_back(status);
            if (status) ++m_num_alive;
            m_material.emplace_back();
            m_k_top.emplace_back();
            touched.push_back(kid);
            touched.push_back(nid);
        }
    }
    // Material (§5.9: recomputed whenever elements are created) and stiffness of every face
    // the refinement touched, once it is finished.
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    for (FaceId t : touched)
        init_element(ix(t));
    std::vector<std::size_t> vertices;
    for (FaceId t : touched)
        for (VertexId w : m_mesh.faces[t].v)
            vertices.push_back(ix(w));
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    refresh_incidence(touched, vertices);
    update_around(vertices); // only the residuals at the refined faces' nodes change
    return touched;
}

mesh::NewVertex FemModel::edge_point(FaceId f, int edge, double t, Vec3* top, Vec3* rate) const {
    NewNode node;
    const mesh::NewVertex nv = point_on_edge(m_mesh, f, edge, t, node);
    if (top) *top = node.top;
    if (rate) *rate = node.rate;
    return nv;
}

FaceId FemModel::flip_edge(FaceId f, int edge) {
    std::vector<std::size_t> vertices;
    for (VertexId w : m_mesh.faces[f].v)
        vertices.push_back(ix(w));
    const FaceId g = mesh::flip_edge(m_mesh, f, edge);
    if (g == mesh::NO_FACE) return g;
    for (VertexId w : m_mesh.faces[g].v)
        vertices.push_back(ix(w));
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    refresh_incidence({f, g}, vertices);
    init_element(ix(f));
    init_element(ix(g));
    update_around(vertices);
    return g;
}

void FemModel::move_vertex(VertexId v, const mesh::NewVertex& to, const Vec3& top, const Vec3& rate) {
    const std::size_t vi = ix(v);
    if (m_mesh.periodic) {
        // Each face keeps v's corner where it was in its own frame, moved by the same step.
        Vec2 step = to.domain - m_mesh.domain[v];
        for (int i = 0; i < 2; ++i)
            step[i] -= m_mesh.period[i] * std::round(step[i] / m_mesh.period[i]);
        for (std::uint32_t f : m_incident[vi]) {
            mesh::Face& face = m_mesh.faces[face_id(f)];
            for (std::size_t k = 0; k < 3; ++k) {
                if (face.v[k] != v) continue;
                const Vec2 unwrapped = m_mesh.corner_domain(face_id(f), static_cast<int>(k)) + step;
                face.offset[k] =
                    Vec2i(static_cast<int>(std::lround((unwrapped.x() - to.domain.x()) / m_mesh.period.x())),
                          static_cast<int>(std::lround((unwrapped.y() - to.domain.y()) / m_mesh.period.y())));
            }
        }
        m_mesh.domain[v] = to.domain;
    }
    m_mesh.positions[v] = to.position;
    const Vec3 keep_top = top;
    init_vertex(vi); // normal and thickness at the new place
    m_x.values[vi] = keep_top;
    m_xdot.values[vi] = rate;
    std::vector<std::size_t> vertices;
    for (std::uint32_t f : m_incident[vi]) {
        init_element(f);
        for (VertexId w : m_mesh.faces[face_id(f)].v)
            vertices.push_back(ix(w));
    }
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    update_around(vertices);
}

std::vector<std::pair<VertexId, VertexId>> FemModel::cut(const std::vector<std::pair<FaceId, int>>& edges) {
    const std::size_t nv_before = m_mesh.num_vertices();
    const auto copies = mesh::cut_edges(
        m_mesh, edges, [&](VertexId v) -> const std::vector<std::uint32_t>& { return m_incident[ix(v)]; });
    const std::size_t nv = m_mesh.num_vertices();
    if (nv == nv_before) {
        // Nothing opened (a cut with both ends inside the mesh): the topology is unchanged.
        return copies;
    }
    // Copies inherit everything per vertex; the faces moved to them change nothing else.
    std::vector<std::size_t> vertices;
    std::vector<FaceId> faces;
    for (const auto& [copy, origin] : copies) {
        const std::size_t v = ix(copy), o = ix(origin);
        m_normal.push_back(m_normal[o]);
        m_thickness.push_back(m_thickness[o]);
        m_x.values.push_back(m_x.values[o]);
        m_xdot.values.push_back(m_xdot.values[o]);
        m_last_update.push_back(0.0);
        for (Field* fd : {&m_x, &m_xdot})
            if (fd->residual_valid) {
                fd->residual.conservativeResize(fd->residual.size() + 3);
                fd->residual.tail<3>().setZero();
            }
        vertices.push_back(o);
        vertices.push_back(v);
        for (std::uint32_t f : m_incident[o])
            faces.push_back(face_id(f)); // the origin's faces, some now at the copy
    }
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    refresh_incidence(faces, vertices);
    update_around(vertices);
    return copies;
}

} // namespace crackle::sim
