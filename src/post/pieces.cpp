#include "post/pieces.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "post/crack_times.hpp"
#include "post/piece_assembly.hpp"
#include "sim/fem_model.hpp"

#include <map>
#include <queue>

namespace crackle::post {

using detail::metric_at;
using detail::PieceTopology;
using detail::Top;
using mesh::face_id;
using mesh::FaceId;
using mesh::ix;
using mesh::vertex_id;

Vec2 reference_uv(const mesh::Surface& surface, const Vec3& p0) {
    return surface.uv(p0);
}

namespace {

/// Step 1: the pieces as a mesh of their own, one vertex copy per fragment.
PieceTopology split_by_fragment(const fracture::CrackPattern& p) {
    PieceTopology t;
    t.mesh.periodic = p.mesh.periodic;
    t.mesh.period = p.mesh.period;
    t.mesh.period_vectors = p.mesh.period_vectors;
    std::map<std::pair<std::uint32_t, int>, std::uint32_t> copy;
    for (std::size_t fi = 0; fi < p.mesh.num_faces(); ++fi) {
        if (p.removed[fi]) continue;
        const int frag = p.fragment[fi];
        mesh::Face face = p.mesh.faces[face_id(fi)];
        for (auto& v : face.v) {
            const auto key = std::make_pair(static_cast<std::uint32_t>(ix(v)), frag);
            auto it = copy.find(key);
            if (it == copy.end()) {
                const auto id = static_cast<std::uint32_t>(t.mesh.positions.size());
                t.mesh.positions.push_back(p.mesh.positions[v]);
                if (p.mesh.periodic) t.mesh.domain.push_back(p.mesh.domain[v]);
                t.source_vertex.push_back(key.first);
                t.fragment.push_back(frag);
                it = copy.emplace(key, id).first;
            }
            v = vertex_id(it->second);
        }
        t.mesh.faces.push_back(face);
        t.source_face.push_back(static_cast<std::uint32_t>(fi));
    }
    t.mesh.rebuild_adjacency();
    return t;
}

/// Distance along piece edges from every vertex to the nearest crack lip (∞ without lips).
std::vector<double> distance_to_lips(const mesh::SurfaceMesh& m) {
    const std::size_t nv = m.num_vertices();
    std::vector<double> dist(nv, std::numeric_limits<double>::infinity());
    std::vector<std::vector<std::pair<std::uint32_t, double>>> adj(nv);
    using Item = std::pair<double, std::uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    for (std::size_t fi = 0; fi < m.num_faces(); ++fi) {
        const FaceId f = face_id(fi);
        const auto p = m.face_positions(f);
        for (int k = 0; k < 3; ++k) {
            const auto a = static_cast<std::uint32_t>(ix(m.faces[f].v[static_cast<std::size_t>(k)]));
            const auto b = static_cast<std::uint32_t>(ix(m.faces[f].v[static_cast<std::size_t>((k + 1) % 3)]));
            const double len = (p[static_cast<std::size_t>((k + 1) % 3)] - p[static_cast<std::size_t>(k)]).norm();
            adj[a].emplace_back(b, len);
            adj[b].emplace_back(a, len);
            if (m.neighbor(f, k).face == mesh::NO_FACE) {
                for (std::uint32_t v : {a, b})
                    if (dist[v] > 0) {
                        dist[v] = 0;
                        queue.emplace(0.0, v);
                    }
            }
        }
    }
    while (!queue.empty()) {
        const auto [d, v] = queue.top();
        queue.pop();
        if (d > dist[v]) continue;
        for (const auto& [w, len] : adj[v])
            if (d + len < dist[w]) {
                dist[w] = d + len;
                queue.emplace(dist[w], w);
            }
    }
    return dist;
}

/// Step 2 (§4.5): the displacement of every piece vertex under further drying
/// (post.shrinkage), solved with the wedge FEM on the pieces, bottoms glued; zero without it.
std::vector<Vec3> relax_further_drying(const fracture::CrackPattern& p, const PieceTopology& topo,
                                       const std::vector<double>& thickness, const PostOptions& o) {
    const mesh::Surface& surface = p.surface;
    const std::size_t nv = topo.mesh.num_vertices();
    std::vector<Vec3> w(nv, Vec3::Zero());
    if ((o.shrink_top == 0.0 && o.shrink_bottom == 0.0) || topo.mesh.num_faces() == 0) return w;
    // Stiffness only: the pieces are relaxed, not cracked (no threshold, no toughness).
    std::vector<sim::ElementMaterial> materials(topo.mesh.num_faces());
    for (std::size_t f = 0; f < materials.size(); ++f)
        materials[f].young_modulus = p.young_modulus[topo.source_face[f]];
    sim::LayerFields fields;
    fields.poisson_ratio = p.poisson_ratio;
    fields.vertex_thickness = &thickness;
    fields.face_material = &materials;
    sim::FemOptions fem;
    fem.stiffness_refresh = 0.0; // the stiffness of the shrunk shapes
    fem.tolerance = 1e-8;
    sim::GrowthOptions no_growth;
    no_growth.kind = sim::GrowthKind::None;
    sim::FemModel model(topo.mesh, surface, sim::GrowthField(no_growth, surface.kind()),
                        sim::ShrinkageOptions{o.shrink_top, o.shrink_bottom}, fields, fem);
    std::vector<Vec3> rest(nv);
    for (std::size_t v = 0; v < nv; ++v)
        rest[v] = model.top_position(vertex_id(v));
    model.set_time(1.0);
    model.relax();
    for (std::size_t v = 0; v < nv; ++v)
        w[v] = model.top_position(vertex_id(v)) - rest[v];
    return w;
}

/// How far each piece vertex's top rises (curl, Fig. 4.11 bottom) and drops (the bevel) near
/// the crack lips.
struct RimShape {
    std::vector<double> lift, bevel_drop;
};

/// Step 3: curl lifts the rims of detached pieces; a bevel rounds the lips.
RimShape rim_shape(const PieceTopology& topo, const std::vector<double>& thickness, const PostOptions& o) {
    const std::size_t nv = topo.mesh.num_vertices();
    const std::vector<double> lip_distance = distance_to_lips(topo.mesh);
    RimShape r{std::vector<double>(nv, 0.0), std::vector<double>(nv, 0.0)};
    std::vector<double>&lift = r.lift, &bevel_drop = r.bevel_drop;
    for (std::size_t v = 0; v < nv; ++v) {
        const double h = thickness[v], d = lip_distance[v];
        if (o.curl > 0 && std::isfinite(d)) {
            const double reach = o.curl_width * h;
            lift[v] = o.curl * h * sqr(std::max(0.0, 1.0 - d / reach));
        }
        if (o.bevel > 0 && std::isfinite(d)) bevel_drop[v] = o.bevel * sqr(std::max(0.0, 1.0 - d / o.bevel));
    }
    return r;
}

/// Step 4: each piece vertex's top in texture space and in the world: the simulation's top
/// node relative to its bottom node, the further drying, the rim shape; `max_height` the tallest.
std::vector<Top> place_tops(const fracture::CrackPattern& p, const PieceTopology& topo, const std::vector<Vec3>& w,
                            const RimShape& rim, double& max_height) {
    const mesh::Surface& surface = p.surface;
    const std::size_t nv = topo.mesh.num_vertices();
    const std::vector<double>&lift = rim.lift, &bevel_drop = rim.bevel_drop;
    const Mat3& G = p.growth_map;
    const Mat3 G_inv = G.inverse();
    const Mat3 G_inv_t = G_inv.transpose();
    std::vector<Top> tops(nv);
    max_height = 0;
    for (std::size_t v = 0; v < nv; ++v) {
        const std::uint32_t sv = topo.source_vertex[v];
        const Vec3& P0 = p.mesh.positions[vertex_id(sv)];
        const mesh::TangentFrame f0 = surface.frame(P0);
        const Vec2 metric = metric_at(surface, P0);
        const Vec3 bottom = G * P0;
        const Vec3 n_final = (G_inv_t * f0.n).normalized();
        // Simulation: the top node relative to its bottom node, in-plane part pulled back
        // through the growth map into the reference tangent plane; the normal part is height.
        const Vec3 d = p.deformed[sv] - bottom;
        const double h_sim = d.dot(n_final);
        const Vec3 d_ref = G_inv * (d - h_sim * n_final);
        const double du = d_ref.dot(f0.e_u) + w[v].dot(f0.e_u);
        const double dv = d_ref.dot(f0.e_v) + w[v].dot(f0.e_v);
        Top& t = tops[v];
        const Vec2 uv0 = surface.periodic() ? surface.uv_of_domain(topo.mesh.domain[vertex_id(v)]) : surface.uv(P0);
        t.uv = uv0 + Vec2(du / metric.x(), dv / metric.y());
        t.height = std::max(0.0, h_sim + w[v].dot(f0.n) + lift[v] - bevel_drop[v]);
        t.base = std::max(0.0, h_sim + w[v].dot(f0.n));
        t.world = bottom + G * (du * f0.e_u + dv * f0.e_v) + (t.height) * n_final;
        t.bottom_world = bottom + lift[v] * n_final;
        t.bottom_uv = uv0;
        t.bottom_height = lift[v];
        max_height = std::max(max_height, t.height);
    }
    return tops;
}

/// The crack network from every piece's copy of each pattern vertex at its final place.
std::vector<CrackChain> network_of(const fracture::CrackPattern& p, const PieceTopology& topo,
                                   const std::vector<Top>& tops, const CrackTimes& times) {
    const mesh::Surface& surface = p.surface;
    const std::size_t nv = topo.mesh.num_vertices();
    std::vector<std::vector<Vec2>> copies(p.mesh.num_vertices());
    std::vector<Vec2> metric(p.mesh.num_vertices());
    for (std::size_t v = 0; v < nv; ++v)
        copies[topo.source_vertex[v]].push_back(tops[v].uv);
    for (std::size_t v = 0; v < copies.size(); ++v) {
        const Vec3& P0 = p.mesh.positions[vertex_id(v)];
        metric[v] = metric_at(surface, P0);
        if (copies[v].empty())
            copies[v].push_back(surface.periodic() ? surface.uv_of_domain(p.mesh.domain[vertex_id(v)])
                                                   : surface.uv(P0));
    }
    return crack_chains(p, copies, metric, times);
}

} // namespace

PieceMesh build_pieces(const fracture::CrackPattern& p, const PostOptions& o) {
    PieceMesh out;
    out.kind = p.surface.kind();
    out.periodic = p.surface.periodic();
    out.tile_size = p.surface.period(); // the sphere's is 2πR × πR (mesh::Surface)
    out.fragments = p.num_fragments;
    out.post_curl = o.curl;
    out.post_curl_width = o.curl_width;
    out.post_bevel = o.bevel;
    const CrackTimes times = crack_times(p);

    const PieceTopology topo = split_by_fragment(p);
    std::vector<double> thickness(topo.mesh.num_vertices());
    for (std::size_t v = 0; v < thickness.size(); ++v)
        thickness[v] = p.thickness[topo.source_vertex[v]];
    const std::vector<Vec3> dried = relax_further_drying(p, topo, thickness, o);
    const RimShape rim = rim_shape(topo, thickness, o);
    const std::vector<Top> tops = place_tops(p, topo, dried, rim, out.max_height);
    out.chains = network_of(p, topo, tops, times);
    detail::add_triangles(p, topo, tops, thickness, times, out);
    return out;
}

} // namespace crackle::post
