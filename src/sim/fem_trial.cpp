/// @file FemModel trials: undoable changes for fem-split's Griffith test of a tip extension (Federl 2002, Alg. 11).
#include "core/error.hpp"
#include "sim/fem_model_internal.hpp"

namespace crackle::sim {

// === Trials (undoable changes)

namespace {

/// Sets an uncompressed row-major matrix's size to n × n, keeping the storage. Only for a
/// matrix whose first n rows hold no column at or past n. SparseMatrix's sizes are protected;
/// a pointer to member formed through a derived class reaches them without a cast.
struct ShrinkSquare : SpMatR {
    static void apply(SpMatR& K, Eigen::Index n) {
        K.*(&ShrinkSquare::m_outerSize) = n;
        K.*(&ShrinkSquare::m_innerSize) = n;
    }
};

} // namespace

struct FemModel::Trial {
    std::size_t faces = 0, vertices = 0;
    mesh::SurfaceMesh mesh;
    std::vector<Vec3> normal;
    std::vector<double> thickness, last_update;
    Field x, xdot;
    std::vector<std::size_t> updated;
    // Incidence lists are many small vectors: the trial saves only those it changes.
    std::vector<char> incident_recorded;
    std::vector<std::pair<std::size_t, std::vector<std::uint32_t>>> incident;
    std::vector<int> alive_degree;
    std::vector<char> alive;
    std::vector<std::uint8_t> broken;
    std::size_t num_alive = 0;
    bool stiffness_dirty = false;
    // Recorded on first change: existing elements and matrix rows.
    std::vector<char> element_recorded;
    std::vector<std::pair<std::size_t, ElementMaterial>> elements;
    std::vector<double> stiffness; // k_stride() per recorded element, in the order of `elements`
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

void FemModel::begin_trial(bool stiffness_only) {
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
    t.incident_recorded.assign(t.vertices, 0);
    t.incident.clear();
    t.alive_degree = m_alive_degree;
    t.alive = m_alive;
    t.broken = m_broken;
    t.num_alive = m_num_alive;
    t.stiffness_dirty = m_stiffness_dirty_for_x;
    t.element_recorded.assign(t.faces, 0);
    t.elements.clear();
    t.stiffness.clear();
    t.row_recorded.assign(static_cast<std::size_t>(m_K.rows()), 0);
    t.rows.clear();
    m_trial.active = true;
    m_trial.stiffness_only = stiffness_only;
}

void FemModel::record_element(std::size_t f) {
    if (!m_trial.active) return;
    Trial& t = *m_trial.trial;
    if (f >= t.faces || t.element_recorded[f]) return;
    t.element_recorded[f] = 1;
    t.elements.emplace_back(f, m_material[f]);
    const double* k = m_k_free.data() + f * k_stride();
    t.stiffness.insert(t.stiffness.end(), k, k + k_stride());
}

void FemModel::record_incidence(std::size_t v) {
    if (!m_trial.active) return;
    Trial& t = *m_trial.trial;
    if (v >= t.vertices || t.incident_recorded[v]) return;
    t.incident_recorded[v] = 1;
    t.incident.emplace_back(v, m_incident[v]);
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
    m_incident.resize(t.vertices);
    for (auto& [v, list] : t.incident)
        m_incident[v].swap(list);
    m_alive_degree = t.alive_degree;
    m_alive = t.alive;
    m_broken = t.broken;
    m_num_alive = t.num_alive;
    m_stiffness_dirty_for_x = t.stiffness_dirty;
    m_material.resize(t.faces);
    m_k_free.resize(t.faces * k_stride());
    for (std::size_t i = 0; i < t.elements.size(); ++i) {
        const auto& [f, material] = t.elements[i];
        m_material[f] = material;
        const auto from = t.stiffness.begin() + static_cast<std::ptrdiff_t>(i * k_stride());
        std::copy(from, from + static_cast<std::ptrdiff_t>(k_stride()),
                  m_k_free.begin() + static_cast<std::ptrdiff_t>(f * k_stride()));
    }
    // Recorded rows get their old entries back and rows and columns of new vertices are cut off.
    const auto n = static_cast<Eigen::Index>(3 * slot(t.vertices));
    if (!m_K.isCompressed()) {
        // In place: the pattern only grows, so a row's storage still holds its old entries.
        for (const auto& [row, entries] : t.rows) {
            if (row >= n) continue;
            const auto count = static_cast<int>(entries.size());
            CRACKLE_ASSERT(count <= m_K.innerNonZeroPtr()[row], "a trial only adds entries to K");
            const int start = m_K.outerIndexPtr()[row];
            for (int i = 0; i < count; ++i) {
                m_K.innerIndexPtr()[start + i] = static_cast<int>(entries[static_cast<std::size_t>(i)].first);
                m_K.valuePtr()[start + i] = entries[static_cast<std::size_t>(i)].second;
            }
            m_K.innerNonZeroPtr()[row] = count;
        }
        // No row below n holds a column at or past n now (only recorded rows were changed), so
        // only the sizes change: Eigen's conservativeResize would walk every row to find that
        // out, a cache miss each (7 % of a 20000-element mud run).
        if (m_K.rows() > n) ShrinkSquare::apply(m_K, n);
    } else {
        for (const auto& [row, entries] : t.rows) {
            for (SpMatR::InnerIterator it(m_K, row); it; ++it)
                it.valueRef() = 0.0;
            for (const auto& [col, value] : entries)
                set_entry(m_K, row, col, value);
        }
        if (m_K.rows() > n) m_K.conservativeResize(n, n);
    }
    m_solver->invalidate(true);
    m_trial.active = m_trial.stiffness_only = false;
}

void FemModel::commit() {
    CRACKLE_ASSERT(m_trial.active, "commit() without begin_trial()");
    CRACKLE_ASSERT(!m_trial.stiffness_only, "a stiffness-only trial has no strengths to keep");
    m_trial.active = false;
}

} // namespace crackle::sim
