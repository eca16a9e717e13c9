#include "support/cross_section.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace crackle::test::oracle {

namespace {

using Matrix18 = Eigen::Matrix<double, 18, 18>;
using Vector18 = Eigen::Matrix<double, 18, 1>;
using Strain18 = Eigen::Matrix<double, 3, 18>;

/// Lamé constants of an isotropic material: λ = E·ν/((1 + ν)(1 − 2ν)), μ = E/(2(1 + ν)).
struct Lame {
    double lambda = 0;
    double mu = 0;
};

Lame lame(double E, double nu) {
    return {E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))};
}

/// Corner coordinates 0 = t₀ < … < tₙ = length of one graded axis: sizes smallest·h·growthⁱ,
/// capped at largest·max(h, t), then all scaled by one factor so the last corner lands on
/// `length` (the last size is kept or dropped, whichever leaves the smaller correction).
std::vector<double> graded_axis(double length, double h, const Grading& g) {
    std::vector<double> sizes;
    double position = 0, size = g.smallest * h;
    while (true) {
        const double step = std::min(size, g.largest * std::max(h, position));
        if (position + step >= length) {
            if (sizes.empty() || position + 0.5 * step < length) {
                sizes.push_back(step);
                position += step;
            }
            break;
        }
        sizes.push_back(step);
        position += step;
        size *= g.growth;
    }
    std::vector<double> corners{0.0};
    for (double s : sizes)
        corners.push_back(corners.back() + s * length / position);
    corners.back() = length;
    return corners;
}

/// Node coordinates of 3-node (quadratic) segments on the given corners: corners and midpoints.
std::vector<double> with_midpoints(const std::vector<double>& corners) {
    std::vector<double> nodes;
    for (std::size_t i = 0; i + 1 < corners.size(); ++i) {
        nodes.push_back(corners[i]);
        nodes.push_back(0.5 * (corners[i] + corners[i + 1]));
    }
    nodes.push_back(corners.back());
    return nodes;
}

/// Tensor-product mesh: node (i, j) sits at (x[i], z[j]); element (ex, ez) has the nodes
/// i = 2·ex + a, j = 2·ez + b for a, b ∈ {0, 1, 2}.
struct Mesh {
    std::vector<double> x, z;
    int interface_row = 0; ///< j of the nodes at z = 0
    int nx() const { return int(x.size()); }
    int nz() const { return int(z.size()); }
    int node(int i, int j) const { return j * nx() + i; }
    int elements_x() const { return (nx() - 1) / 2; }
    int elements_z() const { return (nz() - 1) / 2; }
};

Mesh build_mesh(const CrossSection& s) {
    const double h = s.film.thickness;
    Mesh m;
    m.x = with_midpoints(graded_axis(0.5 * s.spacing, h, s.grading));
    std::vector<double> corners;
    if (!s.substrate.rigid) {
        const std::vector<double> depth = graded_axis(s.substrate.depth, h, s.grading);
        for (auto d = depth.rbegin(); d != depth.rend() - 1; ++d)
            corners.push_back(-*d);
    }
    for (double zf : graded_axis(h, h, s.grading))
        corners.push_back(zf);
    m.z = with_midpoints(corners);
    m.interface_row = int(std::find(m.z.begin(), m.z.end(), 0.0) - m.z.begin());
    return m;
}

// Quadratic Lagrange shape functions on ξ ∈ [−1, 1] with nodes at −1, 0, 1, and their
// derivatives; the 9-node element uses their tensor products (the Lagrange family of Zienkiewicz & Taylor, The Finite
// Element Method).
std::array<double, 3> shape(double t) {
    return {0.5 * t * (t - 1), 1 - t * t, 0.5 * t * (t + 1)};
}
std::array<double, 3> shape_derivative(double t) {
    return {t - 0.5, -2 * t, t + 0.5};
}

// 3-point Gauss–Legendre rule on [−1, 1].
const std::array<double, 3> GAUSS_POINT{-0.7745966692414834, 0.0, 0.7745966692414834};
const std::array<double, 3> GAUSS_WEIGHT{5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};

/// One Gauss point of a rectangular element [x0, x1] × [z0, z1]: strain–displacement matrix B
/// (rows ε_xx, ε_zz, γ_xz; columns u_x, u_z of local node 3·b + a), height and weight·det J.
struct GaussPoint {
    Strain18 B = Strain18::Zero();
    double z = 0;
    double weight = 0;
};

GaussPoint gauss_point(double x0, double x1, double z0, double z1, int p, int q) {
    GaussPoint g;
    const double dx = x1 - x0, dz = z1 - z0;
    const std::array<double, 3> Nx = shape(GAUSS_POINT[p]), Nz = shape(GAUSS_POINT[q]);
    const std::array<double, 3> dNx = shape_derivative(GAUSS_POINT[p]), dNz = shape_derivative(GAUSS_POINT[q]);
    for (int b = 0; b < 3; ++b)
        for (int a = 0; a < 3; ++a) {
            const int k = 3 * b + a;
            const double ddx = dNx[a] * Nz[b] * 2 / dx, ddz = Nx[a] * dNz[b] * 2 / dz;
            g.B(0, 2 * k) = ddx;
            g.B(1, 2 * k + 1) = ddz;
            g.B(2, 2 * k) = ddz;
            g.B(2, 2 * k + 1) = ddx;
        }
    g.z = z0 + 0.5 * (GAUSS_POINT[q] + 1) * dz;
    g.weight = GAUSS_WEIGHT[p] * GAUSS_WEIGHT[q] * dx * dz / 4;
    return g;
}

/// Everything the solver needs per element: corners, local-to-global dofs and material.
struct Element {
    double x0, x1, z0, z1;
    std::array<int, 18> dofs;
    Lame material;
    bool film;
};

Element element(const Mesh& m, const CrossSection& s, int ex, int ez) {
    Element e{};
    e.x0 = m.x[2 * ex];
    e.x1 = m.x[2 * ex + 2];
    e.z0 = m.z[2 * ez];
    e.z1 = m.z[2 * ez + 2];
    for (int b = 0; b < 3; ++b)
        for (int a = 0; a < 3; ++a) {
            const int n = m.node(2 * ex + a, 2 * ez + b);
            e.dofs[2 * (3 * b + a)] = 2 * n;
            e.dofs[2 * (3 * b + a) + 1] = 2 * n + 1;
        }
    e.film = e.z0 >= 0;
    e.material = e.film ? lame(s.film.young, s.film.poisson) : lame(s.substrate.young, s.substrate.poisson);
    return e;
}

/// Film shrinkage s(z), linear from s_bottom at z = 0 to s_top at z = h.
double shrinkage(const Film& f, double z) {
    return f.shrinkage_bottom + (f.shrinkage_top - f.shrinkage_bottom) * z / f.thickness;
}

/// Plane-strain elasticity in the (ε_xx, ε_zz, γ_xz) basis: D = [λ+2μ λ 0; λ λ+2μ 0; 0 0 μ].
Eigen::Matrix3d plane_strain(const Lame& L) {
    Eigen::Matrix3d D;
    D << L.lambda + 2 * L.mu, L.lambda, 0, L.lambda, L.lambda + 2 * L.mu, 0, 0, 0, L.mu;
    return D;
}

/// Element stiffness Kₑ = Σ Bᵀ·D·B·w·det J and eigenstrain load fₑ = Σ Bᵀ·(C:ε*)·w·det J,
/// where ε* = −s·I gives the in-plane components C:ε* = −(3λ + 2μ)·s·(1, 1, 0) (the y
/// component of ε* is held by the plane-strain constraint and enters the energy only).
void element_system(const Element& e, const Film& film, Matrix18& K, Vector18& f) {
    const Eigen::Matrix3d D = plane_strain(e.material);
    K.setZero();
    f.setZero();
    for (int q = 0; q < 3; ++q)
        for (int p = 0; p < 3; ++p) {
            const GaussPoint g = gauss_point(e.x0, e.x1, e.z0, e.z1, p, q);
            K += g.B.transpose() * D * g.B * g.weight;
            if (!e.film) continue;
            const double s = shrinkage(film, g.z);
            const Eigen::Vector3d eigenstress =
                -(3 * e.material.lambda + 2 * e.material.mu) * s * Eigen::Vector3d(1, 1, 0);
            f += g.B.transpose() * eigenstress * g.weight;
        }
}

/// Strain energy of one element, ∫ ½·(ε − ε*):C:(ε − ε*) dA over all three dimensions with
/// ε_yy = 0: ½·[λ·(tr e)² + 2μ·(e_xx² + e_yy² + e_zz²) + μ·γ_xz²], e = ε − ε* = ε + s·I.
double element_energy(const Element& e, const Film& film, const Eigen::VectorXd& u) {
    Vector18 ue;
    for (int k = 0; k < 18; ++k)
        ue[k] = u[e.dofs[k]];
    double energy = 0;
    for (int q = 0; q < 3; ++q)
        for (int p = 0; p < 3; ++p) {
            const GaussPoint g = gauss_point(e.x0, e.x1, e.z0, e.z1, p, q);
            const Eigen::Vector3d strain = g.B * ue;
            const double s = e.film ? shrinkage(film, g.z) : 0.0;
            const double exx = strain[0] + s, eyy = s, ezz = strain[1] + s, gxz = strain[2];
            const double trace = exx + eyy + ezz;
            const Lame& L = e.material;
            energy += 0.5
                      * (L.lambda * trace * trace + 2 * L.mu * (exx * exx + eyy * eyy + ezz * ezz) + L.mu * gxz * gxz)
                      * g.weight;
        }
    return energy;
}

/// Solves K·u = f with the dofs marked in `fixed` held at zero (Eigen's simplicial LDLᵀ with
/// AMD ordering).
Eigen::VectorXd solve(const Eigen::SparseMatrix<double>& K, const Eigen::VectorXd& f, const std::vector<bool>& fixed,
                      int& free_count) {
    std::vector<int> index(fixed.size(), -1);
    free_count = 0;
    for (std::size_t d = 0; d < fixed.size(); ++d)
        if (!fixed[d]) index[d] = free_count++;
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(std::size_t(K.nonZeros()));
    for (int col = 0; col < K.outerSize(); ++col)
        for (Eigen::SparseMatrix<double>::InnerIterator it(K, col); it; ++it)
            if (index[std::size_t(it.row())] >= 0 && index[std::size_t(col)] >= 0)
                entries.emplace_back(index[std::size_t(it.row())], index[std::size_t(col)], it.value());
    Eigen::SparseMatrix<double> Kf(free_count, free_count);
    Kf.setFromTriplets(entries.begin(), entries.end());
    Eigen::VectorXd ff(free_count);
    for (std::size_t d = 0; d < fixed.size(); ++d)
        if (index[d] >= 0) ff[index[d]] = f[Eigen::Index(d)];
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(Kf);
    if (ldlt.info() != Eigen::Success) throw std::runtime_error("cross_section: LDLT factorization failed");
    const Eigen::VectorXd uf = ldlt.solve(ff);
    Eigen::VectorXd u = Eigen::VectorXd::Zero(f.size());
    for (std::size_t d = 0; d < fixed.size(); ++d)
        if (index[d] >= 0) u[Eigen::Index(d)] = uf[index[d]];
    return u;
}

void check_input(const CrossSection& s) {
    const auto poisson_ok = [](double nu) { return nu > -1 && nu < 0.5; };
    const bool ok =
        s.film.thickness > 0 && s.film.young > 0 && poisson_ok(s.film.poisson) && s.spacing > 0
        && s.grading.smallest > 0 && s.grading.growth > 1 && s.grading.largest > 0
        && (s.substrate.rigid || (s.substrate.depth > 0 && s.substrate.young > 0 && poisson_ok(s.substrate.poisson)));
    if (!ok)
        throw std::invalid_argument("cross_section: thickness, moduli, spacing and grading must be positive, "
                                    "-1 < ν < 0.5 and growth > 1");
}

} // namespace

ChannelResult channel_crack(const CrossSection& section) {
    check_input(section);
    const Mesh mesh = build_mesh(section);
    const Film& film = section.film;
    const int dofs = 2 * mesh.nx() * mesh.nz();

    // === Assemble K and the eigenstrain load f over all nodes
    std::vector<Element> elements;
    for (int ez = 0; ez < mesh.elements_z(); ++ez)
        for (int ex = 0; ex < mesh.elements_x(); ++ex)
            elements.push_back(element(mesh, section, ex, ez));
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(elements.size() * 18 * 18);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(dofs);
    Matrix18 Ke;
    Vector18 fe;
    for (const Element& e : elements) {
        element_system(e, film, Ke, fe);
        for (int a = 0; a < 18; ++a) {
            f[e.dofs[a]] += fe[a];
            for (int b = 0; b < 18; ++b)
                entries.emplace_back(e.dofs[a], e.dofs[b], Ke(a, b));
        }
    }
    Eigen::SparseMatrix<double> K(dofs, dofs);
    K.setFromTriplets(entries.begin(), entries.end());

    // === Boundary conditions shared by both states
    std::vector<bool> fixed(std::size_t(dofs), false);
    const auto fix = [&](int i, int j, int component) { fixed[std::size_t(2 * mesh.node(i, j) + component)] = true; };
    for (int j = 0; j < mesh.nz(); ++j)
        fix(mesh.nx() - 1, j, 0); // symmetry midway between channels, x = W/2
    for (int i = 0; i < mesh.nx(); ++i) {
        fix(i, 0, 0); // rigid base at z = 0, or the substrate's fixed bottom at z = −H_s
        fix(i, 0, 1);
    }
    for (int j = 0; j <= mesh.interface_row; ++j)
        fix(0, j, 0); // symmetry under the film, x = 0, z ≤ 0 (the crack root included)

    // === Cracked (x = 0 face of the film free) and uncracked (u_x = 0 there) states
    ChannelResult r;
    r.elements = int(elements.size());
    const Eigen::VectorXd u_cracked = solve(K, f, fixed, r.free_dofs);
    for (int j = mesh.interface_row; j < mesh.nz(); ++j)
        fix(0, j, 0);
    int uncracked_dofs = 0;
    const Eigen::VectorXd u_uncracked = solve(K, f, fixed, uncracked_dofs);
    for (const Element& e : elements) {
        r.energy_cracked += element_energy(e, film, u_cracked);
        r.energy_uncracked += element_energy(e, film, u_uncracked);
    }

    // === G_ss, Z and the opening profile (the x = 0 face moves by u_x; its mirror by −u_x)
    const double h = film.thickness, E = film.young, nu = film.poisson;
    r.release_rate = 2 * (r.energy_uncracked - r.energy_cracked) / h;
    const double sigma = E * 0.5 * (film.shrinkage_bottom + film.shrinkage_top) / (1 - nu);
    const double E_bar = E / (1 - nu * nu);
    r.z = r.release_rate * E_bar / (sigma * sigma * h);
    for (int j = mesh.interface_row; j < mesh.nz(); ++j) {
        r.opening_z.push_back(mesh.z[std::size_t(j)]);
        r.opening.push_back(2 * u_cracked[2 * mesh.node(0, j)]);
    }
    return r;
}

double channel_z_rigid(double nu, double spacing) {
    CrossSection s;
    s.film.poisson = nu;
    s.spacing = spacing * s.film.thickness;
    return channel_crack(s).z;
}

} // namespace crackle::test::oracle
