#include "render/crack_curves.hpp"

#include "render/noise.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::render {

namespace {

/// A chain's points and attributes, subdivided together.
struct Poly {
    std::vector<Vec2> uv;
    std::vector<float> opening, time;
};

/// One pass of corner cutting: every edge gives its points at ¼ and ¾; an open polyline keeps
/// its end points (pinned), a closed one (first point repeated last) is cut all round.
Poly chaikin(const Poly& p, bool closed) {
    Poly out;
    const std::size_t n = p.uv.size();
    auto push = [&](std::size_t i, std::size_t j, double s) {
        out.uv.push_back((1 - s) * p.uv[i] + s * p.uv[j]);
        out.opening.push_back(static_cast<float>((1 - s) * p.opening[i] + s * p.opening[j]));
        out.time.push_back(static_cast<float>((1 - s) * p.time[i] + s * p.time[j]));
    };
    if (!closed) push(0, 0, 0);
    for (std::size_t i = 0; i + 1 < n; ++i) {
        if (closed || i > 0) push(i, i + 1, 0.25);
        if (closed || i + 2 < n) push(i, i + 1, 0.75);
    }
    if (closed) { // a loop may close on its image a period on (round the trunk)
        const Vec2 shift = p.uv.back() - p.uv.front();
        push(0, 0, 0);
        out.uv.back() = out.uv.front() + shift;
        out.opening.back() = out.opening.front();
        out.time.back() = out.time.front();
    } else
        push(n - 1, n - 1, 0);
    return out;
}

/// 1D gradient noise (Perlin) with period-free integer lattice, in about [−1, 1].
double gradient_noise(double x, std::uint32_t seed) {
    const double k = std::floor(x);
    const double f = x - k;
    auto grad = [&](double lattice) {
        const auto i = static_cast<std::uint32_t>(static_cast<std::int64_t>(lattice));
        return 2.0 * double(hash32(i * 0x9e3779b9u ^ hash32(seed))) / 4294967296.0 - 1.0;
    };
    const double fade = f * f * f * (f * (6 * f - 15) + 10);
    return 2.0 * ((1 - fade) * grad(k) * f + fade * grad(k + 1) * (f - 1));
}

double smooth01(double x) {
    x = std::clamp(x, 0.0, 1.0);
    return x * x * (3 - 2 * x);
}

} // namespace

double metres_per_u(const post::PieceMesh& pieces, double v) {
    if (pieces.periodic) return pieces.tile_size.x();
    return pieces.tile_size.x() * std::max(std::cos(PI * (v - 0.5)), 1e-3);
}

std::vector<CrackCurve> crack_curves(const post::PieceMesh& pieces, const CurveOptions& o) {
    // The opening that counts as wide: the 90th percentile of the simulated openings.
    double opening_reference = 0;
    {
        std::vector<float> openings;
        for (const post::CrackChain& c : pieces.chains)
            for (float w : c.opening)
                if (w > 0) openings.push_back(w);
        if (openings.size() >= 4) {
            const auto k = openings.size() * 9 / 10;
            std::nth_element(openings.begin(), openings.begin() + static_cast<std::ptrdiff_t>(k), openings.end());
            opening_reference = openings[k];
        }
    }
    const double mv = pieces.tile_size.y();
    auto metric = [&](const Vec2& a, const Vec2& b) { // metres from a to b
        const Vec2 d = b - a;
        return Vec2(d.x() * metres_per_u(pieces, 0.5 * (a.y() + b.y())), d.y() * mv);
    };
    const double wavelength = o.wander_wavelength > 0 ? o.wander_wavelength : 4.0 * pieces.element_size;
    const double amplitude = std::min(o.wander, wavelength / 12.0);

    std::vector<CrackCurve> curves;
    curves.reserve(pieces.chains.size());
    for (std::size_t ci = 0; ci < pieces.chains.size(); ++ci) {
        const post::CrackChain& chain = pieces.chains[ci];
        Poly p{chain.uv, chain.opening, chain.time};
        // An opening far beyond the pattern's widest (a pattern file from before the periodic
        // fix of fem-split's openings, which measured some across the tile) is capped.
        if (opening_reference > 0)
            for (float& w : p.opening)
                w = std::min(w, static_cast<float>(4.0 * opening_reference));
        if (p.uv.size() < 2) continue;
        double longest = 0;
        for (std::size_t i = 0; i + 1 < p.uv.size(); ++i)
            longest = std::max(longest, metric(p.uv[i], p.uv[i + 1]).norm());
        const double px = longest / std::max(o.metres_per_px, 1e-12);
        const int passes = px > o.step_px ? std::min(8, static_cast<int>(std::ceil(std::log2(px / o.step_px)))) : 0;
        for (int k = 0; k < passes; ++k)
            p = chaikin(p, chain.closed);

        // Arc length and normals (metres), then the wander along the normal.
        const std::size_t n = p.uv.size();
        std::vector<double> s(n, 0.0);
        for (std::size_t i = 1; i < n; ++i)
            s[i] = s[i - 1] + metric(p.uv[i - 1], p.uv[i]).norm();
        const double length = s.back();
        CrackCurve c;
        c.uv = p.uv;
        c.closed = chain.closed;
        c.tip_front = chain.tip_front;
        c.tip_back = chain.tip_back;
        if (amplitude > 0 && length > 0) {
            const std::uint32_t seed = hash32(o.seed * 0x85ebca6bu + static_cast<std::uint32_t>(ci));
            for (std::size_t i = 0; i < n; ++i) {
                if (!chain.closed && (i == 0 || i + 1 == n)) continue;
                const std::size_t a = i > 0 ? i - 1 : n - 2, b = i + 1 < n ? i + 1 : 1;
                const Vec2 shift = p.uv.back() - p.uv.front(); // a loop's period offset
                const Vec2 t =
                    metric(i > 0 ? p.uv[a] : Vec2(p.uv[a] - shift), i + 1 < n ? p.uv[b] : Vec2(p.uv[b] + shift));
                if (t.norm() <= 0) continue;
                const Vec2 normal = Vec2(-t.y(), t.x()).normalized();
                const double x = s[i] / wavelength;
                double offset = amplitude * (gradient_noise(x, seed) + 0.4 * gradient_noise(2.5 * x + 17.0, seed + 1u));
                if (!chain.closed) offset *= smooth01(s[i] / wavelength) * smooth01((length - s[i]) / wavelength);
                c.uv[i] += Vec2(offset * normal.x() / metres_per_u(pieces, p.uv[i].y()), offset * normal.y() / mv);
            }
            if (chain.closed) c.uv.back() = c.uv.front() + (p.uv.back() - p.uv.front());
        }
        c.weight.resize(n);
        c.age.resize(n);
        c.opening = p.opening;
        c.taper.assign(n, 1.0f);
        for (std::size_t i = 0; i < n; ++i) {
            double w = 1.0 - o.crack_age * p.time[i];
            if (opening_reference > 0) w *= std::clamp(std::sqrt(p.opening[i] / opening_reference), 0.25, 1.0);
            c.weight[i] = static_cast<float>(w);
            c.age[i] = 1.0f - p.time[i];
            if (o.tip_length > 0) {
                double taper = 1.0;
                if (chain.tip_front) taper = std::min(taper, smooth01(s[i] / o.tip_length));
                if (chain.tip_back) taper = std::min(taper, smooth01((length - s[i]) / o.tip_length));
                c.taper[i] = static_cast<float>(taper);
            }
        }
        curves.push_back(std::move(c));
    }
    return curves;
}

double largest_displacement(const post::PieceMesh& pieces, const std::vector<CrackCurve>& curves) {
    const double mv = pieces.tile_size.y();
    double largest = 0;
    std::size_t ci = 0;
    for (const post::CrackChain& chain : pieces.chains) {
        if (chain.uv.size() < 2) continue;
        const CrackCurve& c = curves[ci++];
        for (const Vec2& q : c.uv) {
            double best = 1e300;
            for (std::size_t i = 0; i + 1 < chain.uv.size(); ++i) {
                const double mu = metres_per_u(pieces, q.y());
                const Vec2 a(chain.uv[i].x() * mu, chain.uv[i].y() * mv),
                    b(chain.uv[i + 1].x() * mu, chain.uv[i + 1].y() * mv);
                const Vec2 x(q.x() * mu, q.y() * mv);
                const Vec2 ab = b - a;
                const double t = ab.squaredNorm() > 0 ? std::clamp((x - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
                best = std::min(best, (x - a - t * ab).norm());
            }
            largest = std::max(largest, best);
        }
    }
    return largest;
}

} // namespace crackle::render
