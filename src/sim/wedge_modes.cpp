#include "sim/wedge_modes.hpp"

#include "core/error.hpp"
#include "sim/wedge_btdb.hpp"

#include <cmath>

namespace crackle::sim::wedge {

double mode_shape(int k, double zeta) {
    return k == 2 ? 1 - zeta * zeta : zeta * (1 - zeta * zeta);
}

double mode_slope(int k, double zeta) {
    return k == 2 ? -2 * zeta : 1 - 3 * zeta * zeta;
}

const std::array<GaussPoint, 12>& quadrature_high() {
    static const std::array<GaussPoint, 12> points = [] {
        // 4-point Gauss–Legendre on [−1, 1].
        const double a = std::sqrt(3.0 / 7.0 - 2.0 / 7.0 * std::sqrt(6.0 / 5.0));
        const double b = std::sqrt(3.0 / 7.0 + 2.0 / 7.0 * std::sqrt(6.0 / 5.0));
        const double wa = (18.0 + std::sqrt(30.0)) / 36.0, wb = (18.0 - std::sqrt(30.0)) / 36.0;
        const std::array<double, 4> zeta = {b, a, -a, -b};
        const std::array<double, 4> wz = {wb, wa, wa, wb};
        const double p = 2.0 / 3.0, q = 1.0 / 6.0;
        const std::array<std::array<double, 2>, 3> tri = {{{p, q}, {q, p}, {q, q}}};
        std::array<GaussPoint, 12> g{};
        for (std::size_t k = 0; k < 4; ++k)
            for (std::size_t i = 0; i < 3; ++i)
                g[3 * k + i] = {tri[i][0], tri[i][1], zeta[k], wz[k] / 6.0}; // triangle area ½, 3 points
        return g;
    }();
    return points;
}

namespace {

/// Natural derivatives (rows ∂ξ, ∂η, ∂ζ) of every displacement function: the six wedge nodes,
/// then L_c·φ_k per mode k = 2..p and corner c.
MatX natural_derivatives(int order, double xi, double eta, double zeta) {
    const int n = 6 + 3 * (order - 1);
    MatX d(3, n);
    d.leftCols<6>() = shape_derivatives(xi, eta, zeta);
    const std::array<double, 3> L = {xi, eta, 1 - xi - eta};
    const std::array<double, 3> dL_dxi = {1, 0, -1}, dL_deta = {0, 1, -1};
    for (int k = 2; k <= order; ++k) {
        const double phi = mode_shape(k, zeta), slope = mode_slope(k, zeta);
        for (std::size_t c = 0; c < 3; ++c) {
            const int col = 6 + 3 * (k - 2) + static_cast<int>(c);
            d(0, col) = dL_dxi[c] * phi;
            d(1, col) = dL_deta[c] * phi;
            d(2, col) = L[c] * slope;
        }
    }
    return d;
}

} // namespace

MatX strain_matrix(const Nodes& nodes, int order, double xi, double eta, double zeta, double* det_j) {
    CRACKLE_ASSERT(order >= 1 && order <= MAX_THICKNESS_ORDER, "thickness order " << order);
    const Mat3 J = jacobian(nodes, shape_derivatives(xi, eta, zeta));
    const double det = J.determinant();
    CRACKLE_ASSERT(det > 0, "inverted or degenerate wedge (det J = " << det << ")");
    if (det_j) *det_j = det;
    const MatX dx = J.inverse() * natural_derivatives(order, xi, eta, zeta);
    MatX B = MatX::Zero(6, element_dofs(order));
    for (Eigen::Index i = 0; i < dx.cols(); ++i) {
        const double nx = dx(0, i), ny = dx(1, i), nz = dx(2, i);
        const Eigen::Index c = 3 * i;
        B(0, c) = nx;     // εx = u,x
        B(1, c + 1) = ny; // εy = v,y
        B(2, c + 2) = nz; // εz = w,z
        B(3, c + 1) = nz; // γyz = v,z + w,y
        B(3, c + 2) = ny;
        B(4, c) = nz; // γzx = u,z + w,x
        B(4, c + 2) = nx;
        B(5, c) = ny; // γxy = u,y + v,x
        B(5, c + 1) = nx;
    }
    return B;
}

namespace {

/// K_e of order P with fixed-size matrices: NF = 6 + 3(P − 1) displacement functions.
template <int P> MatX stiffness_of_order(const Nodes& nodes, const Mat6& D) {
    constexpr int NF = 6 + 3 * (P - 1);
    Eigen::Matrix<double, 3 * NF, 3 * NF> K = Eigen::Matrix<double, 3 * NF, 3 * NF>::Zero();
    auto add = [&](const GaussPoint& g) {
        const Mat3 J = jacobian(nodes, shape_derivatives(g.xi, g.eta, g.zeta));
        const double det = J.determinant();
        CRACKLE_ASSERT(det > 0, "inverted or degenerate wedge (det J = " << det << ")");
        const Eigen::Matrix<double, 3, NF> dx = J.inverse() * natural_derivatives(P, g.xi, g.eta, g.zeta);
        detail::add_btdb<NF>(dx, D, g.weight * det, K);
    };
    // Order 2's products are of degree 4 in ζ on a prism: Table 5.1's 3-point rule is exact;
    // order 3's are of degree 6 and take four points.
    if constexpr (P == 2)
        for (const GaussPoint& g : quadrature())
            add(g);
    else
        for (const GaussPoint& g : quadrature_high())
            add(g);
    K.template triangularView<Eigen::StrictlyLower>() = K.transpose(); // exactly symmetric
    return K;
}

} // namespace

MatX stiffness(const Nodes& nodes, const Mat6& D, int order) {
    CRACKLE_ASSERT(order >= 1 && order <= MAX_THICKNESS_ORDER, "thickness order " << order);
    if (order == 1) return stiffness(nodes, D);
    if (order == 2) return stiffness_of_order<2>(nodes, D);
    return stiffness_of_order<3>(nodes, D);
}

Vec6 stress(const Nodes& reference, const Mat6& D, const VecX& q, int order, double xi, double eta, double zeta) {
    return D * (strain_matrix(reference, order, xi, eta, zeta) * q);
}

} // namespace crackle::sim::wedge
