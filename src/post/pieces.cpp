#include "post/pieces.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "post/crack_times.hpp"
#include "sim/fem_model.hpp"

#include <map>
#include <queue>

namespace crackle::post {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;
using mesh::vertex_id;

Vec2 reference_uv(const mesh::Surface& surface, const Vec3& p0) {
    return surface.uv(p0);
}

namespace {

/// The pieces as a mesh of their own: every fragment gets its own copy of its vertices, so
/// the lips of a crack are separate boundary edges.
struct PieceTopology {
    mesh::SurfaceMesh mesh;
    std::vector<std::uint32_t> source_vertex; ///< piece vertex → pattern vertex
    std::vector<int> fragment;                ///< piece vertex → fragment
    std::vector<std::uint32_t> source_face;   ///< piece face → pattern face
};

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

/// Metres per unit of u and v at a point of the reference surface.
/// u measured from `from`'s side of the sphere's date line (u wraps there; on periodic
/// surfaces the mesh already carries the shifts).
double unwrap_u(double u, double from, bool periodic) {
    if (periodic) return u;
    if (u - from > 0.5) return u - 1.0;
    if (u - from < -0.5) return u + 1.0;
    return u;
}

Vec2 metric_at(const mesh::Surface& s, const Vec3& p0) {
    if (s.periodic()) return s.period();
    const double lat_cos = std::max(1e-3, std::sqrt(sqr(p0.x()) + sqr(p0.y())) / std::max(p0.norm(), 1e-300));
    return Vec2(TWO_PI * s.radius() * lat_cos, PI * s.radius());
}

} // namespace

PieceMesh build_pieces(const fracture::CrackPattern& p, const PostOptions& o) {
    const mesh::Surface& surface = p.surface;
    PieceMesh out;
    out.kind = surface.kind();
    out.periodic = surface.periodic();
    out.tile_size = surface.period(); // the sphere's is 2πR × πR (mesh::Surface)
    out.fragments = p.num_fragments;
    out.post_curl = o.curl;
    out.post_curl_width = o.curl_width;
    out.post_bevel = o.bevel;
    const CrackTimes times = crack_times(p);

    // === 1. Pieces: one vertex copy per fragment
    const PieceTopology topo = split_by_fragment(p);
    const std::size_t nv = topo.mesh.num_vertices();
    std::vector<double> thickness(nv);
    for (std::size_t v = 0; v < nv; ++v)
        thickness[v] = p.thickness[topo.source_vertex[v]];

    // === 2. Relaxation under further drying: the wedge FEM on the pieces, bottom glued
    std::vector<Vec3> w(nv, Vec3::Zero());
    if ((o.shrink_top != 0.0 || o.shrink_bottom != 0.0) && topo.mesh.num_faces() > 0) {
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
    }

    // === 3. Curl: detached pieces lift their rims (Fig. 4.11 bottom)
    const std::vector<double> lip_distance = distance_to_lips(topo.mesh);
    std::vector<double> lift(nv, 0.0), bevel_drop(nv, 0.0);
    for (std::size_t v = 0; v < nv; ++v) {
        const double h = thickness[v], d = lip_distance[v];
        if (o.curl > 0 && std::isfinite(d)) {
            const double reach = o.curl_width * h;
            lift[v] = o.curl * h * sqr(std::max(0.0, 1.0 - d / reach));
        }
        if (o.bevel > 0 && std::isfinite(d)) bevel_drop[v] = o.bevel * sqr(std::max(0.0, 1.0 - d / o.bevel));
    }

    // === 4. Top vertices in texture space and in the world
    const Mat3& G = p.growth_map;
    const Mat3 G_inv = G.inverse();
    const Mat3 G_inv_t = G_inv.transpose();
    struct Top {
        Vec2 uv; // canonical (before corner offsets)
        double height;
        double base; // before curl and lip rounding
        Vec3 world;  // canonical copy
        Vec3 bottom_world;
        Vec2 bottom_uv;
        double bottom_height;
    };
    std::vector<Top> tops(nv);
    double max_height = 0;
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
    out.max_height = max_height;
    {
        // The crack network from every piece's copy of each pattern vertex at its final place.
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
        out.chains = crack_chains(p, copies, metric, times);
    }

    // === 5. Triangles: tops, walls at crack lips, floor under removed elements
    auto corner_shift_uv = [&](const Vec2i& o_) { return Vec2(o_.x(), o_.y()); };
    auto world_shift = [&](const Vec2i& o_) {
        return G * (o_.x() * p.mesh.period_vectors[0] + o_.y() * p.mesh.period_vectors[1]);
    };
    // One output vertex per (piece vertex, offset) on the tops, so smooth normals stay per piece.
    std::map<std::tuple<std::uint32_t, int, int>, std::uint32_t> top_index;
    auto emit_top = [&](std::size_t v, const Vec2i& off) {
        const auto key = std::make_tuple(static_cast<std::uint32_t>(v), off.x(), off.y());
        const auto it = top_index.find(key);
        if (it != top_index.end()) return it->second;
        PieceVertex pv;
        pv.uv = tops[v].uv + corner_shift_uv(off);
        pv.height = tops[v].height;
        pv.base_height = tops[v].base;
        pv.position = tops[v].world + world_shift(off);
        pv.fragment = topo.fragment[v];
        pv.crack = 0.0f;
        const auto id = static_cast<std::uint32_t>(out.vertices.size());
        out.vertices.push_back(pv);
        top_index.emplace(key, id);
        return id;
    };
    for (std::size_t fi = 0; fi < topo.mesh.num_faces(); ++fi) {
        const mesh::Face& face = topo.mesh.faces[face_id(fi)];
        std::array<std::uint32_t, 3> tri{};
        for (std::size_t k = 0; k < 3; ++k)
            tri[k] = emit_top(ix(face.v[k]), face.offset[k]);
        out.triangles.push_back(tri);
    }
    out.top_triangles = out.triangles.size();
    {
        double length = 0;
        for (const auto& tri : out.triangles)
            for (std::size_t k = 0; k < 3; ++k)
                length += (out.vertices[tri[k]].position - out.vertices[tri[(k + 1) % 3]].position).norm();
        out.element_size = out.triangles.empty() ? 0.0 : length / (3.0 * double(out.triangles.size()));
    }

    // Smooth normals over each piece's top (texture frame and world).
    {
        std::vector<Vec3> tex_n(out.vertices.size(), Vec3::Zero()), world_n(out.vertices.size(), Vec3::Zero());
        for (const auto& tri : out.triangles) {
            const PieceVertex &a = out.vertices[tri[0]], &b = out.vertices[tri[1]], &c = out.vertices[tri[2]];
            const Vec2 m = metric_at(surface, p.surface.periodic() ? Vec3(Vec3::Zero())
                                                                   : Vec3(a.position.normalized() * surface.radius()));
            // On the sphere u wraps at the date line: measure each corner's u from a's side, or a
            // triangle across the seam spans the whole texture backwards and its normal points
            // into the surface (the seam columns of _NormalGL did).
            auto tex = [&](const PieceVertex& q) {
                return Vec3(unwrap_u(q.uv.x(), a.uv.x(), p.surface.periodic()) * m.x(), q.uv.y() * m.y(), q.height);
            };
            const Vec3 nt = (tex(b) - tex(a)).cross(tex(c) - tex(a));
            const Vec3 nw = (b.position - a.position).cross(c.position - a.position);
            for (std::uint32_t i : tri) {
                tex_n[i] += nt;
                world_n[i] += nw;
            }
        }
        for (std::size_t i = 0; i < out.vertices.size(); ++i) {
            out.vertices[i].normal = tex_n[i].norm() > 0 ? Vec3(tex_n[i].normalized()) : Vec3::UnitZ();
            out.vertices[i].world_normal = world_n[i].norm() > 0 ? Vec3(world_n[i].normalized()) : Vec3::UnitZ();
        }
    }

    // Walls: each lip edge a → b drops to the bottom of the layer (or of the lifted rim).
    auto add_quad = [&](const std::array<PieceVertex, 4>& q) {
        // q: top a, top b, bottom b, bottom a. Flat normal, facing out of the piece.
        PieceVertex a = q[0], b = q[1], c = q[2], d = q[3];
        const Vec2 m = out.tile_size;
        auto tex = [&](const PieceVertex& v) {
            return Vec3(unwrap_u(v.uv.x(), a.uv.x(), p.surface.periodic()) * m.x(), v.uv.y() * m.y(), v.height);
        };
        Vec3 nt = (tex(b) - tex(a)).cross(tex(d) - tex(a));
        Vec3 nw = (b.position - a.position).cross(d.position - a.position);
        // Outward is to the right of a → b seen from above.
        const Vec3 right_tex = (tex(b) - tex(a)).cross(Vec3::UnitZ());
        if (nt.dot(right_tex) < 0) nt = -nt;
        const Vec3 up_world = (a.position - d.position);
        const Vec3 right_world = (b.position - a.position).cross(up_world);
        if (nw.dot(right_world) < 0) nw = -nw;
        nt = nt.norm() > 0 ? Vec3(nt.normalized()) : Vec3::UnitX();
        nw = nw.norm() > 0 ? Vec3(nw.normalized()) : Vec3::UnitX();
        const auto base = static_cast<std::uint32_t>(out.vertices.size());
        for (PieceVertex* v : {&a, &b, &c, &d}) {
            v->normal = nt;
            v->world_normal = nw;
            v->crack = 1.0f;
            out.vertices.push_back(*v);
        }
        out.triangles.push_back({base, base + 1, base + 2});
        out.triangles.push_back({base, base + 2, base + 3});
        out.lips.push_back({base, base + 1});
    };
    // A crack that does not go through the layer (mass-spring with several layers, §4.3) has
    // walls down to its depth only and a floor there: each lip carries a ledge half the crack
    // wide, so the two lips' ledges meet under the opening.
    std::map<std::pair<std::uint32_t, int>, const fracture::CrackEdge*> crack_of;
    for (const fracture::CrackEdge& c : p.cracks)
        crack_of[{static_cast<std::uint32_t>(ix(c.face)), c.edge}] = &c;
    auto add_ledge = [&](const PieceVertex& a, const PieceVertex& b, double width) {
        const Vec2 m = out.tile_size;
        const Vec2 along((b.uv - a.uv).x() * m.x(), (b.uv - a.uv).y() * m.y());
        if (along.norm() <= 0) return;
        const Vec2 right = Vec2(along.y(), -along.x()).normalized() * width; // metres, texture frame
        const Vec2 right_uv(right.x() / m.x(), right.y() / m.y());
        // Up: the top's normal made perpendicular to the lip; right: out of the piece.
        const Vec3 t = (b.position - a.position).normalized();
        const Vec3 n_world = (a.world_normal - a.world_normal.dot(t) * t).normalized();
        const Vec3 right_world = t.cross(n_world) * width;
        std::array<PieceVertex, 4> q{a, b, b, a};
        q[2].uv += right_uv;
        q[3].uv += right_uv;
        q[2].position += right_world;
        q[3].position += right_world;
        const auto base = static_cast<std::uint32_t>(out.vertices.size());
        for (PieceVertex& v : q) {
            v.normal = Vec3::UnitZ();
            v.world_normal = n_world;
            v.crack = 1.0f;
            v.fragment = -1;
            out.vertices.push_back(v);
        }
        // Counter-clockwise seen from above: a, a + right, b + right, b.
        out.triangles.push_back({base, base + 3, base + 2});
        out.triangles.push_back({base, base + 2, base + 1});
        out.floor_triangles += 2;
    };
    for (std::size_t fi = 0; fi < topo.mesh.num_faces(); ++fi) {
        const FaceId f = face_id(fi);
        const mesh::Face& face = topo.mesh.faces[f];
        for (int k = 0; k < 3; ++k) {
            if (topo.mesh.neighbor(f, k).face != mesh::NO_FACE) continue;
            const auto ka = static_cast<std::size_t>(k), kb = static_cast<std::size_t>((k + 1) % 3);
            const std::size_t va = ix(face.v[ka]), vb = ix(face.v[kb]);
            const auto it = crack_of.find({topo.source_face[fi], k});
            const fracture::CrackEdge* crack = it == crack_of.end() ? nullptr : it->second;
            std::array<PieceVertex, 4> q;
            q[0] = out.vertices[emit_top(va, face.offset[ka])];
            q[1] = out.vertices[emit_top(vb, face.offset[kb])];
            for (std::size_t j = 0; j < 2; ++j) {
                q[j].crack_time =
                    crack ? static_cast<float>(times.edge[static_cast<std::size_t>(crack - p.cracks.data())]) : 0.0f;
                q[j].crack_opening = crack ? static_cast<float>(crack->opening) : 0.0f;
            }
            bool partial = false;
            for (int s = 0; s < 2; ++s) {
                const std::size_t v = s == 0 ? vb : va;
                const Vec2i& off = s == 0 ? face.offset[kb] : face.offset[ka];
                // Share of the way down the wall goes: depth over the local thickness.
                const double share = crack && crack->depth > 0 ? std::min(1.0, crack->depth / thickness[v]) : 1.0;
                partial = partial || share < 0.999;
                const PieceVertex& top = q[static_cast<std::size_t>(1 - s)];
                PieceVertex bot;
                bot.uv = top.uv + share * (tops[v].bottom_uv + corner_shift_uv(off) - top.uv);
                bot.height = top.height + share * (tops[v].bottom_height - top.height);
                bot.base_height = (1.0 - share) * top.base_height;
                bot.crack_time = top.crack_time;
                bot.crack_opening = top.crack_opening;
                bot.position = top.position + share * (tops[v].bottom_world + world_shift(off) - top.position);
                bot.fragment = topo.fragment[v];
                q[static_cast<std::size_t>(2 + s)] = bot;
            }
            add_quad(q);
            out.wall_triangles += 2;
            if (partial && crack->opening > 0) {
                PieceVertex a = q[3], b = q[2];
                a.world_normal = q[0].world_normal;
                b.world_normal = q[1].world_normal;
                add_ledge(a, b, 0.55 * crack->opening);
            }
        }
    }

    // Floor: the background where elements were removed.
    for (std::size_t fi = 0; fi < p.mesh.num_faces(); ++fi) {
        if (!p.removed[fi]) continue;
        const FaceId f = face_id(fi);
        const auto base = static_cast<std::uint32_t>(out.vertices.size());
        for (int k = 0; k < 3; ++k) {
            const mesh::Face& face = p.mesh.faces[f];
            const Vec3& P0 = p.mesh.positions[face.v[static_cast<std::size_t>(k)]];
            PieceVertex fv;
            const Vec2i& off = face.offset[static_cast<std::size_t>(k)];
            fv.uv = (surface.periodic() ? surface.uv_of_domain(p.mesh.domain[face.v[static_cast<std::size_t>(k)]])
                                        : surface.uv(P0))
                    + corner_shift_uv(off);
            fv.height = 0.0;
            fv.position = G * P0 + world_shift(off);
            fv.world_normal = (G_inv_t * surface.normal(P0)).normalized();
            fv.normal = Vec3::UnitZ();
            fv.fragment = -1;
            fv.crack = 1.0f;
            fv.crack_time = static_cast<float>(times.removed[fi]);
            out.vertices.push_back(fv);
        }
        out.triangles.push_back({base, base + 1, base + 2});
        ++out.floor_triangles;
    }
    log::debug("pieces: ", out.fragments, " fragments, ", out.top_triangles, " top, ", out.wall_triangles, " wall, ",
               out.floor_triangles, " floor triangles");
    return out;
}

} // namespace crackle::post
