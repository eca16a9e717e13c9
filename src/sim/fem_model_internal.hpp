#pragma once
/// @file Private to src/sim's fem_*.cpp: FemModel's solver state and shared sparse helpers (Federl 2002, §5.4–5.5).

#include "core/error.hpp"
#include "sim/fem_model.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

#include <algorithm>

namespace crackle::sim {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;
using mesh::vertex_id;
using mesh::VertexId;
using SpMatR = Eigen::SparseMatrix<double, Eigen::RowMajor>;

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

/// Sets K(row, col) in an uncompressed matrix whose row has room. Eigen's own insert()
/// re-reserves every row (O(nnz)) whenever the storage has spare capacity, which geometric
/// growth always leaves; this never reallocates.
inline void set_entry(SpMatR& K, Eigen::Index row, Eigen::Index col, double value) {
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

} // namespace crackle::sim
