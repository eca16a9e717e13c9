/// @file FemModel's global equilibrium solves: Jacobi CG or CHOLMOD, positions and rates (Federl 2002, §5.5).
#include "core/error.hpp"
#include "core/timer.hpp"
#include "sim/fem_model_internal.hpp"

#include <algorithm>
#include <sstream>
#include <string>

namespace crackle::sim {

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
        // A vertex's update: the largest move of its slots (its top node and its modes' peaks).
        double moved = 0;
        for (int j = 0; j < m_order; ++j) {
            const Vec3 d = dx.segment<3>(static_cast<Eigen::Index>(3 * slot(v, j)));
            fd.values[slot(v, j)] += d;
            moved = std::max(moved, d.norm());
        }
        m_last_update[v] = moved;
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

} // namespace crackle::sim
