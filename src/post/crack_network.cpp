#include "post/crack_network.hpp"

#include "fracture/hanging_splits.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <tuple>

namespace crackle::post {

using mesh::face_id;
using mesh::ix;

namespace {

/// The network as a graph: nodes with texture coordinates, links with the crack's opening and time.
struct Graph {
    std::vector<Vec2> uv;
    std::vector<Vec2> metric; ///< metres per unit of u and v at the node
    std::vector<std::vector<std::uint32_t>> adjacency;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<float, float>> link; ///< (a < b) → opening, time

    std::uint32_t add_node(const Vec2& at, const Vec2& metres) {
        uv.push_back(at);
        metric.push_back(metres);
        adjacency.emplace_back();
        return static_cast<std::uint32_t>(uv.size() - 1);
    }
    void add_link(std::uint32_t a, std::uint32_t b, float opening, float time) {
        if (a == b) return;
        const auto key = std::minmax(a, b);
        const auto [it, inserted] = link.emplace(key, std::make_pair(opening, time));
        if (!inserted) { // the other lip of the same crack edge: the opening is the pair's mean
            it->second.first = 0.5f * (it->second.first + opening);
            it->second.second = std::min(it->second.second, time);
            return;
        }
        adjacency[a].push_back(b);
        adjacency[b].push_back(a);
    }
};

/// The nearest periodic image of `to` as seen from `from` (u always wraps; v on periodic surfaces).
Vec2 nearest_image(const Vec2& from, Vec2 to, bool periodic) {
    to.x() -= std::round(to.x() - from.x());
    if (periodic) to.y() -= std::round(to.y() - from.y());
    return to;
}

/// One side of a crack edge: its nodes and its end points' final places.
struct Lip {
    std::uint32_t a, b;
    Vec2 at_a, at_b, metric;
    Vec2 at(std::uint32_t node) const { return node == a ? at_a : at_b; }
};

using Key = std::pair<std::uint32_t, std::uint32_t>;

struct HangingSides {
    std::set<Key> coarse;      ///< lips whose other side runs through hanging nodes: dropped
    std::map<Key, double> gap; ///< the finer side's links: their gap to the coarse lip (m)
    /// The hanging nodes' places on the coarse lip across the gap: the other side of the crack
    /// there, which the node has no copy on (a stem ending on a bar at a hanging node has its two
    /// corners on the bar's near lip and none on the far one).
    std::map<std::uint32_t, Vec2> across;
};

/// The crack edges split on one side only (fracture/hanging_splits.hpp), with each finer link's
/// gap: the mean separation of its end points from the coarse lip at their places along it.
HangingSides hanging_sides(const std::vector<Lip>& lips, const std::map<Key, std::vector<std::size_t>>& sides,
                           const std::vector<Vec3>& reference, const fracture::CrackPattern& p) {
    const bool periodic = p.surface.periodic();
    std::vector<fracture::NodePair> single;
    for (const auto& [key, list] : sides)
        if (list.size() == 1) single.push_back(key);
    HangingSides out;
    for (const fracture::HangingSplit& split :
         fracture::hanging_splits(single, reference, periodic ? p.mesh.period : Vec2::Zero())) {
        out.coarse.insert(split.coarse);
        const Lip& coarse = lips[sides.at(split.coarse).front()];
        const auto [a, b] = split.coarse;
        const Vec2 ca = coarse.at(a), cb = nearest_image(ca, coarse.at(b), periodic);
        for (std::size_t i = 0; i + 1 < split.path.size(); ++i) {
            const Key fine_key = std::minmax(split.path[i], split.path[i + 1]);
            const Lip& fine = lips[sides.at(fine_key).front()];
            double gap = 0;
            for (const std::size_t k : {i, i + 1}) {
                const Vec2 there = (1 - split.t[k]) * ca + split.t[k] * cb;
                gap +=
                    0.5
                    * (nearest_image(there, fine.at(split.path[k]), periodic) - there).cwiseProduct(fine.metric).norm();
            }
            out.gap[fine_key] = gap;
            if (i > 0) out.across[split.path[i]] = (1 - split.t[i]) * ca + split.t[i] * cb;
        }
    }
    return out;
}

/// The centre of the smallest circle round `points` (texture coordinates; distances in metres
/// through `metres`, per unit of u and v): where a junction's pieces' corners are equally far;
/// the point itself where there is one.
Vec2 enclosing_centre(const std::vector<Vec2>& points, const Vec2& metres) {
    const std::size_t n = points.size();
    std::vector<Vec2> q(n);
    for (std::size_t i = 0; i < n; ++i)
        q[i] = points[i].cwiseProduct(metres);
    Vec2 best = Vec2::Zero();
    double best_r = std::numeric_limits<double>::infinity();
    auto consider = [&](const Vec2& c, double r) {
        if (r >= best_r) return;
        for (const Vec2& p : q)
            if ((p - c).norm() > r * (1 + 1e-9) + 1e-12) return;
        best = c, best_r = r;
    };
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
            consider(0.5 * (q[i] + q[j]), 0.5 * (q[i] - q[j]).norm());
            for (std::size_t k = j + 1; k < n; ++k) {
                const Vec2 a = q[j] - q[i], b = q[k] - q[i];
                const double d = 2 * (a.x() * b.y() - a.y() * b.x());
                if (std::abs(d) < 1e-18) continue;
                const Vec2 c(b.y() * a.squaredNorm() - a.y() * b.squaredNorm(),
                             a.x() * b.squaredNorm() - b.x() * a.squaredNorm());
                consider(q[i] + c / d, (c / d).norm());
            }
        }
    if (!std::isfinite(best_r)) return points.front();
    return best.cwiseQuotient(metres);
}

Graph edge_graph(const fracture::CrackPattern& p, const std::vector<std::vector<Vec2>>& copies,
                 const std::vector<Vec2>& metric, const CrackTimes& times) {
    Graph g;
    const bool periodic = p.surface.periodic();
    // A pattern vertex's final place: the mean of its copies.
    auto place = [&](mesh::VertexId v) {
        const std::vector<Vec2>& c = copies[ix(v)];
        Vec2 sum = Vec2::Zero();
        for (const Vec2& uv : c)
            sum += nearest_image(c.front(), uv, periodic);
        return Vec2(sum / double(c.size()));
    };
    // Copies of one reference point (a split's two sides) are one node, at the centre of the
    // smallest circle round their places (in metres).
    std::map<std::array<double, 3>, std::uint32_t> node_of;
    std::vector<Vec2> node_metric;
    std::vector<std::vector<Vec2>> node_copies; // per node: its pieces' copies, next to the first
    std::vector<Vec3> reference; // per node: the reference position (domain coordinates on a periodic domain)
    auto node = [&](mesh::VertexId v) {
        const Vec3 key3 = periodic ? Vec3(p.mesh.domain[v].x(), p.mesh.domain[v].y(), 0.0) : p.mesh.positions[v];
        // Copies of a point sit at the same reference position up to round-off: keyed to 1 µm.
        auto q = [](double x) { return std::round(x * 1e6); };
        const auto [it, inserted] = node_of.emplace(std::array<double, 3>{q(key3.x()), q(key3.y()), q(key3.z())},
                                                    static_cast<std::uint32_t>(node_copies.size()));
        if (inserted) {
            reference.push_back(key3);
            node_metric.push_back(metric[ix(v)]);
            node_copies.emplace_back();
        }
        auto& cs = node_copies[it->second];
        for (const Vec2& c : copies[ix(v)])
            cs.push_back(nearest_image(cs.empty() ? c : cs.front(), c, periodic));
        return it->second;
    };
    // Each crack edge is one lip; a link's two lips give its gap (the mean separation of their
    // end points, in metres), so a junction does not widen the links that meet there.
    std::vector<Lip> lips(p.cracks.size());
    for (std::size_t c = 0; c < p.cracks.size(); ++c) {
        const auto& face = p.mesh.faces[p.cracks[c].face];
        const auto k = static_cast<std::size_t>(p.cracks[c].edge);
        const mesh::VertexId va = face.v[k], vb = face.v[(k + 1) % 3];
        lips[c] = {node(va), node(vb), place(va), place(vb), metric[ix(va)]};
    }
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::size_t>> sides;
    for (std::size_t c = 0; c < lips.size(); ++c)
        sides[std::minmax(lips[c].a, lips[c].b)].push_back(c);
    // A lip with no partner on the same two nodes is one side of a crack whose other side was
    // split at hanging nodes (a → m → b on one side, a → b on the other): the finer side is the
    // crack's path, measured against the coarse lip; the coarse link is dropped, so the network
    // has no spurious triangles there.
    const HangingSides hanging = hanging_sides(lips, sides, reference, p);
    // A node lies where its pieces' corners are equally far (the centre of the smallest circle
    // round them): the middle of the gap along a crack, and at a junction the point of the gap's
    // centre lines, not the corners' mean (a T's mean lies a sixth of the bar's opening towards
    // the stem). A hanging node takes the far lip's place across the gap as its other side.
    for (std::size_t n = 0; n < node_copies.size(); ++n) {
        std::vector<Vec2>& cs = node_copies[n];
        if (const auto it = hanging.across.find(static_cast<std::uint32_t>(n)); it != hanging.across.end())
            cs.push_back(nearest_image(cs.front(), it->second, periodic));
        // (a vertex's copies were added once per lip it ends: the same places, exactly)
        std::sort(cs.begin(), cs.end(),
                  [](const Vec2& a, const Vec2& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
        cs.erase(std::unique(cs.begin(), cs.end()), cs.end());
        g.add_node(enclosing_centre(cs, node_metric[n]), node_metric[n]);
    }
    for (const auto& [key, list] : sides) {
        if (hanging.coarse.count(key)) continue;
        double gap = 0;
        for (std::size_t i = 0; i < list.size(); ++i)
            for (std::size_t j = i + 1; j < list.size(); ++j) {
                const Lip &l = lips[list[i]], &m = lips[list[j]];
                const Vec2 ma = l.a == m.a ? m.at_a : m.at_b, mb = l.a == m.a ? m.at_b : m.at_a;
                const double da = (nearest_image(l.at_a, ma, periodic) - l.at_a).cwiseProduct(l.metric).norm();
                const double db = (nearest_image(l.at_b, mb, periodic) - l.at_b).cwiseProduct(l.metric).norm();
                gap = std::max(gap, 0.5 * (da + db));
            }
        if (const auto it = hanging.gap.find(key); it != hanging.gap.end()) gap = it->second;
        float time = 1.0f;
        for (std::size_t c : list)
            time = std::min(time, static_cast<float>(times.edge.empty() ? 0.0 : times.edge[c]));
        g.add_link(key.first, key.second, static_cast<float>(gap), time);
    }
    return g;
}

/// Removed elements linked to removed neighbours, each at its centroid; the opening is the
/// element's width across (twice its area over its longest edge, in metres).
Graph removal_graph(const fracture::CrackPattern& p, const std::vector<Vec2>& vertex_uv,
                    const std::vector<Vec2>& metric, const CrackTimes& times) {
    Graph g;
    const std::size_t nf = p.mesh.num_faces();
    std::vector<std::int64_t> node_of(nf, -1);
    std::vector<float> width(nf, 0.0f);
    for (std::size_t f = 0; f < nf; ++f) {
        if (!p.removed[f]) continue;
        const auto& face = p.mesh.faces[face_id(f)];
        const Vec2 a = vertex_uv[ix(face.v[0])];
        const Vec2 b = nearest_image(a, vertex_uv[ix(face.v[1])], p.surface.periodic());
        const Vec2 c = nearest_image(a, vertex_uv[ix(face.v[2])], p.surface.periodic());
        node_of[f] = g.add_node((a + b + c) / 3.0, metric[ix(face.v[0])]);
        const auto pts = p.mesh.face_positions(face_id(f));
        const double area = 0.5 * (pts[1] - pts[0]).cross(pts[2] - pts[0]).norm();
        const double longest =
            std::max({(pts[1] - pts[0]).norm(), (pts[2] - pts[1]).norm(), (pts[0] - pts[2]).norm(), 1e-300});
        width[f] = static_cast<float>(2.0 * area / longest);
    }
    for (std::size_t f = 0; f < nf; ++f) {
        if (node_of[f] < 0) continue;
        for (int k = 0; k < 3; ++k) {
            const mesh::FaceNeighbor nb = p.mesh.neighbor(face_id(f), k);
            if (nb.face == mesh::NO_FACE || node_of[ix(nb.face)] < 0) continue;
            const std::size_t h = ix(nb.face);
            g.add_link(static_cast<std::uint32_t>(node_of[f]), static_cast<std::uint32_t>(node_of[h]),
                       0.5f * (width[f] + width[h]),
                       static_cast<float>(std::min(times.removed.empty() ? 0.0 : times.removed[f],
                                                   times.removed.empty() ? 0.0 : times.removed[h])));
        }
    }
    return g;
}

} // namespace

std::vector<CrackChain> crack_chains(const fracture::CrackPattern& p, const std::vector<std::vector<Vec2>>& copies,
                                     const std::vector<Vec2>& metric, const CrackTimes& times) {
    const bool removal = std::any_of(p.removed.begin(), p.removed.end(), [](char r) { return r != 0; });
    Graph g;
    if (removal) {
        std::vector<Vec2> vertex_uv(copies.size(), Vec2::Zero());
        for (std::size_t v = 0; v < copies.size(); ++v) {
            for (const Vec2& uv : copies[v])
                vertex_uv[v] += nearest_image(copies[v].front(), uv, p.surface.periodic());
            if (!copies[v].empty()) vertex_uv[v] /= double(copies[v].size());
        }
        g = removal_graph(p, vertex_uv, metric, times);
    } else {
        g = edge_graph(p, copies, metric, times);
    }
    const bool periodic = p.surface.periodic();
    // Per node: the mean opening and the earliest time of the links that meet there.
    std::vector<float> node_opening(g.uv.size(), 0.0f), node_time(g.uv.size(), 1.0f);
    for (std::uint32_t u = 0; u < g.adjacency.size(); ++u) {
        double sum = 0;
        for (std::uint32_t w : g.adjacency[u]) {
            const std::pair<std::uint32_t, std::uint32_t> key = std::minmax(u, w);
            const auto& l = g.link.at(key);
            sum += l.first;
            node_time[u] = std::min(node_time[u], l.second);
        }
        if (!g.adjacency[u].empty()) node_opening[u] = static_cast<float>(sum / double(g.adjacency[u].size()));
    }
    // Through a junction the crack that runs on (the two links closest to a straight line,
    // turning less than 60°) is one chain: a T's bar is one curve and its stem ends on it, so
    // smoothing keeps the bar straight through the junction and its groove has no seam there.
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> partner; ///< (node, from) → on to
    for (std::uint32_t u = 0; u < g.adjacency.size(); ++u) {
        const auto& adj = g.adjacency[u];
        if (adj.size() == 2) {
            partner[{u, adj[0]}] = adj[1], partner[{u, adj[1]}] = adj[0];
            continue;
        }
        if (adj.size() < 3) continue;
        std::vector<Vec2> dir(adj.size());
        for (std::size_t k = 0; k < adj.size(); ++k)
            dir[k] = (nearest_image(g.uv[u], g.uv[adj[k]], periodic) - g.uv[u]).cwiseProduct(g.metric[u]).normalized();
        std::vector<std::tuple<double, std::size_t, std::size_t>> pairs; // (cosine, a, b): −1 is straight on
        for (std::size_t a = 0; a < adj.size(); ++a)
            for (std::size_t b = a + 1; b < adj.size(); ++b)
                pairs.emplace_back(dir[a].dot(dir[b]), a, b);
        std::sort(pairs.begin(), pairs.end());
        std::vector<char> paired(adj.size(), 0);
        for (const auto& [cosine, a, b] : pairs) {
            if (cosine > -0.5 || paired[a] || paired[b]) continue;
            paired[a] = paired[b] = 1;
            partner[{u, adj[a]}] = adj[b], partner[{u, adj[b]}] = adj[a];
        }
    }
    auto on_from = [&](std::uint32_t node, std::uint32_t from) -> std::int64_t {
        const auto it = partner.find({node, from});
        return it == partner.end() ? std::int64_t{-1} : std::int64_t{it->second};
    };
    std::vector<CrackChain> chains;
    std::set<std::pair<std::uint32_t, std::uint32_t>> used;
    auto take = [&](std::uint32_t a, std::uint32_t b) { return used.emplace(std::minmax(a, b)).second; };
    auto link = [&](std::uint32_t a, std::uint32_t b) {
        const std::pair<std::uint32_t, std::uint32_t> key = std::minmax(a, b);
        return g.link.at(key);
    };
    // Walks from `from` through `first` along nodes of degree 2 (as statistics' chains do).
    auto walk = [&](std::uint32_t from, std::uint32_t first) {
        CrackChain c;
        c.uv.push_back(g.uv[from]);
        c.tip_front = g.adjacency[from].size() == 1;
        std::vector<std::pair<float, float>> links;
        std::uint32_t prev = from, cur = first;
        while (true) {
            links.push_back(link(prev, cur));
            c.uv.push_back(nearest_image(c.uv.back(), g.uv[cur], periodic));
            if (cur == from) {
                c.closed = on_from(from, prev) == std::int64_t(first);
                break;
            }
            const std::int64_t on = on_from(cur, prev);
            if (on < 0) {
                c.tip_back = g.adjacency[cur].size() == 1;
                break;
            }
            const auto next = static_cast<std::uint32_t>(on);
            if (!take(cur, next)) break;
            prev = cur;
            cur = next;
        }
        // Point values: the mean of the links on either side; a chain's end takes its node's
        // values, so that every chain meeting at a junction starts alike there (and a tip is
        // closed: the crack has not opened where it ends).
        const std::size_t n = c.uv.size();
        c.opening.resize(n);
        c.time.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            const auto& l0 = links[std::min(i, links.size() - 1)];
            const auto& l1 = links[i == 0 ? 0 : i - 1];
            c.opening[i] = 0.5f * (l0.first + l1.first);
            c.time[i] = std::min(l0.second, l1.second);
        }
        if (!c.closed) {
            for (const auto& [i, at] : {std::pair<std::size_t, std::uint32_t>{0, from}, {n - 1, cur}}) {
                c.opening[i] = g.adjacency[at].size() == 1 ? 0.0f : node_opening[at];
                c.time[i] = node_time[at];
            }
        }
        return c;
    };
    for (int pass = 0; pass < 2; ++pass) // from the chains' ends first, then the closed loops
        for (std::uint32_t u = 0; u < g.adjacency.size(); ++u)
            for (std::uint32_t w : g.adjacency[u])
                if ((pass == 1 || on_from(u, w) < 0) && take(u, w)) chains.push_back(walk(u, w));
    return chains;
}

} // namespace crackle::post
