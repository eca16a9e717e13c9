#include "post/crack_times.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace crackle::post {

namespace {

/// Fracture events bucketed on a grid over the (u, v) parameter square (u and v wrap).
class EventGrid {
public:
    EventGrid(const fracture::CrackPattern& p, Vec2 metres) : m_metres(metres) {
        for (const fracture::Event& e : p.events) {
            if (e.kind == "subdivide") continue; // refinement, not a crack
            m_uv.push_back(p.surface.uv(e.position));
            m_time.push_back(e.time);
        }
        m_n = std::clamp(static_cast<int>(std::sqrt(double(m_uv.size()) / 2.0)), 1, 512);
        m_cells.assign(static_cast<std::size_t>(m_n * m_n), {});
        for (std::size_t i = 0; i < m_uv.size(); ++i)
            m_cells[cell(cell_of(m_uv[i].x()), cell_of(m_uv[i].y()))].push_back(i);
    }

    std::size_t size() const { return m_uv.size(); }
    double time(std::size_t i) const { return m_time[i]; }

    /// The event nearest to `uv` (distances in metres, wrapping); searched in growing rings.
    std::size_t nearest(const Vec2& uv) const {
        const int cx = cell_of(uv.x()), cy = cell_of(uv.y());
        double best = std::numeric_limits<double>::infinity();
        std::size_t best_i = 0;
        for (int r = 0; r <= m_n; ++r) {
            for (int dy = -r; dy <= r; ++dy)
                for (int dx = -r; dx <= r; ++dx) {
                    if (std::max(std::abs(dx), std::abs(dy)) != r) continue;
                    for (std::size_t i : m_cells[cell(wrap_i(cx + dx), wrap_i(cy + dy))]) {
                        const double d = distance(uv, m_uv[i]);
                        if (d < best || (d == best && i < best_i)) {
                            best = d;
                            best_i = i;
                        }
                    }
                }
            // Every point of ring r + 1 is at least r cells away.
            const double ring = double(r) / m_n * std::min(m_metres.x(), m_metres.y());
            if (std::isfinite(best) && best <= ring) break;
        }
        return best_i;
    }

private:
    int cell_of(double x) const { return std::clamp(static_cast<int>(std::floor(wrap(x, 1.0) * m_n)), 0, m_n - 1); }
    int wrap_i(int i) const { return ((i % m_n) + m_n) % m_n; }
    std::size_t cell(int x, int y) const { return static_cast<std::size_t>(y * m_n + x); }
    double distance(const Vec2& a, const Vec2& b) const {
        double du = std::abs(a.x() - b.x()), dv = std::abs(a.y() - b.y());
        du = std::min(du, 1.0 - du);
        dv = std::min(dv, 1.0 - dv);
        return std::hypot(du * m_metres.x(), dv * m_metres.y());
    }

    Vec2 m_metres;
    int m_n = 1;
    std::vector<Vec2> m_uv;
    std::vector<double> m_time;
    std::vector<std::vector<std::size_t>> m_cells;
};

/// Reference (u, v) of the midpoint of a face's corners `a` and `b` (u, v wrapped together).
Vec2 mid_uv(const fracture::CrackPattern& p, const std::vector<Vec3>& corners) {
    Vec2 sum = Vec2::Zero();
    const Vec2 first = p.surface.uv(corners[0]);
    for (const Vec3& c : corners) {
        Vec2 uv = p.surface.uv(c);
        for (int k = 0; k < 2; ++k) {
            if (uv[k] - first[k] > 0.5) uv[k] -= 1.0;
            if (uv[k] - first[k] < -0.5) uv[k] += 1.0;
        }
        sum += uv;
    }
    return sum / double(corners.size());
}

} // namespace

CrackTimes crack_times(const fracture::CrackPattern& p) {
    CrackTimes out;
    out.edge.assign(p.cracks.size(), 0.0);
    out.removed.assign(p.mesh.num_faces(), 0.0);
    const Vec2 metres =
        p.surface.periodic() ? p.surface.period() : Vec2(TWO_PI * p.surface.radius(), PI * p.surface.radius());
    const EventGrid grid(p, metres);
    if (grid.size() < 2) return out;
    double first = std::numeric_limits<double>::infinity(), last = -first;
    for (std::size_t i = 0; i < grid.size(); ++i) {
        first = std::min(first, grid.time(i));
        last = std::max(last, grid.time(i));
    }
    if (!(last > first)) return out;
    auto normalised = [&](const Vec2& uv) { return (grid.time(grid.nearest(uv)) - first) / (last - first); };
    for (std::size_t c = 0; c < p.cracks.size(); ++c) {
        const fracture::CrackEdge& e = p.cracks[c];
        const auto corners = p.mesh.face_positions(e.face);
        const auto k = static_cast<std::size_t>(e.edge);
        out.edge[c] = normalised(mid_uv(p, {corners[k], corners[(k + 1) % 3]}));
    }
    for (std::size_t f = 0; f < p.mesh.num_faces(); ++f) {
        if (!p.removed[f]) continue;
        const auto corners = p.mesh.face_positions(mesh::face_id(f));
        out.removed[f] = normalised(mid_uv(p, {corners[0], corners[1], corners[2]}));
    }
    return out;
}

} // namespace crackle::post
