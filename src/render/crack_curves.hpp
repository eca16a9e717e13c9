#pragma once
/// @file Crack curves for the relief (issue 35): the simulation's crack chains (element-scale
/// polylines) smoothed into curves and given a sub-element wander, so that at any map size a
/// crack reads as a crack, not as a polygon.
///  - Smoothing: corner cutting (Chaikin 1974: each pass replaces a corner by the points ¼ and ¾
///    along its edges; the limit is the quadratic B-spline of the polyline, tangent-continuous),
///    with the chain's ends pinned, so junctions stay where they are (a T stays a T, a Y a Y) and
///    tips do not retract; closed loops are cut all round. No point moves more than a quarter of
///    its longer neighbouring edge.
///  - Wander: an offset along the curve's normal, two octaves of 1D gradient noise with a
///    wavelength and amplitude in metres, seeded per chain, faded to zero over a wavelength at
///    pinned ends; amplitude × 2π / wavelength < 1, so a curve never loops on itself.
///  - Attributes per point: the weight of the crack (first and widest cracks 1, the last
///    1 − crack_age, scaled by the opening where simulated, as the raster's), its age, the
///    simulated opening, and the taper towards a tip (0 at the tip, 1 a tip length away).

#include "post/pieces.hpp"

#include <cstdint>
#include <vector>

namespace crackle::render {

struct CurveOptions {
    double wander = 0;            ///< m: amplitude of the sub-element wander (0 = none)
    double wander_wavelength = 0; ///< m: its wavelength (0 = 4 × the element size)
    double tip_length = 0;        ///< m: how far from a tip the groove tapers (0 = no taper)
    double crack_age = 0.6;       ///< how much finer the last cracks are than the first (0..1)
    double step_px = 2.0;         ///< the curves' segment length at most, in pixels
    double metres_per_px = 1e-3;  ///< the map's pixel size (m) at the equator
    std::uint32_t seed = 1;
};

/// A smoothed crack curve: points in texture coordinates (unwrapped along the curve) with
/// their attributes.
struct CrackCurve {
    std::vector<Vec2> uv;
    std::vector<float> weight;                ///< 1 for the first, widest cracks, down to 1 − crack_age
    std::vector<float> age;                   ///< 1 = the first crack, 0 = the last
    std::vector<float> opening;               ///< m, simulated opening at the top (0 if not simulated)
    std::vector<float> taper;                 ///< 0 at a crack tip, 1 a tip length or more away
    bool closed = false;                      ///< a loop (the first point repeated at the end)
    bool tip_front = false, tip_back = false; ///< the curve ends at a crack tip there
};

/// The curves of a piece mesh's crack chains.
std::vector<CrackCurve> crack_curves(const post::PieceMesh& pieces, const CurveOptions& options);

/// Metres per unit of u at texture coordinate v (the sphere: the row's circumference).
double metres_per_u(const post::PieceMesh& pieces, double v);

/// Largest distance (m) of a curve's points from the polyline of its chain, over all curves:
/// the smoothing's and the wander's displacement of the simulated crack (for tests).
double largest_displacement(const post::PieceMesh& pieces, const std::vector<CrackCurve>& curves);

} // namespace crackle::render
