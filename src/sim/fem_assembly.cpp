/// @file FemModel assembly of K_tt, local row rebuilds and incidence (Federl 2002, §5.4, Alg. 4, Alg. 7).
#include "sim/fem_model_internal.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::sim {

namespace {
/// An absolute floor for the residual: forces that move nodes by 1e-13 of an element.
double residual_floor(const SpMatR& K, const mesh::SurfaceMesh& mesh) {
    const double k_max = K.diagonal().cwiseAbs().maxCoeff();
    const double length =
        std::sqrt(mesh.total_area() / static_cast<double>(std::max<std::size_t>(mesh.num_faces(), 1)));
    return 1e-13 * k_max * length * std::sqrt(static_cast<double>(K.rows()));
}
} // namespace

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
    const auto n = static_cast<Eigen::Index>(3 * slot(m_mesh.num_vertices()));
    const auto p2 = static_cast<std::size_t>(m_order * m_order);
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(81 * p2 * m_mesh.num_faces() + 3 * slot(m_mesh.num_vertices()));
    for (std::size_t f = 0; f < m_mesh.num_faces(); ++f) {
        const mesh::Face& face = m_mesh.faces[face_id(f)];
        const bool on = m_alive[f] != 0;
        const auto K = k_free(f);
        for (std::size_t a = 0; a < 3; ++a)
            for (int ja = 0; ja < m_order; ++ja)
                for (std::size_t b = 0; b < 3; ++b)
                    for (int jb = 0; jb < m_order; ++jb) {
                        const auto ra = static_cast<Eigen::Index>(3 * slot(ix(face.v[a]), ja));
                        const auto cb = static_cast<Eigen::Index>(3 * slot(ix(face.v[b]), jb));
                        const auto ka = 9 * ja + static_cast<Eigen::Index>(3 * a);
                        const auto kb = 9 + 9 * jb + static_cast<Eigen::Index>(3 * b);
                        for (int i = 0; i < 3; ++i)
                            for (int j = 0; j < 3; ++j)
                                // Dead elements keep their (zero) entries so the pattern never shrinks.
                                triplets.emplace_back(ra + i, cb + j, on ? K(ka + i, kb + j) : 0.0);
                    }
    }
    // A top node with no element left keeps its place: identity rows, zero right-hand side.
    for (std::size_t v = 0; v < m_mesh.num_vertices(); ++v)
        if (m_alive_degree[v] == 0)
            for (int j = 0; j < m_order; ++j)
                for (int i = 0; i < 3; ++i) {
                    const auto d = static_cast<Eigen::Index>(3 * slot(v, j)) + i;
                    triplets.emplace_back(d, d, 1.0);
                }
    SpMatR K(n, n);
    K.setFromTriplets(triplets.begin(), triplets.end());
    return K;
}

void FemModel::assemble() {
    m_K = assemble_from_scratch();
    // Room for three more neighbours per row: splitting and cutting add entries locally.
    m_K.reserve(Eigen::VectorXi::Constant(m_K.outerSize(), 27 * m_order));
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
        record_incidence(v);
        auto& list = m_incident[v];
        list.erase(std::remove_if(list.begin(), list.end(), [&](std::uint32_t f) { return !has(f, v); }), list.end());
    }
    for (FaceId f : faces)
        for (VertexId w : m_mesh.faces[f].v) {
            record_incidence(ix(w));
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

std::vector<FemModel::StiffnessBlock> FemModel::stiffness_blocks(const std::vector<std::size_t>& vertices) const {
    // The new blocks between slots: (a, b, K_ab) summed over the faces a's and b's vertices share.
    std::vector<StiffnessBlock> blocks;
    for (std::size_t va : vertices) {
        for (int ja = 0; ja < m_order; ++ja) {
            const std::size_t a = slot(va, ja);
            const std::size_t first = blocks.size();
            for (std::uint32_t f : m_incident[va]) {
                if (!m_alive[f]) continue;
                const mesh::Face& face = m_mesh.faces[face_id(f)];
                std::size_t ka = 3;
                for (std::size_t k = 0; k < 3; ++k)
                    if (ix(face.v[k]) == va) ka = k;
                for (std::size_t kb = 0; kb < 3; ++kb)
                    for (int jb = 0; jb < m_order; ++jb) {
                        const std::size_t b = slot(ix(face.v[kb]), jb);
                        const Mat3 K = k_block(f, ja, ka, jb, kb);
                        auto it = std::find_if(blocks.begin() + static_cast<std::ptrdiff_t>(first), blocks.end(),
                                               [&](const StiffnessBlock& e) { return e.b == b; });
                        if (it == blocks.end())
                            blocks.push_back({a, b, K});
                        else
                            it->K += K;
                    }
            }
            if (m_alive_degree[va] == 0) blocks.push_back({a, a, Mat3::Identity()});
        }
    }
    return blocks;
}

// Make room first, in one move: Eigen's one-at-a-time insertion reallocates everything.
// The matrix stays uncompressed with slack in every row, so most changes fit where they
// are; a short row moves the rows after it (O(nnz)), so it gets generous slack.
void FemModel::reserve_stiffness_room(const std::vector<StiffnessBlock>& blocks) {
    const int slack = 18 * m_order; // six new neighbour vertices
    // (row, first column) of each missing 3-column block, each once: a block (a, b) and
    // its mirror (b, a) both ask for the same two.
    std::vector<std::pair<Eigen::Index, Eigen::Index>> absent;
    auto has = [&](Eigen::Index row, Eigen::Index col) {
        for (SpMatR::InnerIterator it(m_K, row); it; ++it)
            if (it.col() == col) return true;
        return false;
    };
    for (const StiffnessBlock& bl : blocks)
        for (int i = 0; i < 3; ++i) {
            const auto ra = static_cast<Eigen::Index>(3 * bl.a) + i, rb = static_cast<Eigen::Index>(3 * bl.b) + i;
            const auto ca = static_cast<Eigen::Index>(3 * bl.a), cb = static_cast<Eigen::Index>(3 * bl.b);
            if (!has(ra, cb)) absent.emplace_back(ra, cb);
            if (!has(rb, ca)) absent.emplace_back(rb, ca);
        }
    std::sort(absent.begin(), absent.end());
    absent.erase(std::unique(absent.begin(), absent.end()), absent.end());
    std::vector<Eigen::Index> missing; // rows, one entry per missing 3-column block
    for (const auto& rc : absent)
        missing.push_back(rc.first);
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
        // Eigen's reserve walks and moves every row whatever it is asked for, so one pass
        // gives every row room for twelve new neighbours: a tip sub-model's trial (§5.7.8)
        // adds up to about ten to the rows around a tip (and takes them away again), and
        // a pass per trial was 15 % of mud's run.
        Eigen::VectorXi need = Eigen::VectorXi::Zero(m_K.outerSize());
        for (Eigen::Index r : missing)
            need[r] += 3;
        for (Eigen::Index r = 0; r < need.size(); ++r) // the room each row gets (at least);
            need[r] = need[r] > 0 ? std::max(need[r] + 2 * slack, m_K.innerNonZeroPtr()[r]) // a short row doubles
                                  : 2 * slack;
        // Grow the storage geometrically, and only when it is full.
        Eigen::Index extra = 0;
        for (Eigen::Index r = 0; r < need.size(); ++r)
            extra += std::max<Eigen::Index>(
                0, need[r] - (m_K.outerIndexPtr()[r + 1] - m_K.outerIndexPtr()[r] - m_K.innerNonZeroPtr()[r]));
        if (m_K.data().size() + extra > m_K.data().allocatedSize())
            m_K.data().reserve(std::max<Eigen::Index>(extra, m_K.data().size() / 2));
        m_K.reserve(need);
    }
}

void FemModel::reassemble_around(const std::vector<std::size_t>& vertices) {
    // The rows (and, by symmetry, columns) of these vertices are rebuilt from their current
    // elements (Alg. 7 generalised): exact, O(changed), no full assembly. The pattern only grows.
    grow_rows(static_cast<Eigen::Index>(3 * slot(m_mesh.num_vertices())));
    const std::vector<StiffnessBlock> blocks = stiffness_blocks(vertices);
    reserve_stiffness_room(blocks);
    if (m_trial.active) {
        // Every row this touches: the vertices' own, their old and new neighbours'.
        for (std::size_t va : vertices)
            for (int j = 0; j < m_order; ++j)
                for (int i = 0; i < 3; ++i) {
                    const auto row = static_cast<Eigen::Index>(3 * slot(va, j)) + i;
                    if (row >= m_K.rows()) continue;
                    record_row(row);
                    for (SpMatR::InnerIterator it(m_K, row); it; ++it)
                        record_row(it.col());
                }
        for (const StiffnessBlock& bl : blocks)
            for (int i = 0; i < 3; ++i) {
                record_row(static_cast<Eigen::Index>(3 * bl.a) + i);
                record_row(static_cast<Eigen::Index>(3 * bl.b) + i);
            }
    }
    for (std::size_t va : vertices)
        for (int j = 0; j < m_order; ++j)
            for (int i = 0; i < 3; ++i) {
                const auto row = static_cast<Eigen::Index>(3 * slot(va, j)) + i;
                for (SpMatR::InnerIterator it(m_K, row); it; ++it) {
                    it.valueRef() = 0.0;
                    set_entry(m_K, it.col(), row, 0.0);
                }
            }
    for (const StiffnessBlock& bl : blocks) {
        set_block(bl.a, bl.b, bl.K);
        set_block(bl.b, bl.a, bl.K.transpose());
    }
    m_stiffness_dirty_for_x = true;
    m_solver->invalidate(true);
}

void FemModel::defer_updates() {
    CRACKLE_ASSERT(!m_defer_updates, "deferred updates do not nest");
    m_defer_updates = true;
}

void FemModel::flush_updates() {
    CRACKLE_ASSERT(m_defer_updates, "flush_updates() without defer_updates()");
    m_defer_updates = false;
    std::vector<std::size_t> vertices;
    vertices.swap(m_deferred_vertices);
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    if (!vertices.empty()) update_around(vertices);
}

void FemModel::update_around(const std::vector<std::size_t>& vertices) {
    if (m_defer_updates) {
        m_deferred_vertices.insert(m_deferred_vertices.end(), vertices.begin(), vertices.end());
        return;
    }
    reassemble_around(vertices);
    recompute_residual_at(Unknown::Position, vertices);
    recompute_residual_at(Unknown::Rate, vertices);
    m_x.load_norm = m_xdot.load_norm = -1;
}

void FemModel::grow_rows(Eigen::Index n) {
    // Per old row, per new row (20 neighbour vertices: bisection around a tip, §5.7.8, gives a new
    // vertex up to ~16), three entries per slot of each.
    const int slack = 18 * m_order, room = 60 * m_order;
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

} // namespace crackle::sim
