#pragma once
/// @file The 1D crack model of Federl 2002, Appendix A (thesis-digest §2.6): a bar of material
/// springs tied to a growing background by anchor springs. The continuous model (App. A.2)
/// gives closed forms for the positions, the tension and the break time of a fragment; the
/// discrete model (App. A.1) solves the spring network exactly and simulates the hierarchical
/// fracture of Figs. A.2–A.3 event by event, without time stepping.
///
/// Units: lengths in any unit L, forces in F, time in T. K_S is the stiffness of a spring of
/// unit rest length (F), K_A the anchor stiffness per unit length (F/L²), tensions are in F
/// (positive = tension) and rates in 1/T. x and X are reference (t = 0) coordinates.

#include "core/math.hpp"

#include <cstddef>
#include <vector>

namespace crackle::fracture::bar1d {

// === Material

/// Stiffnesses of the 1D layer (Federl 2002, App. A.1).
struct Stiffness {
    double K_S = 1.0;  ///< material spring stiffness per unit length: a sub-segment of size h has K_S/h (F)
    double K_A = 50.0; ///< anchor stiffness per unit length: each end of a sub-segment of size h has K_A·h/2 (F/L²)

    /// r = √(K_A/K_S) (1/L): the inverse decay length of the tension near a free end (Eq. A.6).
    double r() const { return std::sqrt(K_A / K_S); }
};

/// The break tension of a strain threshold: T_b = K_S·ε_b (F). A spring breaks when its tension
/// exceeds T_b, i.e. when its length exceeds h·(1 + ε_b) (digest §2.6.1, discretization-independent).
inline double break_tension(const Stiffness& stiffness, double break_strain) {
    return stiffness.K_S * break_strain;
}

// === Continuous model (Federl 2002, App. A.2)

/// The four boundary-condition types of App. A.2. A free end carries zero tension (p' = λ); an
/// end attached to a neighbouring fragment has a prescribed position Z.
enum class BoundaryType {
    FreeFree,   ///< I: no neighbours (Eq. A.11), p'(0) = λ, p'(l₀) = λ
    LeftFixed,  ///< II: left neighbour (Eq. A.12), p(0) = Z_L, p'(l₀) = λ
    RightFixed, ///< III: right neighbour (Eqs. A.13–A.14), p'(0) = λ, p(l₀) = Z_R
    BothFixed,  ///< IV: both neighbours (Eqs. A.15–A.16), p(0) = Z_L, p(l₀) = Z_R
};

struct Boundary {
    BoundaryType type = BoundaryType::FreeFree;
    double Z_L = 0.0; ///< p(0) for types II and IV (L)
    double Z_R = 0.0; ///< p(l₀) for types III and IV (L)
};

/// A fragment x ∈ [0, l₀] whose anchors lie uniformly between a₀ and a_n:
/// a(x) = a₀ + (a_n − a₀)·x/l₀.
struct Segment {
    double l0 = 1.0;     ///< reference length (L)
    double a0 = 0.0;     ///< anchor at x = 0 (L)
    double an = 1.0;     ///< anchor at x = l₀ (L)
    double lambda = 1.0; ///< rest length per unit reference length: 1 without shrinkage, 1 − s·t with it

    /// d = a_n − a₀ − λ·l₀ (L): how much the anchor span exceeds the rest length.
    double mismatch() const { return an - a0 - lambda * l0; }
};

/// p(x) = (a_n − a₀)·x/l₀ + a₀ + C₁·sinh(r·x) + C₂·cosh(r·x) (Eqs. A.5–A.6).
struct ContinuousSolution {
    Stiffness stiffness;
    Segment segment;
    double C1 = 0.0; ///< (L)
    double C2 = 0.0; ///< (L)
};

/// C₁ and C₂ of the four boundary types (digest §2.6.2 table, with 1 replaced by λ).
/// The hyperbolic terms cancel for large r·l₀: accurate to about ε·e^{r·l₀} relative.
/// @throws NumericError when sinh/cosh(r·l₀) overflow (r·l₀ ≳ 700).
ContinuousSolution solve_continuous(const Stiffness& stiffness, const Segment& segment, const Boundary& boundary);

/// p(x) (L), x ∈ [0, l₀].
double position(const ContinuousSolution& solution, double x);

/// p'(x) = (a_n − a₀)/l₀ + r·(C₁·cosh(r·x) + C₂·sinh(r·x)) (dimensionless).
double slope(const ContinuousSolution& solution, double x);

/// T(x) = K_S·(p'(x) − λ) (F).
double tension(const ContinuousSolution& solution, double x);

struct TensionPeak {
    double x = 0.0;       ///< location in [0, l₀] (L)
    double tension = 0.0; ///< T(x) (F)
};

/// The largest tension over [0, l₀]: the interior stationary point of p', where
/// p''(x) = 0 ⇔ tanh(r·x) = −C₂/C₁, if it lies inside (0, l₀), and the two end points.
/// Ties go to the smaller x.
TensionPeak max_tension(const ContinuousSolution& solution);

/// Type I in closed form (digest §2.6.2):
/// T(x) = K_S·d/l₀·[1 − cosh(r·(x − l₀/2)) / cosh(r·l₀/2)] (F).
double tension_free(const Stiffness& stiffness, double l0, double d, double x);

/// Type I: T_max = T(l₀/2) = K_S·d/l₀·(1 − sech(r·l₀/2)) (F): a free fragment breaks first at
/// its midpoint.
double max_tension_free(const Stiffness& stiffness, double l0, double d);

/// The break time of a free fragment of length l₀ under linear background growth
/// a(x, t) = x·(1 + g·t), i.e. d = l₀·g·t: t* = T_b / (K_S·g·(1 − sech(r·l₀/2))) (T).
/// Shrinkage at rate s gives the same t* with g = s (d = l₀·s·t).
double break_time_free(const Stiffness& stiffness, double l0, double growth_rate, double break_tension);

// === Discrete model (Federl 2002, App. A.1)

/// A bar of sub-segments j = 0 … #S−1, sub-segment j joining nodes j and j + 1.
///
/// Each sub-segment has a material spring of stiffness K_S/m_j and two anchor springs of
/// stiffness K_A·m_j/2, one at each end node (Eq. A.1; the bar's end nodes then satisfy the
/// free-end equations A.7–A.8). m_j = X_{j+1} − X_j is the sub-segment's reference (material)
/// size: it does not change with time, so the equilibrium is linear in the anchors and rest
/// lengths, and the tension reads T = K_S·(p' − λ) as in the continuous model.
///
/// A broken material spring has stiffness 0 but keeps its anchor springs: the fragment on
/// either side ends at the node next to the break, and that node keeps the anchor half of the
/// broken sub-segment, so each fragment is a free–free fragment reaching to the midpoint of
/// the broken spring (a cell-centred free end, second-order accurate, and no material lost).
struct DiscreteBar {
    Stiffness stiffness;
    std::vector<double> reference; ///< #N node reference coordinates X_i, strictly increasing (L)
    std::vector<double> anchors;   ///< #N current anchor positions a_i (L)
    std::vector<double> rest;      ///< #S = #N − 1 current rest lengths h_j of the material springs (L)
    std::vector<char> broken;      ///< #S 1 where the material spring is broken

    std::size_t num_nodes() const { return reference.size(); }
    std::size_t num_springs() const { return rest.size(); }
    /// m_j = X_{j+1} − X_j (L).
    double size(std::size_t j) const { return reference[j + 1] - reference[j]; }
    /// (X_j + X_{j+1})/2 (L): where a break of spring j is reported.
    double midpoint(std::size_t j) const { return 0.5 * (reference[j] + reference[j + 1]); }
};

/// n sub-segments of equal size h = l₀/n, X_i = i·h, rest lengths λ·h and uniform anchors
/// a_i = a₀ + (a_n − a₀)·X_i/l₀ (App. A.1).
DiscreteBar uniform_bar(const Stiffness& stiffness, int n, const Segment& segment);

/// Equilibrium node positions p (#N): the tridiagonal system of Eqs. A.1 and A.7–A.8,
///   Σ_springs (K_S/m)·[±(p_{i±1} − p_i) ∓ h] − c_i·(p_i − a_i) = 0, c_i = Σ K_A·m/2,
/// solved exactly by the Thomas algorithm (the matrix is strictly diagonally dominant).
/// @throws NumericError on a non-positive pivot (K_A = 0, or a sub-segment of size 0).
VecX equilibrium(const DiscreteBar& bar);

/// T_j = (K_S/m_j)·(p_{j+1} − p_j − h_j) (F), 0 for broken springs; #S.
VecX spring_tensions(const DiscreteBar& bar, const VecX& positions);

/// Sets spring j's stiffness to 0 (its anchor springs stay).
void break_spring(DiscreteBar& bar, std::size_t j);

/// Replaces intact sub-segment j by two halves (Fig. A.3b): a new node at the reference
/// midpoint with the mean anchor, rest length and size halved (so the series stiffness and the
/// total anchor stiffness are unchanged). Springs after j shift up by one index.
void subdivide(DiscreteBar& bar, std::size_t j);

// === Discrete fracture simulation (Figs. A.2–A.3)

/// Parameters of simulate(). The bar starts at t = 0 with n sub-segments of rest length
/// h₀ = l₀/n on anchors a_i = X_i, and evolves as
///   a(X, t) = X·(1 + g·t)            (background growth)
///   h_j(t) = m_j·(1 + (q − s)·t)      (rest-length growth q, Fig. A.3a, and shrinkage s).
struct SimulationOptions {
    Stiffness stiffness;
    int segments = 64;                 ///< n, initial number of sub-segments
    double length = 1.0;               ///< l₀ (L)
    double growth_rate = 0.0;          ///< g (1/T)
    double shrinkage_rate = 0.0;       ///< s (1/T); 1 + (q − s)·duration must stay positive
    double rest_growth_rate = 0.0;     ///< q (1/T)
    double break_tension = 0.01;       ///< T_b (F); see break_tension(stiffness, ε_b)
    double max_rest_length = 0.0;      ///< subdivide an intact sub-segment whose rest length reaches this (L); 0: never
    double duration = 1.0;             ///< simulate t ∈ [0, duration] (T)
    std::size_t max_events = 100000;   ///< stop (capped) after this many breaks
    std::size_t max_springs = 1 << 16; ///< stop (capped) when subdivision exceeds this many springs
};

/// A spring break.
struct BreakEvent {
    double time = 0.0;      ///< (T)
    double position = 0.0;  ///< reference midpoint of the broken spring (L)
    std::size_t spring = 0; ///< its index in the bar at that time (subdivision shifts indices)
    double ratio = 0.0;     ///< T/T_b when it broke: 1 at a threshold crossing, ≥ 1 in a cascade
};

struct SimulationResult {
    std::vector<BreakEvent> events; ///< in time order
    DiscreteBar bar;                ///< state at final_time
    VecX positions;                 ///< #N equilibrium positions at final_time (L)
    VecX tensions;                  ///< #S spring tensions at final_time (F)
    double final_time = 0.0;        ///< duration unless capped (T)
    std::size_t subdivisions = 0;
    bool capped = false; ///< stopped at max_events or max_springs before duration
};

/// Event-driven fracture of a free bar (Federl 2002, App. A.1, Figs. A.2–A.3).
/// At the current time: subdivide the intact sub-segments whose rest length has reached
/// max_rest_length; then, while some intact spring has T/T_b > 1, break only the most stressed
/// one (ties within a relative 1e-12 go to the lowest index) and re-solve. Otherwise jump to
/// the next event. Between events the tensions are affine in t, T_j(t) = T_j + Ṫ_j·(t − t₀),
/// because the equilibrium is linear in the anchors and rest lengths, which move linearly; Ṫ
/// is the equilibrium of the rates (ȧ = g·X, ḣ = (q − s)·m). So the next break is the exact
/// earliest crossing T_j(t) = T_b (ties again to the lowest index), and the next subdivision
/// is m_j·(1 + (q − s)·t) = max_rest_length.
/// @throws InputError for non-positive stiffnesses, length, segments or T_b, a negative
/// duration or max_rest_length, non-finite rates, or rest lengths that would shrink to zero
/// before the end.
SimulationResult simulate(const SimulationOptions& options);

} // namespace crackle::fracture::bar1d
