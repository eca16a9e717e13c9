/// @file FemModel's adaptive local relaxation around a change (Federl 2002, §5.8, §5.8.3; elimination, §5.5).
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/timer.hpp"
#include "sim/fem_model_internal.hpp"

#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>

namespace crackle::sim {

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
    auto force = [&](std::size_t v) { return std::sqrt(vertex_force_squared(fd, v)); };
    const auto p = static_cast<std::size_t>(m_order); // slots per vertex
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
        std::vector<std::size_t> set = local_ball(sources, radius);
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

        // === K_SS Δ = r_S with the rest held (the thesis' elimination method, §5.5); every slot
        // of a vertex in the set is solved for: local unknown 3·(p·i + j) + d.
        Eigen::VectorXd rhs;
        const Eigen::VectorXd dx = solve_local_set(fd, set, rhs);
        stats.iterations += 1;
        stats.energy_release += 0.5 * rhs.dot(dx);
        stats.nodes = std::max(stats.nodes, set.size());

        // === Apply: x_S += Δ; r −= K[:, S] Δ (K symmetric: walk the rows of S). The force
        // this pushes onto the nodes just outside the set is what is left to resolve.
        const std::vector<std::size_t> outside = apply_local_step(fd, set, dx);
        for (std::size_t v : set)
            local_index[v] = -1;

        // === Radius control (§5.8.3): grow while the pushed-out forces are not negligible
        // next to the change (the thesis checks the residual; forces left over from earlier
        // events are not this change's to resolve).
        std::vector<std::size_t> unresolved;
        for (std::size_t w : outside) {
            double left = 0; // the force pushed onto w's slots
            for (std::size_t j = 0; j < p; ++j) {
                left += pushed[p * w + j].squaredNorm();
                pushed[p * w + j] = Vec3::Zero();
            }
            if (m_alive_degree[w] > 0 && std::sqrt(left) > tol) unresolved.push_back(w);
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

std::vector<std::size_t> FemModel::local_ball(const std::vector<std::size_t>& sources, double radius) {
    std::vector<int>& hop = m_scratch_hop;
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
    return set;
}

Eigen::VectorXd FemModel::solve_local_set(const Field& fd, const std::vector<std::size_t>& set, Eigen::VectorXd& rhs) {
    const auto p = static_cast<std::size_t>(m_order);
    std::vector<int>& local_index = m_scratch_index;
    const auto m = static_cast<Eigen::Index>(3 * p * set.size());
    for (std::size_t i = 0; i < set.size(); ++i)
        local_index[set[i]] = static_cast<int>(i);
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(static_cast<std::size_t>(m) * 21 * p);
    rhs.resize(m);
    for (std::size_t i = 0; i < set.size(); ++i) {
        const std::size_t v = set[i];
        for (std::size_t j = 0; j < p; ++j) {
            const auto local = static_cast<Eigen::Index>(3 * (p * i + j));
            rhs.segment<3>(local) = fd.residual.segment<3>(static_cast<Eigen::Index>(3 * (p * v + j)));
            for (int d = 0; d < 3; ++d) {
                const auto row = static_cast<Eigen::Index>(3 * (p * v + j)) + d;
                for (SpMatR::InnerIterator it(m_K, row); it; ++it) {
                    const auto col_slot = static_cast<std::size_t>(it.col() / 3);
                    const int lj = local_index[col_slot / p];
                    // K keeps explicit zeros where edits left them (its pattern only grows);
                    // leaving them out makes the ordering, and so the answer's last bits,
                    // independent of the edit history.
                    if (lj >= 0 && it.value() != 0.0)
                        triplets.emplace_back(
                            local + d,
                            static_cast<Eigen::Index>(3 * (p * static_cast<std::size_t>(lj) + col_slot % p))
                                + it.col() % 3,
                            it.value());
                }
            }
        }
    }
    Eigen::SparseMatrix<double> Kss(m, m);
    Kss.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Kss);
    if (ldlt.info() != Eigen::Success) throw NumericError("local stiffness matrix is not positive definite");
    return ldlt.solve(rhs);
}

std::vector<std::size_t> FemModel::apply_local_step(Field& fd, const std::vector<std::size_t>& set,
                                                    const Eigen::VectorXd& dx) {
    const auto p = static_cast<std::size_t>(m_order);
    const std::size_t nv = m_mesh.num_vertices();
    std::vector<int>& local_index = m_scratch_index;
    std::vector<char>& touched = m_scratch_touched;
    std::vector<Vec3>& pushed = m_scratch_pushed;
    std::vector<std::size_t> outside;
    if (pushed.size() < p * nv) pushed.resize(p * nv, Vec3::Zero());
    auto untouched = [&](std::size_t w) {
        for (std::size_t j = 0; j < p; ++j)
            if (pushed[p * w + j] != Vec3::Zero()) return false;
        return true;
    };
    for (std::size_t i = 0; i < set.size(); ++i) {
        const std::size_t v = set[i];
        double moved = 0;
        for (std::size_t j = 0; j < p; ++j) {
            const Vec3 d = dx.segment<3>(static_cast<Eigen::Index>(3 * (p * i + j)));
            fd.values[p * v + j] += d;
            moved = std::max(moved, d.norm());
            for (int c = 0; c < 3; ++c) {
                const auto row = static_cast<Eigen::Index>(3 * (p * v + j)) + c;
                for (SpMatR::InnerIterator it(m_K, row); it; ++it) {
                    const auto w_slot = static_cast<std::size_t>(it.col() / 3);
                    const std::size_t w = w_slot / p;
                    fd.residual[it.col()] -= it.value() * d[c];
                    if (local_index[w] < 0) {
                        if (untouched(w)) outside.push_back(w);
                        pushed[w_slot][it.col() % 3] -= it.value() * d[c];
                    }
                }
            }
        }
        m_last_update[v] += moved;
        if (!touched[v]) {
            touched[v] = 1;
            m_updated.push_back(v);
        }
    }
    return outside;
}

} // namespace crackle::sim
