#pragma once
/// @file The 6-node wedge (prism) element of Federl 2002, §5.3 (digest §3.4): shape
/// functions, Jacobian, strain–displacement matrix B, isotropic elasticity D, the 9-point
/// quadrature of Table 5.1 with correctly normalised weights, the element stiffness K_e and
/// stresses. Nodes 0–2 are the bottom face (thesis nodes 1–3), 3–5 the top face (4–6).
/// Isoparametric coordinates: (ξ, η) on the unit triangle, ζ ∈ [−1, 1] through the thickness.

#include "core/math.hpp"

#include <array>

namespace crackle::sim::wedge {

using Nodes = std::array<Vec3, 6>;          ///< node positions, bottom 0..2, top 3..5
using Vec6 = Eigen::Matrix<double, 6, 1>;   ///< Voigt vector [xx, yy, zz, yz, zx, xy]
using Vec18 = Eigen::Matrix<double, 18, 1>; ///< nodal vector [x0 y0 z0 … x5 y5 z5]
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat6x18 = Eigen::Matrix<double, 6, 18>;
using Mat18 = Eigen::Matrix<double, 18, 18>;
using Mat3x6 = Eigen::Matrix<double, 3, 6>;

struct GaussPoint {
    double xi, eta, zeta, weight;
};

/// Table 5.1: 3-point triangle rule × 3-point Gauss–Legendre in ζ. The printed weights
/// (1/3 × {5/9, 8/9, 5/9}) sum to 2 although the reference wedge has volume 1 (triangle
/// area ½ × ζ-length 2): used as printed they double K_e, forces and strain energy (digest
/// §3.4 pitfall). These weights are ½ of the table's, so Σ w_g·det J_g is the volume.
/// Points 0–2 lie nearest the top face (ζ = +√(3/5)), 6–8 nearest the bottom.
const std::array<GaussPoint, 9>& quadrature();

/// The weights as printed in Table 5.1 (for the test that documents the erratum).
constexpr double TABLE_5_1_WEIGHT_SUM = 2.0;

/// Indices of the Gauss points nearest the top face, where cracks start (§5.6.1).
constexpr std::array<int, 3> TOP_GAUSS_POINTS = {0, 1, 2};

/// N_1..N_6 at (ξ, η, ζ) (Eqs. 5.9–5.14).
Vec6 shape_functions(double xi, double eta, double zeta);
/// ∂N/∂(ξ, η, ζ), 3 × 6 (Eq. 5.24).
Mat3x6 shape_derivatives(double xi, double eta, double zeta);

/// J = [N_ξηζ]·[Q]ᵀ, J_ij = ∂x_j/∂ξ_i (Eqs. 5.27–5.30).
Mat3 jacobian(const Nodes& nodes, const Mat3x6& dN);

/// B (6 × 18) at a point, rows (εx, εy, εz, γyz, γzx, γxy) with engineering shears
/// (Eqs. 5.33–5.37). Writes det J when asked.
Mat6x18 strain_matrix(const Nodes& nodes, double xi, double eta, double zeta, double* det_j = nullptr);

/// Isotropic D (Eq. 5.32).
Mat6 elasticity(double young, double poisson);

/// K_e = Σ_g w_g Bᵀ D B det J (Eqs. 5.25–5.26, 5.42), 18 × 18, symmetric PSD with the six
/// rigid-body modes as its null space.
Mat18 stiffness(const Nodes& nodes, double young, double poisson);
/// The same with any symmetric material matrix D (an edge-damaged one, below).
Mat18 stiffness(const Nodes& nodes, const Mat6& D);

// === Edge damage (graph-based FEM, digest §1.4–1.7 and §7; crackle's wedge adaptation)
//
// The graph's edges are the element's three top-triangle edges (the vertical faces it shares
// with its neighbours). Breaking edge k removes the in-plane strain along it: in the element's
// tangent frame, the in-plane engineering strain e = (εxx, εyy, γxy) maps to the edge strains
// ε_k = c_k²εxx + s_k²εyy + c_k s_k γxy (T, rows [c², s², cs]: exact on engineering strain,
// erratum E2), and Π = T⁻¹ Z T with Z = diag(1 − ζ_k) (erratum E1: ζ = 1 means broken, so the
// mask is 1 − ζ) zeroes the broken ones while keeping the others. εzz and the transverse shears
// are left alone, so a fully broken element still holds its top to the background and K stays
// positive definite. The damaged material matrix is ΠᵀDΠ (the double projection of Eqs. 21–22:
// symmetric, energy ½(Πε)ᵀD(Πε)); the edge tension conjugate to a broken edge's strain is zero.

/// Unit directions of the element's three edges (edge k: corner k → k + 1) on its mid-surface
/// triangle, and the unit normal of that triangle.
struct EdgeFrame {
    std::array<Vec3, 3> edge;
    Vec3 normal;
};
EdgeFrame edge_frame(const Nodes& nodes);

/// Π (6 × 6, global Voigt, engineering strains) removing the in-plane strain along the edges
/// whose bit is set in `broken` (bit k: edge k). Identity for broken = 0.
Mat6 edge_projector(const Nodes& nodes, unsigned broken);

/// ΠᵀDΠ: the material matrix of an element with broken edges.
Mat6 damaged_elasticity(const Mat6& D, const Mat6& projector);

/// The in-plane stress of an element as edge tensions t (Pa), σ_in = Σ_k t_k n_k n_kᵀ in the
/// element's frame (t = T⁻ᵀ σ_in): the stress each graph edge carries. A broken edge carries 0.
Vec3 edge_tensions(const Nodes& nodes, const Vec6& stress);

/// The rotation of engineering-strain Voigt vectors into a frame whose columns are R's:
/// ε_local = Q ε_global. Stresses (tensor Voigt) rotate with Q⁻ᵀ.
Mat6 strain_rotation(const Mat3& R);

/// Σ_g w_g det J_g: the element volume (exact for wedges with parallel triangles).
double volume(const Nodes& nodes);

/// The smallest det J over the stiffness' Gauss points: ≤ 0 when the wedge is inverted or flat.
double min_det_j(const Nodes& nodes);

/// σ = D·B·q at a point (Eq. 5.53); q = current − reference nodal positions.
Vec6 stress(const Nodes& reference, const Mat6& D, const Vec18& q, double xi, double eta, double zeta);

/// The symmetric 3 × 3 tensor of a Voigt stress vector.
Mat3 tensor(const Vec6& s);

/// Largest principal stress and its unit direction (tension positive).
struct Principal {
    double value;
    Vec3 direction;
};
Principal max_principal(const Vec6& s);

/// Stacks 6 nodal positions into an 18-vector.
Vec18 flatten(const Nodes& nodes);

} // namespace crackle::sim::wedge
