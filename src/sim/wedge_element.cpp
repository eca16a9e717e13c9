#include "sim/wedge_element.hpp"

#include "core/error.hpp"
#include "sim/wedge_btdb.hpp"

#include <Eigen/Eigenvalues>

#include <limits>

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
    return stiffness(nodes, elasticity(young, poisson));
}

Mat18 stiffness(const Nodes& nodes, const Mat6& D) {
    Mat18 K = Mat18::Zero();
    for (const GaussPoint& g : quadrature()) {
        const Mat3x6 dN = shape_derivatives(g.xi, g.eta, g.zeta);
        const Mat3 J = jacobian(nodes, dN);
        const double det = J.determinant();
        CRACKLE_ASSERT(det > 0, "inverted or degenerate wedge (det J = " << det << ")");
        const Mat3x6 dx = J.inverse() * dN;
        detail::add_btdb<6>(dx, D, g.weight * det, K); // B as in strain_matrix (Eqs. 5.39–5.41)
    }
    K.triangularView<Eigen::StrictlyLower>() = K.transpose(); // exactly symmetric, so CG sees it so
    return K;
}

double min_det_j(const Nodes& nodes) {
    double smallest = std::numeric_limits<double>::infinity();
    for (const GaussPoint& g : quadrature())
        smallest = std::min(smallest, jacobian(nodes, shape_derivatives(g.xi, g.eta, g.zeta)).determinant());
    return smallest;
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

// === Edge damage

namespace {

/// Engineering-strain Voigt vector ↔ symmetric tensor.
Mat3 strain_tensor(const Vec6& e) {
    Mat3 t;
    t << e[0], 0.5 * e[5], 0.5 * e[4], //
        0.5 * e[5], e[1], 0.5 * e[3],  //
        0.5 * e[4], 0.5 * e[3], e[2];
    return t;
}

Vec6 strain_voigt(const Mat3& t) {
    Vec6 e;
    e << t(0, 0), t(1, 1), t(2, 2), 2 * t(1, 2), 2 * t(2, 0), 2 * t(0, 1);
    return e;
}

/// The element's tangent frame (columns e₁, e₂, n; e₁ along edge 0) and T, the in-plane edge
/// strains from (εxx, εyy, γxy) in that frame.
struct InPlane {
    Mat3 R;
    Mat3 T;
};

InPlane in_plane(const Nodes& nodes) {
    const EdgeFrame f = edge_frame(nodes);
    InPlane p;
    const Vec3 e1 = f.edge[0], e2 = f.normal.cross(e1);
    p.R.col(0) = e1;
    p.R.col(1) = e2;
    p.R.col(2) = f.normal;
    for (int k = 0; k < 3; ++k) {
        const double c = f.edge[static_cast<std::size_t>(k)].dot(e1), s = f.edge[static_cast<std::size_t>(k)].dot(e2);
        p.T.row(k) << c * c, s * s, c * s;
    }
    return p;
}

} // namespace

EdgeFrame edge_frame(const Nodes& nodes) {
    std::array<Vec3, 3> mid;
    for (std::size_t k = 0; k < 3; ++k)
        mid[k] = 0.5 * (nodes[k] + nodes[k + 3]);
    EdgeFrame f;
    for (std::size_t k = 0; k < 3; ++k)
        f.edge[k] = (mid[(k + 1) % 3] - mid[k]).normalized();
    f.normal = (mid[1] - mid[0]).cross(mid[2] - mid[0]).normalized();
    return f;
}

Mat6 strain_rotation(const Mat3& R) {
    Mat6 Q;
    for (int i = 0; i < 6; ++i)
        Q.col(i) = strain_voigt(R.transpose() * strain_tensor(Vec6::Unit(i)) * R);
    return Q;
}

Mat6 edge_projector(const Nodes& nodes, unsigned broken) {
    if ((broken & 7u) == 0) return Mat6::Identity();
    const InPlane p = in_plane(nodes);
    Mat3 Z = Mat3::Zero();
    for (int k = 0; k < 3; ++k)
        Z(k, k) = (broken >> k) & 1u ? 0.0 : 1.0;
    const Mat3 P = p.T.inverse() * Z * p.T; // in-plane block of Π, acting on (εxx, εyy, γxy)
    // Local Voigt order (xx, yy, zz, yz, zx, xy): the in-plane components are 0, 1 and 5.
    constexpr std::array<int, 3> in = {0, 1, 5};
    Mat6 local = Mat6::Identity();
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            local(in[static_cast<std::size_t>(i)], in[static_cast<std::size_t>(j)]) = P(i, j);
    const Mat6 Q = strain_rotation(p.R);
    return Q.inverse() * local * Q;
}

Mat6 damaged_elasticity(const Mat6& D, const Mat6& projector) {
    const Mat6 Dd = projector.transpose() * D * projector;
    return 0.5 * (Dd + Dd.transpose());
}

Vec3 edge_tensions(const Nodes& nodes, const Vec6& stress) {
    const InPlane p = in_plane(nodes);
    const Mat3 local = p.R.transpose() * tensor(stress) * p.R;
    return p.T.transpose().inverse() * Vec3(local(0, 0), local(1, 1), local(0, 1));
}

Vec18 flatten(const Nodes& nodes) {
    Vec18 v;
    for (std::size_t i = 0; i < 6; ++i)
        v.segment<3>(static_cast<Eigen::Index>(3 * i)) = nodes[i];
    return v;
}

} // namespace crackle::sim::wedge
