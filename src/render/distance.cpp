#include "render/distance.hpp"

#include "core/parallel.hpp"

#include <cmath>
#include <limits>

namespace crackle::render {

namespace {

constexpr double INF = std::numeric_limits<double>::infinity();
constexpr std::uint32_t NONE = std::numeric_limits<std::uint32_t>::max();
constexpr int NO_POSITION = std::numeric_limits<int>::min(); // positions may be negative (wrapped copies)

/// Lower envelope of the parabolas a·(q − p)² + f(p) over positions p ∈ [first, first + n)
/// (f read through `value(p)`), evaluated at q ∈ [0, count): out_d and out_p.
template <typename Value>
void lower_envelope(int first, int n, double a, const Value& value, int count, std::vector<double>& out_d,
                    std::vector<int>& out_p, std::vector<int>& v, std::vector<double>& z) {
    v.resize(static_cast<std::size_t>(n));
    z.resize(static_cast<std::size_t>(n) + 1);
    int k = -1;
    for (int p = first; p < first + n; ++p) {
        const double fp = value(p);
        if (!std::isfinite(fp)) continue;
        double s = -INF;
        while (k >= 0) {
            const int r = v[static_cast<std::size_t>(k)];
            s = ((fp + a * double(p) * p) - (value(r) + a * double(r) * r)) / (2.0 * a * (p - r));
            if (s > z[static_cast<std::size_t>(k)]) break;
            --k;
        }
        ++k;
        v[static_cast<std::size_t>(k)] = p;
        z[static_cast<std::size_t>(k)] = k == 0 ? -INF : s;
        z[static_cast<std::size_t>(k) + 1] = INF;
    }
    out_d.assign(static_cast<std::size_t>(count), INF);
    out_p.assign(static_cast<std::size_t>(count), NO_POSITION);
    if (k < 0) return;
    int j = 0;
    for (int q = 0; q < count; ++q) {
        while (z[static_cast<std::size_t>(j) + 1] < q)
            ++j;
        const int p = v[static_cast<std::size_t>(j)];
        out_d[static_cast<std::size_t>(q)] = a * double(q - p) * (q - p) + value(p);
        out_p[static_cast<std::size_t>(q)] = p;
    }
}

int wrap_index(int i, int n) {
    return ((i % n) + n) % n;
}

} // namespace

DistanceField distance_transform(const PixelGrid& g, const std::vector<std::uint8_t>& source, bool with_nearest) {
    const int w = g.width, h = g.height;
    // === Columns: the nearest source row above and below every pixel, by two sweeps over the
    // rows (row-major, so the image streams through the cache once per sweep); with v wrapping
    // the sweeps start one period early so sources across the border count.
    std::vector<int> col_row(g.pixels(), NO_POSITION); // the nearest source row (unwrapped)
    constexpr int BANDS = 16;                          // bands of columns, swept on the worker threads side by side
    parallel_rows(
        BANDS,
        [&](int band) {
            const int x0 = band * w / BANDS, x1 = (band + 1) * w / BANDS;
            std::vector<int> last(static_cast<std::size_t>(w), NO_POSITION);
            for (int y = g.wrap_v ? -h : 0; y < h; ++y) {
                const int row = wrap_index(y, h);
                for (int x = x0; x < x1; ++x) {
                    if (source[g.index(x, row)]) last[static_cast<std::size_t>(x)] = y;
                    if (y >= 0) col_row[g.index(x, y)] = last[static_cast<std::size_t>(x)];
                }
            }
            std::fill(last.begin(), last.end(), NO_POSITION);
            for (int y = g.wrap_v ? 2 * h - 1 : h - 1; y >= 0; --y) {
                const int row = wrap_index(y, h);
                for (int x = x0; x < x1; ++x) {
                    const int b = source[g.index(x, row)] ? y : last[static_cast<std::size_t>(x)];
                    last[static_cast<std::size_t>(x)] = b;
                    if (y >= h || b == NO_POSITION) continue;
                    int& a = col_row[g.index(x, y)];
                    if (a == NO_POSITION || b - y < y - a) a = b;
                }
            }
        },
        1);
    std::vector<float> col_d2(g.pixels(), std::numeric_limits<float>::infinity());
    const double av = g.metres_v * g.metres_v;
    parallel_rows(h, [&](int y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = g.index(x, y);
            if (col_row[i] == NO_POSITION) continue;
            const double d = double(col_row[i] - y);
            col_d2[i] = static_cast<float>(av * d * d);
            col_row[i] = wrap_index(col_row[i], h);
        }
    });
    // === Rows: combine the columns with the row's own pixel width; u always wraps (the row is
    // laid out three times so the envelope sees the copies on either side).
    DistanceField out;
    out.distance.assign(g.pixels(), std::numeric_limits<float>::infinity());
    if (with_nearest) out.nearest.assign(g.pixels(), NONE);
    parallel_rows(h, [&](int y) {
        std::vector<int> v;
        std::vector<double> z, d, tripled(3 * static_cast<std::size_t>(w));
        std::vector<int> p;
        for (int k = 0; k < 3; ++k)
            for (int x = 0; x < w; ++x)
                tripled[static_cast<std::size_t>(k * w + x)] = col_d2[g.index(x, y)];
        const double au = g.metres_u[static_cast<std::size_t>(y)] * g.metres_u[static_cast<std::size_t>(y)];
        auto value = [&](int x) { return tripled[static_cast<std::size_t>(x + w)]; };
        lower_envelope(-w, 3 * w, au, value, w, d, p, v, z);
        for (int x = 0; x < w; ++x) {
            const int px = p[static_cast<std::size_t>(x)];
            if (px == NO_POSITION) continue;
            out.distance[g.index(x, y)] = static_cast<float>(std::sqrt(d[static_cast<std::size_t>(x)]));
            if (!with_nearest) continue;
            const int sx = wrap_index(px, w);
            out.nearest[g.index(x, y)] = static_cast<std::uint32_t>(g.index(sx, col_row[g.index(sx, y)]));
        }
    });
    return out;
}

} // namespace crackle::render
