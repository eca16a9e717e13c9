#pragma once
/// @file The distance scan behind the grooves (render/groove.hpp): every segment of the crack
/// curves offers its exact distance to the pixels within its curve's reach, and each pixel keeps
/// its nearest few curves. Scan-converted per segment (Mauch 2000's characteristic regions): a
/// segment scans the rectangle of its curve's widest reach beside it, and past a joint only the
/// wedge of pixels nearest to the joint (reach · sin of the turn) on the bend's outer side; round
/// caps only at a curve's ends. The cost grows with crack length × reach.

#include "render/crack_curves.hpp"
#include "render/distance.hpp"

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace crackle::render::scan {

/// A segment of a curve, in a grid's pixel coordinates (x right, y down; pixel centres at integers).
struct Segment {
    Vec2 a{0, 0}, b{0, 0};
    std::uint32_t curve = 0, point = 0; ///< the curve and its first point's index
    double extent = 0;                  ///< m: the farthest the groove (or the curl) reaches
    Vec2 before{0, 0}, after{0, 0};     ///< the curve's points before a and after b (= a, b at an end)
    bool cap_a = false, cap_b = false;  ///< the curve ends at a (b): a round cap of the whole reach
    double scan = 0;                    ///< m: how far from the segment pixels are scanned (its curve's widest reach)
};

/// The nearest few distinct curves of a pixel: each curve's distance (the least over its
/// segments) and where on which segment it is met.
struct alignas(64) Nearest {
    static constexpr int SLOTS = 4;
    std::array<float, SLOTS> distance{};
    std::array<std::int32_t, SLOTS> curve{-1, -1, -1, -1};
    std::array<std::uint32_t, SLOTS> segment{};
    std::array<float, SLOTS> t{};

    /// Curve c's segment k, met at parameter `at`, at squared distance d2 (m²).
    void offer(double d2, std::int32_t c, std::uint32_t k, double at);
    bool empty() const { return curve[0] < 0 && curve[1] < 0 && curve[2] < 0 && curve[3] < 0; }
};

/// The curves' segments in `grid`'s pixel coordinates. `extent[c][i]` (m): how far the groove
/// reaches from point i of curve c; every segment of a curve scans (1 + fade) × the curve's widest.
std::vector<Segment> segments(const PixelGrid& grid, const std::vector<CrackCurve>& curves,
                              const std::vector<std::vector<double>>& extent, double fade);

/// Each block of `block_rows` rows (and `halo` rows each side): the segments, and the periodic
/// shift in v (pixels) of each image that reaches it.
using Bin = std::vector<std::pair<std::uint32_t, double>>;
std::vector<Bin> bins(const PixelGrid& grid, const std::vector<Segment>& segs, int block_rows, int halo);

/// Offers every segment of `bin` to the rows h0 … h0 + rows − 1 (wrapped in v, or skipped past
/// the map's edge) of `state` (rows × width). `margin_px`: how far past the wedge of pixels
/// nearest to a joint the scan reaches (a huge value scans every segment's whole neighbourhood).
void offer_block(const PixelGrid& grid, const std::vector<Segment>& segs, const Bin& bin, int h0, int rows,
                 double margin_px, std::vector<Nearest>& state);

} // namespace crackle::render::scan
