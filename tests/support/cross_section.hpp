#pragma once
/// @file An independent oracle for the steady-state channelling energy release rate of a film:
/// a 2D plane-strain finite-element model of the cross-section perpendicular to a channel crack
/// (Beuth 1992, Int. J. Solids Struct. 29:1657; Hutchinson & Suo 1992, Adv. Appl. Mech. 29:63,
/// channel cracking). It shares no code with crackle's wedge FEM (src/sim, src/fracture): Eigen only.
///
/// Geometry (z up, x across the channel): the film occupies 0 ≤ z ≤ h, bonded at z = 0 to a
/// rigid base or to an elastic substrate −H_s ≤ z ≤ 0 whose bottom is fixed. Channels of spacing
/// W repeat along x; by symmetry only the half-cell 0 ≤ x ≤ W/2 is modelled, with u_x = 0 at
/// x = W/2. The channel crack cuts the whole film at x = 0: cracked, the film's x = 0 face is
/// traction free; uncracked, u_x = 0 there. Under the film, x = 0 is always a symmetry plane.
/// Along the channel (y) the total strain is 0 (plane strain).
///
/// Steady-state channelling (Hutchinson & Suo 1992): far behind the tip the section is
/// cracked, far ahead it is not, so a channel advancing by da releases the difference of the two
/// sections' energies over one period W (two half-cells), G_ss·h·da = [U(uncracked) − U(cracked)]·da.

#include <vector>

namespace crackle::test::oracle {

/// The film. Its stress-free strain is the isotropic eigenstrain ε* = −s(z)·I (shrinkage s > 0
/// puts the bonded film in tension), with s linear from `shrinkage_bottom` at z = 0 to
/// `shrinkage_top` at z = h.
struct Film {
    double thickness = 1.0;         ///< h (m)
    double young = 1.0;             ///< E_f (Pa)
    double poisson = 0.3;           ///< ν_f
    double shrinkage_bottom = 1e-3; ///< s at z = 0
    double shrinkage_top = 1e-3;    ///< s at z = h
};

/// What the film is bonded to: a rigid base (every node at z = 0 fixed) or an elastic substrate
/// of depth H_s whose bottom (z = −H_s) is fixed.
struct Substrate {
    bool rigid = true;
    double depth = 40.0;  ///< H_s (m), elastic substrate only
    double young = 1.0;   ///< E_s (Pa)
    double poisson = 0.3; ///< ν_s
};

/// Tensor-product mesh of 9-node quadrilaterals, graded geometrically towards the crack root
/// (x = 0, z = 0), where the stress is singular. Along each axis the element sizes are
/// smallest·h, ×growth per element, capped at largest·max(h, distance from the root).
struct Grading {
    double smallest = 1e-4; ///< size of the elements at the root, in units of h
    double growth = 1.4;    ///< size ratio of neighbouring elements (> 1)
    double largest = 0.5;   ///< cap on an element's size relative to max(h, its distance from the root)
};

/// One cross-section: film, what it is bonded to, crack spacing W and mesh.
struct CrossSection {
    Film film;
    Substrate substrate;
    double spacing = 20.0; ///< W (m), distance between neighbouring channels
    Grading grading;
};

/// Both states of one cross-section.
struct ChannelResult {
    double energy_uncracked = 0; ///< U strain energy per unit channel length of the half-cell 0 ≤ x ≤ W/2 (J/m)
    double energy_cracked = 0;   ///< the same with the crack open (J/m)
    /// G_ss (J/m²): one period holds two half-cells, so G_ss = 2·(U_uncracked − U_cracked)/h.
    double release_rate = 0;
    /// Z = G_ss·Ē_f/(σ²·h) with Ē_f = E_f/(1 − ν_f²) and σ = E_f·s̄/(1 − ν_f), s̄ the film's mean
    /// shrinkage (for uniform shrinkage σ is the uncracked biaxial stress).
    double z = 0;
    std::vector<double> opening_z; ///< heights of the film's nodes on the crack face, 0 … h (m)
    /// δ(z): full crack opening (both faces) at those heights (m); nodes come in element triples
    /// (corner, mid-side, corner), so δ is piecewise quadratic between them.
    std::vector<double> opening;
    int elements = 0;  ///< number of 9-node elements
    int free_dofs = 0; ///< unknowns of the cracked state
};

/// Solves the uncracked and cracked cross-sections and returns their energies, G_ss, Z and the
/// crack-opening profile. Throws std::invalid_argument on a nonsensical input and
/// std::runtime_error if a factorization fails.
ChannelResult channel_crack(const CrossSection& section);

/// Z of a channel in a uniformly shrinking film on a rigid base, channels W = `spacing`·h apart
/// (20 h by default: isolated, as the film's stress recovers within a few h of a crack). Z
/// depends on ν and W/h only. The default Grading (775 elements at W = 20 h) is within 0.01 % of
/// finer meshes and takes about 0.05 s of CPU.
double channel_z_rigid(double nu, double spacing = 20.0);

} // namespace crackle::test::oracle
