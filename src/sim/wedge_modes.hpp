#pragma once
/// @file The wedge with a richer displacement through the thickness: the thesis' 6-node wedge
/// (Federl 2002, §5.3) is linear in ζ, so εzz is constant through the layer. That locks the
/// Poisson contraction a shrinkage gradient needs (the top stress of a layer whose shrinkage
/// varies with depth comes out about 11 % high at ν = 0.3) and stiffens the layer next to a crack
/// (a channel crack releases 17 % less energy than in plane-strain elasticity). Order p adds, at
/// each corner c of the triangle, the hierarchical modes L_c(ξ, η)·φ_k(ζ), k = 2..p, with
/// φ₂ = 1 − ζ² and φ₃ = ζ(1 − ζ²) (integrated-Legendre-like bubbles that vanish on the top and
/// bottom faces): the displacement is then a polynomial of degree p through the thickness,
/// conforming between elements (the amplitudes are per vertex). Solid-shell elements fix the
/// same locking with a linear thickness strain (Bischoff & Ramm 1997); conforming modes also let
/// the crack faces bulge, which the energy release needs. The geometry stays the 6-node wedge.
///
/// Element DOF order: bottom corners (9), top corners (9), then per mode k = 2..p the three
/// corners' amplitudes (9 each, metres at the mode's peak): 9 + 9p in all. For p = 1 this is the
/// thesis' wedge, and FemModel uses wedge_element.hpp's functions unchanged.

#include "sim/wedge_element.hpp"

namespace crackle::sim::wedge {

constexpr int MAX_THICKNESS_ORDER = 3;

/// Element DOFs for through-thickness order p: 18 for the linear wedge, 9 more per mode.
constexpr int element_dofs(int order) {
    return 9 + 9 * order;
}

/// φ_k(ζ) and dφ_k/dζ for mode k ∈ {2, 3}.
double mode_shape(int k, double zeta);
double mode_slope(int k, double zeta);

/// The quadrature of order 3: Table 5.1's triangle rule × 4-point Gauss–Legendre in ζ (exact
/// for its degree-6 products on a prism; order 2 needs only Table 5.1's three points), weights
/// normalised so that Σ w·det J is the volume.
const std::array<GaussPoint, 12>& quadrature_high();

/// B (6 × (9 + 9p)) at a point, the strain of every DOF (rows as strain_matrix()).
MatX strain_matrix(const Nodes& nodes, int order, double xi, double eta, double zeta, double* det_j = nullptr);

/// K_e = Σ_g w_g Bᵀ D B det J, (9 + 9p)²; for order 1 it equals stiffness(nodes, D).
MatX stiffness(const Nodes& nodes, const Mat6& D, int order);

/// σ = D·B·q at a point; q holds the element DOFs in the order above.
Vec6 stress(const Nodes& reference, const Mat6& D, const VecX& q, int order, double xi, double eta, double zeta);

} // namespace crackle::sim::wedge
