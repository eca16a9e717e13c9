#pragma once
/// @file Grooves from the crack curves (issue 35): per pixel, the exact distance (metres) to the
/// nearest few crack curves and a groove profile across them with continuous normals:
///
///     plate top ─╮ lip fillet (slope turns from 0 to α over L_top)
///                 ╲ wall at slope α
///                  ╰─ floor fillet (α back to 0 over L_floor) ── floor (half the simulated opening, less the
///                                                                     floor fillet: the walls' feet stand in the gap)
///
/// The slope angle turns at a bounded rate (α over a fillet length in metres), so the walls are
/// smooth across the curve's points and the normal map has no creases at the lips; α is solved
/// so that the groove reaches its depth (the groove widens where a deep crack would otherwise
/// need walls steeper than MAX_WALL_DEG, or fillets shorter than the shape pixel allows). The
/// profiles are smoothed over a pixel and a half (the nearest curve point jumps across the
/// inner side of a bend). Where
/// grooves meet, the curves' distances join by a log-sum-exp smooth minimum and their profiles
/// blend (plate corners round, no crease on the ridge between two grooves). Near a tip the
/// floor closes over the groove's width, and with a tip length the width and depth taper too.
/// The distance field is scan-converted per segment (render/groove_scan.hpp) within each groove's
/// extent, so a groove's shape does not depend on the curl. The curl's lift reaches farther
/// (post.curl_width layer heights from the lip) but varies slowly there: beyond half a groove's
/// extent it comes from the same scan on a grid a few pixels coarser, interpolated bicubically
/// (plane and cylinder; on the sphere at every pixel).
/// The scan keeps only the curve points it needs (Douglas-Peucker to `simplify_px`, in height: the
/// smoothing and the wander leave points far closer than a pixel). The cost grows with crack
/// length × reach. Measured against every point and the lift at every pixel (docs/benchmarks.md):
/// mud and bark at 4096² within 16 and 46 µm, 99.9 % of pixels within 2.4 µm.

#include "render/crack_curves.hpp"
#include "render/distance.hpp"

#include <vector>

namespace crackle::render {

struct GrooveOptions {
    double crack_width = 0;    ///< m: the first cracks' groove reach beyond the floor (bake.crack_width)
    double crack_depth = 0;    ///< 0..1: depth share of the first cracks (bake.crack_depth; 0 = the simulation's)
    double bevel = 0;          ///< m: a closed crack's depth when crack_depth is 0 (post.bevel)
    double crack_shape = 0;    ///< 0 = V (short lip fillet), 1 = rounded ridges (the lip fillet is half the reach)
    double rounding = 0;       ///< m: the fillets' least length (post.bevel, at least 1.5 pixels)
    double curl = 0;           ///< post.curl: rim lift at the lip, in layer heights
    double curl_reach = 0;     ///< m: how far from the lip the lift reaches (post.curl_width × the height)
    double join_radius = 1e-3; ///< m: where cracks meet, the plates' corners round in plan by about this
    double pixel = 1e-3;       ///< m: the map's pixel
    double shape_pixel = 0; ///< m: the pixel the shapes are sized for (fillets turn ≤ 9° per such pixel; 0 = `pixel`)
    double smoothing_px = 0; ///< px: the plate height along a curve is averaged over this each way
    /// px: how far a segment's scan reaches beyond the wedge of pixels nearest to its joints
    /// (a guard against rounding; a huge value scans every segment's whole neighbourhood, the
    /// exhaustive reference the tests compare with).
    double wedge_margin_px = 1.0;
    /// px: the step of the grid the curl's lift is measured on beyond the grooves (a power of two
    /// dividing the map; 0 = the largest at most a third of join_radius; 1 = every pixel, the
    /// reference the tests compare with).
    int lift_step_px = 0;
    /// px: the scan keeps a curve's points only where dropping them would move the curve or its
    /// profile by more than this (0 = every point, the reference the tests compare with).
    double simplify_px = 0.02;
};

/// Per pixel of the grid.
struct GrooveField {
    std::vector<float> drop;     ///< m below the plate top (0 … the top)
    std::vector<float> lift;     ///< m the rim is lifted by curl
    std::vector<float> coverage; ///< share of the pixel inside the crack's gap (the simulated opening) or hairline
    std::vector<float> age;      ///< the nearest crack's age (1 = first crack); 1 with no crack near
    std::vector<float> distance; ///< m to the nearest crack curve (∞ with none within reach)
};

/// `top`: the plates' smoothed height per pixel (m), continued across the cracks.
GrooveField groove_field(const PixelGrid& grid, const std::vector<CrackCurve>& curves, const std::vector<float>& top,
                         const GrooveOptions& options);

} // namespace crackle::render
