#include "sim/wedge_element.hpp"

#include "core/error.hpp"

#include <Eigen/Eigenvalues>

namespace crackle::sim::wedge {

const std::array<GaussPoint, 9>& quadrature() {
    // Federl 2002, Table 5.1, with weights ½·(1/3)·{5/9, 8/9, 5/9} (see header).
    static const std::array<GaussPoint, 9> points = [] {
        const double z = std::sqrt(3.0 / 5.0);
        const double a = 2.0 / 3.0, b = 1.0 / 6.0;
        const std::array<double, 3> zeta = {z, 0.0, -z};
        const std::array<double, 3> wz = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
        const std::array<std::array<double, 2>, 3> tri = {{{a, b}, {b, a}, {b, b}}};
        std::array<GaussPoint, 9> p{};
        for (std::size_t k = 0; k < 3; ++k)
            for (std::size_t i = 0; i < 3; ++i)
                p[3 * k + i] = {tri[i][0], tri[i][1], zeta[k], wz[k] / 6.0};
        return p;
    }();
    return points;
}

Vec6 shape_functions(double xi, double eta, double zeta) {
    const double m = 1.0 - xi - eta;
    Vec6 N;
    N << 0.5 * xi * (1 - zeta), 0.5 * eta * (1 - zeta), 0.5 * m * (1 - zeta), 0.5 * xi * (1 + zeta),
        0.5 * eta * (1 + zeta), 0.5 * m * (1 + zeta);
    return N;
}

Mat3x6 shape_derivatives(double xi, double eta, double zeta) {
    // Eq. 5.24: rows ∂/∂ξ, ∂/∂η, ∂/∂ζ.
    const double lo = 1 - zeta, hi = 1 + zeta, m = 1 - xi - eta;
    Mat3x6 d;
    d << lo, 0, -lo, hi, 0, -hi, //
        0, lo, -lo, 0, hi, -hi,  //
        -xi, -eta, -m, xi, eta, m;
    return 0.5 * d;
}

Mat3 jacobian(const Nodes& nodes, const Mat3x6& dN) {
    Mat3 J = Mat3::Zero();
    for (std::size_t i = 0; i < 6; ++i)
        J += dN.col(static_cast<Eigen::Index>(i)) * nodes[i].transpose();
    return J;
}

Mat6x18 strain_matrix(const Nodes& nodes, double xi, double eta, double zeta, double* det_j) {
    const Mat3x6 dN = shape_derivatives(xi, eta, zeta);
    const Mat3 J = jacobian(nodes, dN);
    const double det = J.determinant();
    CRACKLE_ASSERT(det > 0, "inverted or degenerate wedge (det J = " << det << ")");
    if (det_j) *det_j = det;
    // [N_xyz] = J⁻¹ [N_ξηζ] (Eqs. 5.39–5.40)
    const Mat3x6 dx = J.inverse() * dN;
    Mat6x18 B = Mat6x18::Zero();
    for (int i = 0; i < 6; ++i) {
        const double nx = dx(0, i), ny = dx(1, i), nz = dx(2, i);
        const int c = 3 * i;
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

Mat6 elasticity(double E, double nu) {
    // Eq. 5.32: D = E / ((1 + ν)(1 − 2ν)) · [[1−ν ν ν], [ν 1−ν ν], [ν ν 1−ν], (1−2ν)/2 · I₃]
    CRACKLE_ASSERT(E > 0 && nu > -1.0 && nu < 0.5, "invalid elastic constants E = " << E << ", nu = " << nu);
    const double c = E / ((1 + nu) * (1 - 2 * nu));
    Mat6 D = Mat6::Zero();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            D(i, j) = c * (i == j ? 1 - nu : nu);
    for (int i = 3; i < 6; ++i)
        D(i, i) = c * (1 - 2 * nu) / 2;
    return D;
}

Mat18 stiffness(const Nodes& nodes, double young, double poisson) {
    const Mat6 D = elasticity(young, poisson);
    Mat18 K = Mat18::Zero();
    for (const GaussPoint& g : quadrature()) {
        double det = 0;
        const Mat6x18 B = strain_matrix(nodes, g.xi, g.eta, g.zeta, &det);
        K.noalias() += (g.weight * det) * (B.transpose() * D * B);
    }
    // Symmetrize away round-off so CG sees an exactly symmetric matrix.
    return 0.5 * (K + K.transpose());
}

double volume(const Nodes& nodes) {
    double v = 0;
    for (const GaussPoint& g : quadrature())
        v += g.weight * jacobian(nodes, shape_derivatives(g.xi, g.eta, g.zeta)).determinant();
    return v;
}

Vec6 stress(const Nodes& reference, const Mat6& D, const Vec18& q, double xi, double eta, double zeta) {
    return D * (strain_matrix(reference, xi, eta, zeta) * q);
}

Mat3 tensor(const Vec6& s) {
    Mat3 t;
    t << s[0], s[5], s[4], //
        s[5], s[1], s[3],  //
        s[4], s[3], s[2];
    return t;
}

Principal max_principal(const Vec6& s) {
    Eigen::SelfAdjointEigenSolver<Mat3> eig;
    eig.computeDirect(tensor(s));
    return {eig.eigenvalues()[2], eig.eigenvectors().col(2)};
}

Vec18 flatten(const Nodes& nodes) {
    Vec18 v;
    for (std::size_t i = 0; i < 6; ++i)
        v.segment<3>(static_cast<Eigen::Index>(3 * i)) = nodes[i];
    return v;
}

} // namespace crackle::sim::wedge
