#pragma once
/// @file Pattern statistics (thesis-digest §7.1): the measurable proxies that tests and
/// `crackle simulate --json` report, with the field names of design.md.

#include "core/math.hpp"
#include "fracture/crack_pattern.hpp"

#include <vector>

namespace crackle::fracture {

/// A crack segment in the surface's local 2D frame (texture space in metres: x along u,
/// y along v), reference configuration.
struct CrackSegment {
    Vec2 a, b;              ///< end points (unwrapped: b − a is the true segment)
    double weight = 1;      ///< ½ for each lip of a crack, so lips add up to the crack length
    Vec2 uv = Vec2::Zero(); ///< texture coordinates of the midpoint
    double length() const { return (b - a).norm(); }
};

struct PatternStatistics {
    int fragments = 0;
    double total_area = 0;            ///< reference surface area (m²)
    double mean_fragment_area = 0;    ///< m²
    double fragment_area_cv = 0;      ///< standard deviation / mean of the fragment areas (0 with < 2)
    double crack_length = 0;          ///< m
    double crack_length_per_area = 0; ///< ρ_c (1/m)
    double anisotropy = 0;            ///< (λ1 − λ2)/(λ1 + λ2) of the orientation tensor, 0..1
    double dominant_angle_deg = 0;    ///< direction of the dominant crack tangent from u, [0, 180)
    double psi6 = 0;                  ///< |Σ ℓ e^{6iθ}| / Σ ℓ: 1 for 60°-locked cracks
    double axial_fraction = 0;        ///< share of crack length within 30° of the v axis
    int junctions = 0;                ///< crack-network nodes of degree 3
    double t_junction_fraction = 0;   ///< one angle ≈ 180°, two ≈ 90°
    double y_junction_fraction = 0;   ///< all three ≈ 120°
    double min_angle_deg = 0;         ///< worst intact triangle
};

/// Crack lips: every edge of an intact face whose other side is removed or split off.
std::vector<CrackSegment> crack_segments(const CrackPattern& pattern);

PatternStatistics pattern_statistics(const CrackPattern& pattern);

/// The shape of the crack paths (digest §7.1, Fig. 5.31: "cracks are no longer straight").
/// The crack network (the graph of the junction statistics) is cut into chains at its nodes
/// of degree ≠ 2 (junctions and ends); a closed chain without such nodes counts when it wraps
/// around the periodic domain (its end-to-end distance is the period) and is skipped when it
/// does not. Reference configuration; distances are minimum-image on periodic surfaces.
struct CrackPathStatistics {
    int chains = 0;             ///< chains measured (≥ min_chain_length)
    double tortuosity = 1;      ///< Σ chain length / Σ end-to-end distance (≥ 1; 1 when straight)
    double mean_tortuosity = 1; ///< unweighted mean over chains of length / end-to-end distance
    double orientation_spread_deg =
        0; ///< √(Σ ℓ δ² / Σ ℓ), δ ∈ [0°, 90°] between a crack segment and the dominant direction
};

/// Tortuosity of the chains whose path length is at least `min_chain_length` (m; short stubs
/// between nearby junctions are straight by construction), and the orientation spread of all
/// crack segments (crack_segments()).
CrackPathStatistics crack_path_statistics(const CrackPattern& pattern, double min_chain_length = 0.0);

/// Junction classification from the angles between the three branches (degrees, summing
/// to 360): T when the largest is ≥ 155°, Y when all lie in [95°, 145°].
enum class JunctionKind { T, Y, Other };
JunctionKind classify_junction(double a, double b, double c);

} // namespace crackle::fracture
