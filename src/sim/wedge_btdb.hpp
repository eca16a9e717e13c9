#pragma once
/// @file Private to the wedge elements (wedge_element.cpp, wedge_modes.cpp): K += s·Bᵀ D B for a
/// strain-displacement matrix B that is never formed (Federl 2002, Eqs. 5.39–5.41).

#include "core/math.hpp"

namespace crackle::sim::wedge::detail {

/// The rows of B holding a column's three non-zeros, and which of (∂x, ∂y, ∂z) each is: column
/// 3i + d of B (Eq. 5.41) has them for displacement component d of function i.
constexpr int B_ROW[3][3] = {{0, 4, 5}, {1, 3, 5}, {2, 3, 4}};
constexpr int B_DERIV[3][3] = {{0, 2, 1}, {1, 2, 0}, {2, 1, 0}};

/// K += s·Bᵀ D B, where B's columns come from the Cartesian derivatives `dx` (3 × NF) of NF
/// displacement functions: each column of B has three non-zeros, so D B costs 3 terms per
/// entry instead of 6 and Bᵀ (D B) 3 instead of 6 (a quarter of the dense work). Only the upper
/// triangle is written; the caller mirrors it.
template <int NF>
void add_btdb(const Eigen::Matrix<double, 3, NF>& dx, const Eigen::Matrix<double, 6, 6>& D, double s,
              Eigen::Matrix<double, 3 * NF, 3 * NF>& K) {
    Eigen::Matrix<double, 6, 3 * NF> DB;
    for (int i = 0; i < NF; ++i)
        for (int d = 0; d < 3; ++d) {
            const int q = 3 * i + d;
            DB.col(q) = D.col(B_ROW[d][0]) * dx(B_DERIV[d][0], i) + D.col(B_ROW[d][1]) * dx(B_DERIV[d][1], i)
                        + D.col(B_ROW[d][2]) * dx(B_DERIV[d][2], i);
        }
    for (int i = 0; i < NF; ++i)
        for (int d = 0; d < 3; ++d) {
            const int p = 3 * i + d, r0 = B_ROW[d][0], r1 = B_ROW[d][1], r2 = B_ROW[d][2];
            const double b0 = s * dx(B_DERIV[d][0], i), b1 = s * dx(B_DERIV[d][1], i), b2 = s * dx(B_DERIV[d][2], i);
            for (int q = p; q < 3 * NF; ++q)
                K(p, q) += b0 * DB(r0, q) + b1 * DB(r1, q) + b2 * DB(r2, q);
        }
}

} // namespace crackle::sim::wedge::detail
