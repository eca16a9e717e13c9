#pragma once
/// @file The distance scan behind the grooves (render/groove.hpp): every segment of the crack
/// curves offers its exact distance to the pixels within its curve's reach, and each pixel keeps
/// its nearest few curve parts. Scan-converted per segment (Mauch 2000's characteristic regions): a
/// segment scans the rectangle of its curve's widest reach beside it, and past a joint only the
/// wedge of pixels nearest to the joint (reach · sin of the turn) on the bend's outer side; round
/// caps only at a curve's ends. The cost grows with crack length × reach.

#include "render/crack_curves.hpp"
#include "render/distance.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace crackle::render::scan {

/// A segment of a curve, in a grid's pixel coordinates (x right, y down; pixel centres at integers).
struct Segment {
    Vec2 a{0, 0}, b{0, 0};
    std::uint32_t curve = 0, point = 0;  ///< the curve and its first point's index
    std::uint32_t part = 0;              ///< the part of its curve (below): the key a pixel keeps its nearest by
    double extent = 0;                   ///< m: the farthest the groove (or the curl) reaches
    Vec2 before{0, 0}, after{0, 0};      ///< the curve's points before a and after b (= a, b at an end)
    bool cap_a = false, cap_b = false;   ///< the curve ends at a (b): a round cap of the whole reach
    bool open_a = false, open_b = false; ///< a (b) is where the part meets the next part of its curve
    double scan = 0;                     ///< m: how far from the segment pixels are scanned (its curve's widest reach)
    double arc = 0, length = 0;          ///< m: along the curve to a, and the segment's own length
    double curve_length = 0;             ///< m: the whole curve's (a loop's arcs are compared round it)
};

/// The nearest few distinct curve parts of a pixel: each part's nearest local minimum of the
/// distance along it (the least over its segments' offers, which are local minima only: a
/// projection inside a segment, a joint on the bend's outer side, a curve's end) and where on
/// which segment it is met. A curve keeps one entry per part, so where it comes back beside
/// itself (a hairpin, a chain's young end beside its old middle) both of its stretches are kept.
struct alignas(32) Nearest {
    static constexpr int SLOTS = 6;
    std::array<float, SLOTS> distance{};
    std::array<std::int32_t, SLOTS> curve{-1, -1, -1, -1, -1, -1};
    std::array<std::uint32_t, SLOTS> segment{};
    std::array<float, SLOTS> t{};

    /// Part c's segment k, met at parameter `at`, at squared distance d2 (m²).
    void offer(double d2, std::int32_t c, std::uint32_t k, double at);
    bool empty() const {
        return std::all_of(curve.begin(), curve.end(), [](std::int32_t c) { return c < 0; });
    }
};

/// The curves' segments in `grid`'s pixel coordinates. `extent[c][i]` (m): how far the groove
/// reaches from point i of curve c; every segment of a curve scans (1 + fade) × the curve's widest.
/// Each curve is cut into parts of about `part` × that scan width along it (each cut at the
/// straightest joint within a quarter part of its place); a part's ends where it meets the next
/// part are `open`. A joint between two parts is offered by the part that starts there only (the
/// part that ends there has the same point, so nothing is lost).
std::vector<Segment> segments(const PixelGrid& grid, const std::vector<CrackCurve>& curves,
                              const std::vector<std::vector<double>>& extent, double fade, double part);

/// Each block of `block_rows` rows (and `halo` rows each side): the segments, and the periodic
/// shift in v (pixels) of each image that reaches it.
using Bin = std::vector<std::pair<std::uint32_t, double>>;
std::vector<Bin> bins(const PixelGrid& grid, const std::vector<Segment>& segs, int block_rows, int halo);

/// Offers every segment of `bin` to the rows h0 … h0 + rows − 1 (wrapped in v, or skipped past
/// the map's edge) of `state` (rows × width), where its nearest point is a local minimum of the
/// distance along the curve (so the offers do not depend on how far the scan reaches).
/// `margin_px`: how far past the wedge of pixels nearest to a joint the scan reaches (a huge
/// value scans every segment's whole neighbourhood).
void offer_block(const PixelGrid& grid, const std::vector<Segment>& segs, const Bin& bin, int h0, int rows,
                 double margin_px, std::vector<Nearest>& state);

} // namespace crackle::render::scan
