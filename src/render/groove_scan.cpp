#include "render/groove_scan.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::render::scan {

void Nearest::offer(double d2, std::int32_t c, std::uint32_t k, double at) {
    int slot = -1, farthest = 0;
    for (int i = 0; i < SLOTS; ++i) {
        if (curve[i] == c) slot = i;
        if (curve[i] < 0 || (curve[farthest] >= 0 && distance[i] > distance[farthest])) farthest = i;
    }
    // The distance the offer must beat: the part's own, else the farthest of the slots.
    const int against = slot >= 0 ? slot : farthest;
    if (curve[against] >= 0) {
        // float(√d2) ≥ L whenever d2 ≥ L² (rounding is monotone): most offers end here, before the root.
        const double limit = distance[against];
        if (d2 >= limit * limit) return;
        if (distance[against] <= static_cast<float>(std::sqrt(d2))) return;
    }
    curve[against] = c, distance[against] = static_cast<float>(std::sqrt(d2)), segment[against] = k,
    t[against] = static_cast<float>(at);
}

std::vector<Segment> segments(const PixelGrid& g, const std::vector<CrackCurve>& curves,
                              const std::vector<std::vector<double>>& extent, double fade, double part) {
    const int W = g.width, H = g.height;
    auto to_px = [&](const Vec2& uv) { return Vec2(uv.x() * W - 0.5, (1.0 - uv.y()) * H - 0.5); };
    std::vector<Segment> segs;
    for (std::size_t c = 0; c < curves.size(); ++c) {
        const CrackCurve& cv = curves[c];
        for (std::size_t i = 0; i + 1 < cv.uv.size(); ++i) {
            Segment s;
            s.a = to_px(cv.uv[i]);
            s.b = to_px(cv.uv[i + 1]);
            s.curve = static_cast<std::uint32_t>(c);
            s.point = static_cast<std::uint32_t>(i);
            s.extent = std::max(extent[c][i], extent[c][i + 1]);
            segs.push_back(s);
        }
    }
    // Past a joint the rectangle reaches only as far as the pixels whose nearest point of the
    // curve is the joint itself (the wedge on the bend's outer side, Mauch 2000): reach · sin θ
    // for a turn θ ≤ 90°, set per row below in that row's metres. At the curve's ends, a round
    // cap of the whole reach.
    for (std::size_t k = 0, first = 0; k < segs.size(); ++k) {
        Segment& s = segs[k];
        const CrackCurve& cv = curves[s.curve];
        const std::size_t n = cv.uv.size(), i = s.point;
        if (i == 0) first = k;
        // A loop may close on its image a period on (round the trunk): its neighbours across
        // the closing point are brought back by that period.
        const Vec2 period = to_px(cv.uv.back()) - to_px(cv.uv.front());
        if (i > 0) {
            s.before = segs[k - 1].a;
        } else if (cv.closed && n > 2) {
            s.before = to_px(cv.uv[n - 2]) - period;
        } else {
            s.before = s.a, s.cap_a = true;
        }
        if (i + 2 < n) {
            s.after = to_px(cv.uv[i + 2]);
        } else if (cv.closed && n > 2) {
            s.after = segs[first].b + period;
        } else {
            s.after = s.b, s.cap_b = true;
        }
    }

    // Every segment of a curve scans as wide as the curve's widest reach: each pixel within it
    // then finds its nearest point of the curve, whose profile alone shapes it (a narrower groove
    // ahead, as at a tapering tip, is not overlapped by the round end of a wider one behind).
    for (std::size_t k0 = 0; k0 < segs.size();) {
        std::size_t k1 = k0;
        double widest = 0;
        for (; k1 < segs.size() && segs[k1].curve == segs[k0].curve; ++k1)
            widest = std::max(widest, (1.0 + fade) * segs[k1].extent);
        for (std::size_t k = k0; k < k1; ++k)
            segs[k].scan = widest;
        k0 = k1;
    }

    // Arcs in metres (each segment at its middle row's metres per pixel), and the parts: a
    // curve cut into equal parts about `part` scan widths long, each cut at the straightest joint
    // within a quarter part of its place. On a bend's inner side the pixels near a cut see both
    // parts' nearest points (the same neighbourhood of the curve, counted once by the join, but
    // a slot each): at a straight joint that wedge is thin.
    auto metres_u = [&](double y) {
        const int row = std::clamp(static_cast<int>(std::lround(y)), 0, H - 1);
        return g.metres_u[static_cast<std::size_t>(g.wrap_v ? ((row % H) + H) % H : row)];
    };
    auto direction = [&](const Segment& s, double y) {
        const Vec2 d((s.b.x() - s.a.x()) * metres_u(y), (s.b.y() - s.a.y()) * g.metres_v);
        return d.norm() > 0 ? Vec2(d / d.norm()) : Vec2(1, 0);
    };
    std::uint32_t parts = 0;
    for (std::size_t k0 = 0; k0 < segs.size();) {
        std::size_t k1 = k0;
        double arc = 0;
        for (; k1 < segs.size() && segs[k1].curve == segs[k0].curve; ++k1) {
            Segment& s = segs[k1];
            const Vec2 d = s.b - s.a;
            s.arc = arc;
            s.length = std::hypot(d.x() * metres_u(0.5 * (s.a.y() + s.b.y())), d.y() * g.metres_v);
            arc += s.length;
        }
        const auto n = static_cast<std::size_t>(std::max(1.0, std::round(arc / std::max(part * segs[k0].scan, 1e-12))));
        const bool loop = curves[segs[k0].curve].closed;
        std::size_t at = k0; // the joint the last cut was made at (the curve's start)
        for (std::size_t cut = 1; cut < n; ++cut) {
            const double place = arc * double(cut) / double(n), window = 0.25 * arc / double(n);
            std::size_t best = 0;
            double best_bend = 0, best_off = 0;
            bool inside_best = false;
            for (std::size_t k = at + 1; k < k1 && !(best != 0 && segs[k].arc > place + window); ++k) {
                const double off = std::abs(segs[k].arc - place); // the joint at segs[k].a
                const double bend = 1.0 - direction(segs[k - 1], segs[k].a.y()).dot(direction(segs[k], segs[k].a.y()));
                const bool inside = off <= window;
                if (best == 0 || (inside && (!inside_best || bend < best_bend)) || (!inside_best && off < best_off))
                    best = k, best_bend = bend, best_off = off, inside_best = inside;
            }
            if (best == 0) break; // no joint left: fewer parts
            segs[best - 1].open_b = segs[best].open_a = true;
            at = best;
        }
        for (std::size_t k = k0, p = 0; k < k1; ++k) {
            Segment& s = segs[k];
            if (k > k0 && s.open_a) ++p;
            s.part = parts + static_cast<std::uint32_t>(p);
            s.curve_length = arc;
            if (k + 1 == k1) {
                if (loop && p > 0) segs[k0].open_a = s.open_b = true; // the first and last parts meet
                parts += static_cast<std::uint32_t>(p + 1);
            }
        }
        k0 = k1;
    }

    return segs;
}

std::vector<Bin> bins(const PixelGrid& g, const std::vector<Segment>& segs, int block_rows, int halo) {
    const int H = g.height;
    // === Bin the segments (and their periodic images in v) by blocks of rows.
    const int blocks = (H + block_rows - 1) / block_rows;
    std::vector<Bin> bins(static_cast<std::size_t>(blocks));
    for (std::size_t k = 0; k < segs.size(); ++k) {
        const Segment& s = segs[k];
        // The scanned rectangle reaches at most scan · √2 from the segment in v (its corners).
        const double reach_px = std::sqrt(2.0) * s.scan / g.metres_v + 1 + halo;
        const double y0 = std::min(s.a.y(), s.b.y()) - reach_px, y1 = std::max(s.a.y(), s.b.y()) + reach_px;
        std::vector<double> shifts{0.0};
        if (g.wrap_v) {
            const double base = -H * std::floor(std::min(s.a.y(), s.b.y()) / H);
            shifts = {base - H, base, base + H};
        }
        for (double shift : shifts) {
            const int b0 = std::max(0, static_cast<int>(std::floor((y0 + shift) / block_rows)));
            const int b1 = std::min(blocks - 1, static_cast<int>(std::floor((y1 + shift) / block_rows)));
            for (int b = b0; b <= b1; ++b)
                bins[static_cast<std::size_t>(b)].emplace_back(static_cast<std::uint32_t>(k), shift);
        }
    }

    return bins;
}

void offer_block(const PixelGrid& g, const std::vector<Segment>& segs, const Bin& bin, int h0, int rows,
                 double margin_px, std::vector<Nearest>& state) {
    const int W = g.width, H = g.height;
    auto grid_row = [&](int y) { return g.wrap_v ? ((y % H) + H) % H : (y >= 0 && y < H ? y : -1); };
    for (const auto& [k, shift] : bin) {
        const Segment& s = segs[k];
        const auto key = static_cast<std::int32_t>(s.part);
        // The segment and its rectangle in a row's metres (recomputed only where the metres
        // per pixel in u change: on the sphere).
        double mu = -1;
        const double mv = g.metres_v;
        Vec2 a(0, 0), ab(0, 0), into_a(0, 0), out_of_b(0, 0); // (the directions of the neighbouring segments)
        double len = 0;
        const double scan2 = s.scan * s.scan;
        std::array<Vec2, 4> corner{a, a, a, a};
        for (int y = h0; y < h0 + rows; ++y) {
            if (grid_row(y) < 0) continue;
            if (const double row_mu = g.metres_u[static_cast<std::size_t>(grid_row(y))]; row_mu != mu) {
                mu = row_mu;
                a = Vec2(s.a.x() * mu, (s.a.y() + shift) * mv);
                const Vec2 b(s.b.x() * mu, (s.b.y() + shift) * mv);
                ab = b - a;
                len = ab.norm();
                into_a = Vec2((s.a.x() - s.before.x()) * mu, (s.a.y() - s.before.y()) * mv);
                out_of_b = Vec2((s.after.x() - s.b.x()) * mu, (s.after.y() - s.b.y()) * mv);
                const Vec2 dir = len > 0 ? Vec2(ab / len) : Vec2(1, 0), nrm(-dir.y(), dir.x());
                // How far past a joint the wedge of pixels nearest to it reaches (plus a
                // margin), and on which side: the wedge lies on the bend's outer side, away
                // from the neighbouring point (the inner side is in the slabs of the
                // segments either side). Each segment's rectangle is extended there only.
                auto past = [&](const Vec2& from, const Vec2& to, bool cap) {
                    const Vec2 d((to.x() - from.x()) * mu, (to.y() - from.y()) * mv);
                    const double dn = d.norm();
                    if (cap || dn <= 0) return s.scan;
                    const double cos_turn = d.dot(dir) / dn;
                    if (cos_turn <= 0) return s.scan;
                    return std::min(s.scan, s.scan * std::sqrt(std::max(0.0, 1.0 - cos_turn * cos_turn))
                                                + margin_px * std::max(mu, mv));
                };
                // The side (+1: along nrm) where the neighbour beyond an end lies.
                auto side = [&](const Vec2& neighbour, const Vec2& end) {
                    return Vec2((neighbour.x() - end.x()) * mu, (neighbour.y() - end.y()) * mv).dot(nrm) > 0 ? 1 : -1;
                };
                const double pa = past(s.before, s.a, s.cap_a), pb = past(s.b, s.after, s.cap_b);
                const bool round_a = s.cap_a || pa >= s.scan, round_b = s.cap_b || pb >= s.scan;
                const int sa = side(s.before, s.a), sb = side(s.after, s.b);
                // A corner on the +nrm side is extended when the neighbour lies on the − side.
                auto at_a = [&](int sign) {
                    return a - dir * ((round_a || sa != sign) ? pa : 0.0) + sign * nrm * s.scan;
                };
                auto at_b = [&](int sign) {
                    return b + dir * ((round_b || sb != sign) ? pb : 0.0) + sign * nrm * s.scan;
                };
                corner = {at_a(1), at_b(1), at_b(-1), at_a(-1)};
            }
            const double ym = y * mv;
            double xlo = 1e300, xhi = -1e300;
            for (int e = 0; e < 4; ++e) {
                const Vec2 &p = corner[static_cast<std::size_t>(e)], &q = corner[static_cast<std::size_t>((e + 1) % 4)];
                if ((p.y() - ym) * (q.y() - ym) > 0 || p.y() == q.y()) continue;
                const double x = p.x() + (ym - p.y()) / (q.y() - p.y()) * (q.x() - p.x());
                xlo = std::min(xlo, x);
                xhi = std::max(xhi, x);
            }
            if (xlo > xhi) continue;
            int x0 = static_cast<int>(std::ceil(xlo / mu)), x1 = static_cast<int>(std::floor(xhi / mu));
            if (x1 - x0 >= W) {
                // Near the sphere's poles a row's rectangle can be wider than the period: each
                // column then has several images in it, and its distance, convex along the
                // row, is least at one of the two images either side of the row's closest
                // point to the segment. Scan those.
                const double ty = ab.y() != 0 ? std::clamp((ym - a.y()) / ab.y(), 0.0, 1.0) : 0.0;
                const int closest = static_cast<int>(std::floor((a.x() + ty * ab.x()) / mu));
                x0 = std::max(x0, closest - W + 1);
                x1 = std::min(x1, closest + W);
            }
            Nearest* row = &state[static_cast<std::size_t>((y - h0) * W)];
            for (int x = x0, wrapped = ((x0 % W) + W) % W; x <= x1; ++x, wrapped = wrapped + 1 < W ? wrapped + 1 : 0) {
                const Vec2 q(x * mu, ym);
                const double raw = len > 0 ? (q - a).dot(ab) / (len * len) : 0.0;
                // Past an end the nearest point is the end: a local minimum along the curve only
                // at the curve's own end, or at a joint where the neighbouring segment's nearest
                // point is the joint too (the bend's outer side). A joint between two parts
                // belongs to the part that starts there.
                if (raw < 0 && !s.cap_a && (q - a).dot(into_a) < 0) continue;
                if (raw > 1 && !s.cap_b && (s.open_b || (q - a - ab).dot(out_of_b) > 0)) continue;
                const double t = std::clamp(raw, 0.0, 1.0);
                const double d2 = (q - a - t * ab).squaredNorm();
                if (d2 <= scan2) row[wrapped].offer(d2, key, k, t);
            }
        }
    }
}

} // namespace crackle::render::scan
