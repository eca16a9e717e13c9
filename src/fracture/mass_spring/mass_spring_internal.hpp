#pragma once
/// @file Private to mass_spring/*.cpp: the stiffness factor of MassSpringModel's Newton solver (Federl 2002, Ch. 4).

#include "fracture/mass_spring/mass_spring.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/SparseCore>

#include <cstddef>
#include <vector>

namespace crackle::fracture {

// === The linear solver: modified Newton with a Cholesky factor of the (projected) Hessian
// M = Σ k(uuᵀ + g(I − uuᵀ)) + anchors + layer links, frozen when factored (u the spring
// direction, g = max(0, 1 − L/l) its geometric factor). M drifts from the true Hessian only as
// the strains change, so x ← x − M⁻¹∇E contracts fast. A broken spring is a rank-1 (or rank-3,
// with its geometric part) downdate of the factor (CHOLMOD updown, Davis & Hager) instead of a
// refactorization; the factor is rebuilt only when the iteration slows.

namespace mass_spring_detail {

/// Exposes the factor held by Eigen's CHOLMOD wrapper, for cholmod_updown.
struct CholmodFactor : Eigen::CholmodDecomposition<Eigen::SparseMatrix<double>, Eigen::Lower> {
    cholmod_factor* factor() { return m_cholmodFactor; }
};

} // namespace mass_spring_detail

using mass_spring_detail::CholmodFactor;

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

/// The crack pattern of a finished run (kite_pattern.cpp, §4.4-4.5): the masses' Voronoi cells
/// as kites cut along broken top-layer springs, at their final places, with the crack lips and
/// their depths (counted into `stats.crack_depth_layers`). Events are the loop's to add.
CrackPattern kite_pattern(const MassSpringModel& model, MassSpringStats& stats);

} // namespace crackle::fracture
