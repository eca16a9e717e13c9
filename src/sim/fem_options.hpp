#pragma once
/// @file Options of the wedge-FEM equilibrium solves (Federl 2002, §5.5), a preset's simulation.solver* keys,
/// without the whole model (sim::FemModel).

namespace crackle::sim {

enum class SolverKind {
    Cg,    ///< conjugate gradient, Jacobi preconditioned, warm-started (the thesis' choice)
    Direct ///< sparse Cholesky (CHOLMOD supernodal), refactorized when K changes
};

struct FemOptions {
    SolverKind solver = SolverKind::Cg;
    double tolerance = 1e-9;    ///< CG: residual norm relative to the load's norm
    int max_iterations = 20000; ///< CG iterations before a NumericError
    /// Rebuild K when the shrinkage scale has moved this much since the last build; 0 rebuilds
    /// it at every change of time. In the fracture loops time moves in steps: with 0 each step
    /// starts from a fresh K, but the step's own search (Alg. 5) extrapolates with it, so the
    /// events of one long step still see its stiffness (a small positive value ends steps where
    /// the shrinkage has moved by it).
    double stiffness_refresh = 0.01;
    /// Polynomial order of the displacement through the layer (wedge_modes.hpp): 1 is the
    /// thesis' linear wedge; 2 and 3 add per-vertex through-thickness modes (3 unknowns each).
    int thickness_order = 1;
    bool operator==(const FemOptions&) const = default; ///< every field: the options test compares whole structs
};

} // namespace crackle::sim
