// Step 5 of post::build_pieces (§4.5, Figs. 4.10-4.11): the pieces' triangles. Tops keep one
// vertex per piece and periodic offset, so smooth normals stay per piece; every crack lip gets a
// wall down to the crack's depth, a crack that stops inside the layer a ledge there, removed
// elements a floor. Every triangle winds counter-clockwise seen from outside (a test checks it on
// the plane, the cylinder and the sphere).
#include "core/log.hpp"
#include "post/piece_assembly.hpp"

#include <array>
#include <map>
#include <tuple>

namespace crackle::post::detail {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;

namespace {

/// The triangles' builder: the pieces' vertices (steps 1-4) and the mesh it appends to.
struct TriangleBuilder {
    const fracture::CrackPattern& p;
    const PieceTopology& topo;
    const std::vector<Top>& tops;
    const std::vector<double>& thickness;
    const CrackTimes& times;
    PieceMesh& out;
    const mesh::Surface& surface = p.surface;
    const Mat3& G = p.growth_map;
    const Mat3 G_inv_t = p.growth_map.inverse().transpose();
    /// One output vertex per (piece vertex, offset) on the tops, so smooth normals stay per piece.
    std::map<std::tuple<std::uint32_t, int, int>, std::uint32_t> top_index{};

    /// The tops: one triangle per piece face, and the mean top edge (the facets' scale).
    void add_tops() {
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
    }

    /// Smooth normals over each piece's top (texture frame and world).
    void smooth_top_normals() {
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

    /// A wall at every crack lip: each lip edge a → b drops to the bottom of the layer (or of
    /// the lifted rim), or to the crack's depth with a ledge there.
    void add_walls() {
        std::map<std::pair<std::uint32_t, int>, const fracture::CrackEdge*> crack_of;
        for (const fracture::CrackEdge& c : p.cracks)
            crack_of[{static_cast<std::uint32_t>(ix(c.face)), c.edge}] = &c;
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
                        crack ? static_cast<float>(times.edge[static_cast<std::size_t>(crack - p.cracks.data())])
                              : 0.0f;
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
    }

    /// The floor: the background where elements were removed.
    void add_floor() {
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
    }

    Vec2 corner_shift_uv(const Vec2i& o_) const { return Vec2(o_.x(), o_.y()); }
    Vec3 world_shift(const Vec2i& o_) const {
        return G * (o_.x() * p.mesh.period_vectors[0] + o_.y() * p.mesh.period_vectors[1]);
    }

    /// The top vertex of piece vertex `v` in the periodic copy `off`, made once.
    std::uint32_t emit_top(std::size_t v, const Vec2i& off) {
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
    }

    /// A wall quad q: top a, top b, bottom b, bottom a. Flat normal, facing out of the piece.
    void add_quad(const std::array<PieceVertex, 4>& q) {
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
        // The corners a, b, c, d wind about nw; when that points into the piece the triangles
        // take them the other way round, so that every wall is counter-clockwise seen from
        // outside (where its normal points), as the tops and the floor are.
        const bool inward = nw.dot(right_world) < 0;
        if (inward) nw = -nw;
        nt = nt.norm() > 0 ? Vec3(nt.normalized()) : Vec3::UnitX();
        nw = nw.norm() > 0 ? Vec3(nw.normalized()) : Vec3::UnitX();
        const auto base = static_cast<std::uint32_t>(out.vertices.size());
        for (PieceVertex* v : {&a, &b, &c, &d}) {
            v->normal = nt;
            v->world_normal = nw;
            v->crack = 1.0f;
            out.vertices.push_back(*v);
        }
        if (inward) {
            out.triangles.push_back({base, base + 2, base + 1});
            out.triangles.push_back({base, base + 3, base + 2});
        } else {
            out.triangles.push_back({base, base + 1, base + 2});
            out.triangles.push_back({base, base + 2, base + 3});
        }
        out.lips.push_back({base, base + 1});
    }

    /// A crack that does not go through the layer (mass-spring with several layers, §4.3) has
    /// walls down to its depth only and a floor there: each lip carries a ledge half the crack
    /// wide, so the two lips' ledges meet under the opening.
    void add_ledge(const PieceVertex& a, const PieceVertex& b, double width) {
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
    }
};

} // namespace

void add_triangles(const fracture::CrackPattern& p, const PieceTopology& topo, const std::vector<Top>& tops,
                   const std::vector<double>& thickness, const CrackTimes& times, PieceMesh& out) {
    TriangleBuilder build{p, topo, tops, thickness, times, out};
    build.add_tops();
    build.smooth_top_normals();
    build.add_walls();
    build.add_floor();
    log::debug("pieces: ", out.fragments, " fragments, ", out.top_triangles, " top, ", out.wall_triangles, " wall, ",
               out.floor_triangles, " floor triangles");
}

} // namespace crackle::post::detail
