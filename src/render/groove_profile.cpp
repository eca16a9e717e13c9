#include "render/groove_profile.hpp"

#include <cmath>
#include <cstdint>
#include <utility>

namespace crackle::render::groove {

void ProfileWindow::smooth(int radius) {
    std::vector<float> kernel{1.0f};
    for (int pass = 0; pass < 3; ++pass) {
        std::vector<float> wider(kernel.size() + 2 * std::size_t(radius), 0.0f);
        for (std::size_t k = 0; k < kernel.size(); ++k)
            for (std::size_t j = 0; j <= 2 * std::size_t(radius); ++j)
                wider[k + j] += kernel[k] / float(2 * radius + 1);
        kernel = std::move(wider);
    }
    const std::size_t reach = kernel.size() / 2, n = std::size_t(m_width) * CH, rows = std::size_t(m_rows);
    // Along the rows: each row padded by its wrapped ends.
    std::vector<float> line(n + 2 * reach * CH);
    for (std::size_t row = 0; row < rows; ++row) {
        float* data = &m_data[row * n];
        const std::size_t width = std::size_t(m_width);
        for (std::size_t p = 0; p < width + 2 * reach; ++p) // pixel p − reach, wrapped
            std::copy_n(data + ((p + width * reach - reach) % width) * CH, CH, &line[p * CH]);
        std::fill_n(data, n, 0.0f);
        for (std::size_t j = 0; j < kernel.size(); ++j) {
            const float k = kernel[j], *in = &line[j * CH];
            for (std::size_t i = 0; i < n; ++i)
                data[i] += k * in[i];
        }
    }
    // Down the columns: the rows as they were before they were overwritten, in a ring.
    const std::size_t kept = kernel.size();
    std::vector<float> before(kept * n);
    for (std::size_t row = 0; row < rows; ++row) {
        float* data = &m_data[row * n];
        std::copy_n(data, n, &before[(row % kept) * n]);
        std::fill_n(data, n, 0.0f);
        for (std::size_t j = 0; j < kernel.size(); ++j) {
            const std::size_t from = row + j; // + reach − reach: row − reach + j, if within the window
            if (from < reach || from - reach >= rows) continue;
            const std::size_t source = from - reach;
            const float k = kernel[j];
            const float* in = source <= row ? &before[(source % kept) * n] : &m_data[source * n];
            for (std::size_t i = 0; i < n; ++i)
                data[i] += k * in[i];
        }
    }
}

Profile solve(Profile p, const Fillets& f) {
    const double max_alpha = MAX_WALL_DEG * PI / 180.0;
    p.reach = std::max(p.reach, p.fillet_top + p.fillet_bottom);
    auto depth_at = [&](double alpha) {
        return p.fillet_top * f.top(alpha, 1.0) + p.fillet_bottom * f.bottom(alpha, 1.0)
               + (p.reach - p.fillet_top - p.fillet_bottom) * std::tan(alpha);
    };
    if (p.depth <= 0) {
        p.alpha = 0;
        return p;
    }
    if (depth_at(max_alpha) < p.depth) {
        p.alpha = static_cast<float>(max_alpha);
        const double fillet_depth = p.fillet_top * f.top(max_alpha, 1.0) + p.fillet_bottom * f.bottom(max_alpha, 1.0);
        p.reach = static_cast<float>(p.fillet_top + p.fillet_bottom + (p.depth - fillet_depth) / std::tan(max_alpha));
        return p;
    }
    // The depth grows monotonically with α: the Illinois variant of regula falsi (Dowell & Jarratt
    // 1971) to a depth within 1e-12 of it, in about 8 evaluations where bisection took 40.
    double lo = 0, hi = max_alpha, f_lo = -p.depth, f_hi = depth_at(hi) - p.depth, alpha = hi;
    for (int k = 0, side = 0; k < 100; ++k) {
        alpha = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        if (!(alpha > lo && alpha < hi)) alpha = 0.5 * (lo + hi);
        const double miss = depth_at(alpha) - p.depth;
        if (std::abs(miss) <= 1e-12 * p.depth || hi - lo <= 1e-15) break;
        if (miss < 0) {
            lo = alpha, f_lo = miss;
            if (side < 0) f_hi *= 0.5;
            side = -1;
        } else {
            hi = alpha, f_hi = miss;
            if (side > 0) f_lo *= 0.5;
            side = 1;
        }
    }
    p.alpha = static_cast<float>(alpha);
    // The table's interpolation: the depth the profile reaches is the depth at this α.
    p.depth = static_cast<float>(depth_at(p.alpha));
    return p;
}

std::vector<double> smooth_along(const std::vector<double>& arc, const std::vector<double>& values, double half,
                                 bool closed) {
    const std::size_t n = values.size();
    if (n < 3 || half <= 0) return values;
    const double length = arc.back(), margin = 2 * half;
    std::vector<double> s, v;
    for (std::size_t k = n - 1; k-- > 1;) { // before the start, in order of arc length
        const std::size_t j = closed ? n - 1 - k : k;
        if (closed && length - arc[j] <= margin) s.push_back(arc[j] - length), v.push_back(values[j]);
        if (!closed && arc[j] <= margin) s.push_back(-arc[j]), v.push_back(2 * values[0] - values[j]);
    }
    const std::size_t first = s.size();
    s.insert(s.end(), arc.begin(), arc.end());
    v.insert(v.end(), values.begin(), values.end());
    for (std::size_t k = n - 1; k-- > 1;) { // after the end
        const std::size_t j = closed ? n - 1 - k : k;
        if (closed && arc[j] <= margin) s.push_back(length + arc[j]), v.push_back(values[j]);
        if (!closed && length - arc[j] <= margin)
            s.push_back(2 * length - arc[j]), v.push_back(2 * values[n - 1] - values[j]);
    }
    const std::size_t m = s.size();
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<double> sum(m + 1, 0.0), mean(m);
        for (std::size_t i = 0; i < m; ++i)
            sum[i + 1] = sum[i] + v[i];
        for (std::size_t i = 0, lo = 0, hi = 0; i < m; ++i) {
            while (s[i] - s[lo] > half)
                ++lo;
            hi = std::max(hi, i);
            while (hi + 1 < m && s[hi + 1] - s[i] <= half)
                ++hi;
            mean[i] = (sum[hi + 1] - sum[lo]) / double(hi + 1 - lo);
        }
        v = std::move(mean);
    }
    std::vector<double> out(v.begin() + static_cast<std::ptrdiff_t>(first),
                            v.begin() + static_cast<std::ptrdiff_t>(first + n));
    if (!closed) out.front() = values.front(), out.back() = values.back();
    return out;
}

std::vector<std::size_t> kept_points(const std::vector<Vec2>& at, const std::vector<Profile>& profile, double tolerance,
                                     double pixel, double top) {
    const std::size_t n = at.size();
    std::vector<std::size_t> kept;
    if (n < 3 || tolerance <= 0) {
        for (std::size_t i = 0; i < n; ++i)
            kept.push_back(i);
        return kept;
    }
    auto extent = [&](std::size_t i) { return double(profile[i].floor + profile[i].reach); };
    auto error = [&](std::size_t i, std::size_t j, std::size_t m) {
        const Vec2 chord = at[j] - at[i];
        const double l2 = chord.squaredNorm();
        const double t = l2 > 0 ? std::clamp((at[m] - at[i]).dot(chord) / l2, 0.0, 1.0) : 0.0;
        const Profile& p = profile[m];
        const Profile q = lerp(profile[i], profile[j], t);
        // A wall of slope tan α turns a shift across it into α's tangent times that in height.
        const double reach = std::max(p.reach, q.reach) / pixel, wall = std::max(1.0, std::tan(double(p.alpha)));
        return std::max(
            {wall * (at[i] + t * chord - at[m]).norm(), wall * std::abs(p.floor - q.floor) / pixel,
             wall * std::abs(p.reach - q.reach) / pixel, wall * std::abs(p.fillet_top - q.fillet_top) / pixel,
             wall * std::abs(p.fillet_bottom - q.fillet_bottom) / pixel, std::abs(p.depth - q.depth) / pixel,
             std::abs(p.gap - q.gap) / pixel, std::abs(p.alpha - q.alpha) * reach * (1 + wall * wall),
             std::abs(p.share - q.share) * top / pixel, std::abs(p.age - q.age) * 200 * tolerance,
             // a segment's extent (where its curve fades out of the join) is its ends' larger
             std::abs(std::max(extent(i), extent(j)) - extent(m)) / pixel});
    };
    // Where a groove fades out of the join (a tapering tip), its share moves the joined distance by
    // up to r / fade: those points are all kept, and the runs between them simplified.
    std::vector<std::uint8_t> keep(n, 0);
    keep.front() = keep.back() = 1;
    for (std::size_t i = 0; i < n; ++i)
        keep[i] = keep[i] || profile[i].share < SHALLOW;
    std::vector<std::pair<std::size_t, std::size_t>> spans;
    for (std::size_t i = 0, last = 0; i < n; ++i)
        if (i > 0 && keep[i]) {
            if (i - last > 1) spans.emplace_back(last, i);
            last = i;
        }
    while (!spans.empty()) {
        const auto [i, j] = spans.back();
        spans.pop_back();
        double worst = 0;
        std::size_t split = i;
        for (std::size_t m = i + 1; m < j; ++m)
            if (const double e = error(i, j, m); e > worst) worst = e, split = m;
        if (worst <= tolerance) continue;
        keep[split] = 1;
        spans.emplace_back(i, split);
        spans.emplace_back(split, j);
    }
    for (std::size_t i = 0; i < n; ++i)
        if (keep[i]) kept.push_back(i);
    return kept;
}

} // namespace crackle::render::groove
