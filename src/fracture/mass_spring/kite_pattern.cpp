/// @file The crack pattern of a finished mass-spring run (§4.4-4.5): the masses' Voronoi cells as
/// kites, one per side of each Delaunay edge, cut along the Voronoi edges of broken top-layer
/// springs, at the masses' final places, with a crack lip per opened Voronoi edge.
#include "fracture/mass_spring/mass_spring_internal.hpp"
#include "mesh/cut.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace crackle::fracture {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;
using mesh::vertex_id;

namespace {

/// The point standing for a Delaunay face in its dual: the circumcentre if it lies inside the
/// triangle (then the cells are exactly Voronoi), else the centroid (obtuse triangles, whose
/// circumcentre would fold the cells over).
Vec3 dual_point(const std::array<Vec3, 3>& p) {
    const Vec3 a = p[1] - p[0], b = p[2] - p[0];
    const Vec3 axb = a.cross(b);
    const Vec3 cc =
        p[0] + (b.squaredNorm() * axb.cross(a) + a.squaredNorm() * b.cross(axb)) / (2.0 * axb.squaredNorm());
    // Barycentric coordinates of cc.
    const double area = axb.norm();
    auto sub = [&](const Vec3& u, const Vec3& v, const Vec3& w) {
        return (v - u).cross(w - u).dot(axb) / (area * area);
    };
    const double w0 = sub(cc, p[1], p[2]), w1 = sub(p[0], cc, p[2]), w2 = 1.0 - w0 - w1;
    // Well inside: exact Voronoi. Near an edge (right triangles) the kites would be slivers.
    if (std::min({w0, w1, w2}) >= 0.05) return cc;
    return (p[0] + p[1] + p[2]) / 3.0;
}

/// What the kites keep of the lattice: each kite vertex's mass or dual point, each kite's spring.
struct Kites {
    std::vector<mesh::VertexId> origin;   ///< kite vertex → lattice vertex (< nv) or nv + Delaunay face
    std::vector<std::size_t> kite_spring; ///< top-layer spring of each kite's Voronoi edge
};

/// The kites' mesh in `p.mesh`, cut open along broken springs: the masses, one dual point per
/// Delaunay face, and for Delaunay edge a → b of face T (neighbour T') the kite (a, d_T', d_T)
/// of cell a and (b, d_T, d_T') of cell b; the Voronoi edge d_T–d_T' separates them.
Kites kite_mesh(const MassSpringModel& model, CrackPattern& p) {
    const auto& springs = model.springs();
    const auto& dm = model.mesh();
    const mesh::Surface& surface = model.surface();
    const std::size_t nv = dm.num_vertices(), nf = dm.num_faces();
    const int L = model.layers();
    mesh::SurfaceMesh& km = p.mesh;
    km.periodic = dm.periodic;
    km.period = dm.period;
    km.period_vectors = dm.period_vectors;
    // Vertices: the masses, then one dual point per Delaunay face.
    std::vector<Vec2i> dual_offset(nf, Vec2i::Zero());
    for (std::size_t v = 0; v < nv; ++v) {
        km.positions.push_back(dm.positions[vertex_id(v)]);
        if (dm.periodic) km.domain.push_back(dm.domain[vertex_id(v)]);
    }
    for (std::size_t fi = 0; fi < nf; ++fi) {
        const FaceId f = face_id(fi);
        const Vec3 d3 = dual_point(dm.face_positions(f));
        if (dm.periodic) {
            // The same point in the unrolled domain: barycentric weights carry over.
            const Vec2 a = dm.corner_domain(f, 0), b = dm.corner_domain(f, 1), c = dm.corner_domain(f, 2);
            const auto pos = dm.face_positions(f);
            const Vec3 n = (pos[1] - pos[0]).cross(pos[2] - pos[0]);
            const double w0 = (pos[1] - d3).cross(pos[2] - d3).dot(n) / n.squaredNorm();
            const double w1 = (pos[2] - d3).cross(pos[0] - d3).dot(n) / n.squaredNorm();
            const Vec2 unwrapped = w0 * a + w1 * b + (1 - w0 - w1) * c;
            const Vec2 canonical(wrap(unwrapped.x(), dm.period.x()), wrap(unwrapped.y(), dm.period.y()));
            dual_offset[fi] = Vec2i(static_cast<int>(std::lround((unwrapped.x() - canonical.x()) / dm.period.x())),
                                    static_cast<int>(std::lround((unwrapped.y() - canonical.y()) / dm.period.y())));
            km.domain.push_back(canonical);
            km.positions.push_back(surface.position(canonical));
        } else {
            km.positions.push_back(surface.project(d3));
        }
    }
    std::vector<std::array<char, 3>> cut;
    Kites kites;
    std::vector<std::size_t>& kite_spring = kites.kite_spring;
    std::map<std::pair<std::uint32_t, int>, std::size_t> spring_index;
    for (std::size_t si = 0; si < springs.size(); ++si)
        if (springs[si].layer == L - 1) spring_index[{springs[si].face, springs[si].edge}] = si;
    for (const auto& [key, si] : spring_index) {
        const FaceId T = face_id(key.first);
        const int k = key.second;
        const mesh::FaceNeighbor nb = dm.neighbor(T, k);
        if (nb.face == mesh::NO_FACE) continue;
        const mesh::Face& ft = dm.faces[T];
        const mesh::Face& fn = dm.faces[nb.face];
        const auto ka = static_cast<std::size_t>(k), kb = static_cast<std::size_t>((k + 1) % 3);
        // d_T' in T's frame: shift by the offset difference of the shared corner a.
        const Vec2i shift_n = ft.offset[ka] - fn.offset[static_cast<std::size_t>((nb.edge + 1) % 3)];
        const mesh::VertexId dT = vertex_id(nv + ix(T)), dN = vertex_id(nv + ix(nb.face));
        const Vec2i oT = dual_offset[ix(T)], oN = dual_offset[ix(nb.face)] + shift_n;
        mesh::Face cell_a, cell_b;
        cell_a.v = {ft.v[ka], dN, dT};
        cell_a.offset = {ft.offset[ka], oN, oT};
        cell_b.v = {ft.v[kb], dT, dN};
        cell_b.offset = {ft.offset[kb], oT, oN};
        const bool broken = springs[si].broken;
        km.faces.push_back(cell_a);
        km.faces.push_back(cell_b);
        // The Voronoi edge is edge 1 of both kites (corner 1 → corner 2).
        cut.push_back({0, static_cast<char>(broken), 0});
        cut.push_back({0, static_cast<char>(broken), 0});
        kite_spring.push_back(si);
        kite_spring.push_back(si);
    }
    km.rebuild_adjacency();
    kites.origin = mesh::cut_along(km, cut);
    return kites;
}

/// The kites at the end of the run: the top of the layer moved with its masses; dual points
/// take the mean displacement of their face's masses.
void place_kites(const MassSpringModel& model, const Mat3& G, const std::vector<mesh::VertexId>& origin,
                 CrackPattern& p) {
    const auto& dm = model.mesh();
    const mesh::Surface& surface = model.surface();
    const std::size_t nv = dm.num_vertices();
    const int L = model.layers();
    const mesh::SurfaceMesh& km = p.mesh;
    std::vector<Vec3> displacement(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        const Vec3 bottom = G * dm.positions[vertex_id(v)];
        const Vec3 n = (G.inverse().transpose() * surface.normal(dm.positions[vertex_id(v)])).normalized();
        displacement[v] =
            model.position(static_cast<std::size_t>(L - 1) * nv + v) - bottom - (L - 1) * model.layer_thickness() * n;
    }
    const std::size_t nk = km.num_vertices();
    p.deformed.resize(nk);
    p.thickness.resize(nk);
    for (std::size_t k = 0; k < nk; ++k) {
        const std::size_t o = ix(origin[k]);
        const Vec3 P0 = km.positions[vertex_id(k)];
        const Vec3 n = (G.inverse().transpose() * surface.normal(P0)).normalized();
        Vec3 u = Vec3::Zero();
        double h = 0;
        if (o < nv) {
            u = displacement[o];
            h = model.vertex_thickness(o);
        } else {
            for (mesh::VertexId w : dm.faces[face_id(o - nv)].v) {
                u += displacement[ix(w)] / 3.0;
                h += model.vertex_thickness(ix(w)) / 3.0;
            }
        }
        p.thickness[k] = h;
        p.deformed[k] = G * P0 + u + h * n;
    }
    for (int i = 0; i < 2; ++i)
        p.deformed_period[static_cast<std::size_t>(i)] = G * km.period_vectors[static_cast<std::size_t>(i)];
    p.removed.assign(km.num_faces(), 0);
    p.young_modulus.resize(km.num_faces());
    for (std::size_t f = 0; f < km.num_faces(); ++f)
        p.young_modulus[f] = model.young_modulus(ix(origin[ix(km.faces[face_id(f)].v[0])]));
    label_fragments(p);
}

/// A crack lip per kite whose Voronoi edge opened, its depth the broken layers counted down from
/// the top (§4.3); their depths in layers go to `stats`.
void add_lips(const MassSpringModel& model, const Mat3& G, const std::vector<std::size_t>& kite_spring, CrackPattern& p,
              MassSpringStats& stats) {
    const auto& springs = model.springs();
    const auto& dm = model.mesh();
    const int L = model.layers();
    const mesh::SurfaceMesh& km = p.mesh;
    std::map<std::pair<std::uint32_t, int>, std::vector<std::size_t>> layers_of_edge;
    for (std::size_t si = 0; si < springs.size(); ++si)
        layers_of_edge[{springs[si].face, springs[si].edge}].push_back(si);
    // A crack lip per kite whose Voronoi edge opened. A spring broken alone (both its Voronoi
    // vertices crack tips, e.g. the ladders of parallel breaks a load along a lattice direction
    // makes) is micro-damage: the cells stay joined around it, nothing opens, and it is neither
    // drawn nor counted.
    for (std::size_t f = 0; f < km.num_faces(); ++f) {
        const auto& top = springs[kite_spring[f]];
        if (!top.broken || km.neighbor(face_id(f), 1).face != mesh::NO_FACE) continue;
        const auto& column = layers_of_edge[{top.face, top.edge}];
        int depth_layers = 0;
        for (int l = L - 1; l >= 0; --l) {
            const auto it =
                std::find_if(column.begin(), column.end(), [&](std::size_t si) { return springs[si].layer == l; });
            if (it == column.end() || !springs[*it].broken) break;
            ++depth_layers;
        }
        CrackEdge c;
        c.face = face_id(f);
        c.edge = 1;
        const Vec3 d = model.position(top.b)
                       + G * (top.offset.x() * dm.period_vectors[0] + top.offset.y() * dm.period_vectors[1])
                       - model.position(top.a);
        c.opening = std::max(0.0, d.norm() - top.rest0);
        c.depth = depth_layers * model.layer_thickness();
        p.cracks.push_back(c);
        if (f % 2 == 0) stats.crack_depth_layers.push_back(depth_layers);
    }
}

} // namespace

CrackPattern kite_pattern(const MassSpringModel& model, MassSpringStats& stats) {
    const double t_end = model.time();
    const Mat3 G = Mat3::Identity() + t_end * model.growth().tensor();
    CrackPattern p;
    p.method = "mass-spring";
    p.surface = model.surface();
    p.final_time = t_end;
    p.elements_initial = model.springs().size() / static_cast<std::size_t>(model.layers());
    p.growth_map = G;
    p.poisson_ratio = model.poisson_ratio();
    const Kites kites = kite_mesh(model, p);
    place_kites(model, G, kites.origin, p);
    add_lips(model, G, kites.kite_spring, p, stats);
    return p;
}

} // namespace crackle::fracture
