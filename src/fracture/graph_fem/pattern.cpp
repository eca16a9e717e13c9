/// @file graph-fem's crack pattern on the mesh's dual (graph-fem digest §7.6; §1.14's child vertices).
#include "fracture/graph_fem/graph_fem.hpp"
#include "mesh/cut.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::fracture {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;
using mesh::vertex_id;

namespace {

/// Adds the point with barycentric weights w in face f: its canonical copy on the surface and
/// the lattice offset of the copy f's frame sees.
Vec2i add_point(mesh::SurfaceMesh& km, const mesh::SurfaceMesh& dm, const mesh::Surface& surface, FaceId f,
                const std::array<double, 3>& w) {
    const auto p = dm.face_positions(f);
    if (!dm.periodic) {
        km.positions.push_back(surface.project(w[0] * p[0] + w[1] * p[1] + w[2] * p[2]));
        return Vec2i::Zero();
    }
    const Vec2 unrolled = w[0] * dm.corner_domain(f, 0) + w[1] * dm.corner_domain(f, 1) + w[2] * dm.corner_domain(f, 2);
    const Vec2 canonical(wrap(unrolled.x(), dm.period.x()), wrap(unrolled.y(), dm.period.y()));
    km.domain.push_back(canonical);
    km.positions.push_back(surface.position(canonical));
    return {static_cast<int>(std::lround((unrolled.x() - canonical.x()) / dm.period.x())),
            static_cast<int>(std::lround((unrolled.y() - canonical.y()) / dm.period.y()))};
}

/// The graph's kites, cut open along the broken edges: which mesh vertex each kite vertex copies
/// and the kite pairs facing each other across a crack.
struct Kites {
    std::vector<mesh::VertexId> origin;
    std::vector<std::array<std::size_t, 2>> lips;
};

/// One dual point per face (after the mesh's vertices in `km`), their periodic offsets.
std::vector<Vec2i> dual_points(const sim::FemModel& model, mesh::SurfaceMesh& km) {
    const mesh::SurfaceMesh& dm = model.mesh();
    const mesh::Surface& surface = model.surface();
    const std::size_t nf = dm.num_faces();
    // A face a crack passes through (two broken edges, sharing corner a) gets its dual point
    // halfway between the two edge midpoints, so the crack runs straight across it instead of
    // kinking at the centroid (digest §7.6: smoothing for rendering only; the simulation never
    // sees it). Tips (one broken edge) and junctions (three) keep the centroid.
    std::vector<Vec2i> centroid_offset(nf);
    for (std::size_t f = 0; f < nf; ++f) {
        std::array<double, 3> w = {1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0};
        const unsigned broken = model.broken_edges(face_id(f));
        for (std::size_t a = 0; a < 3; ++a)
            if (broken == ((1u << a) | (1u << ((a + 2) % 3)))) { // edges a → a+1 and a+2 → a
                w = {0.25, 0.25, 0.25};
                w[a] = 0.5;
            }
        centroid_offset[f] = add_point(km, dm, surface, face_id(f), w);
    }
    return centroid_offset;
}

/// The kites (and the Young's modulus of each in `p`), halved and opened along broken edges.
Kites kite_mesh(const sim::FemModel& model, const EdgeGraph& graph, const std::vector<Vec2i>& centroid_offset,
                CrackPattern& p) {
    const mesh::SurfaceMesh& dm = model.mesh();
    const mesh::Surface& surface = model.surface();
    const std::size_t nv = dm.num_vertices();
    mesh::SurfaceMesh& km = p.mesh;
    // Kites around each corner: for edge a → b of face T (neighbour N), cell a gets (a, d_N, d_T)
    // and cell b (b, d_T, d_N), all in T's frame; a broken edge's kites are halved through its
    // midpoint m and opened along m–d_T and d_N–m (edge 1 of each).
    std::vector<std::array<char, 3>> cut;
    std::vector<std::array<std::size_t, 2>> lips; // kite pairs facing each other across a crack
    auto push = [&](const mesh::Face& face, bool open, double young) {
        km.faces.push_back(face);
        cut.push_back({0, static_cast<char>(open), 0});
        p.young_modulus.push_back(young);
        return km.faces.size() - 1;
    };
    for (std::size_t e = 0; e < graph.size(); ++e) {
        const EdgeGraph::Edge& edge = graph.edge(e);
        if (edge.sides < 2) continue; // the surfaces crackle grows are closed or periodic
        const EdgeGraph::Side& side = edge.side[0];
        const FaceId T = face_id(side.face), N = face_id(edge.side[1].face);
        const mesh::Face& ft = dm.faces[T];
        const mesh::Face& fn = dm.faces[N];
        const auto ka = static_cast<std::size_t>(side.edge), kb = (ka + 1) % 3;
        const Vec2i shift_n = ft.offset[ka] - fn.offset[static_cast<std::size_t>((edge.side[1].edge + 1) % 3)];
        const mesh::VertexId a = ft.v[ka], b = ft.v[kb];
        const mesh::VertexId dT = vertex_id(nv + ix(T)), dN = vertex_id(nv + ix(N));
        const Vec2i oa = ft.offset[ka], ob = ft.offset[kb], oT = centroid_offset[ix(T)],
                    oN = centroid_offset[ix(N)] + shift_n;
        const double eT = model.material(T).young_modulus, eN = model.material(N).young_modulus;
        if (!graph.broken(model, e)) {
            push({{a, dN, dT}, {oa, oN, oT}}, false, 0.5 * (eT + eN));
            push({{b, dT, dN}, {ob, oT, oN}}, false, 0.5 * (eT + eN));
            continue;
        }
        std::array<double, 3> w = {0.0, 0.0, 0.0};
        w[ka] = w[kb] = 0.5;
        const mesh::VertexId m = vertex_id(km.num_vertices());
        const Vec2i om = add_point(km, dm, surface, T, w);
        const std::size_t i0 = push({{a, m, dT}, {oa, om, oT}}, true, eT);
        const std::size_t i1 = push({{a, dN, m}, {oa, oN, om}}, true, eN);
        const std::size_t i2 = push({{b, dT, m}, {ob, oT, om}}, true, eT);
        const std::size_t i3 = push({{b, m, dN}, {ob, om, oN}}, true, eN);
        lips.push_back({i0, i2});
        lips.push_back({i1, i3});
    }
    km.rebuild_adjacency();
    return {mesh::cut_along(km, cut), lips};
}

/// The kites at the end of the run: every vertex copy at its parents' mean displacement.
void follow_parents(const sim::FemModel& model, const Mat3& G, const std::vector<mesh::VertexId>& origin,
                    CrackPattern& p) {
    const mesh::SurfaceMesh& dm = model.mesh();
    const mesh::Surface& surface = model.surface();
    const std::size_t nv = dm.num_vertices();
    const double t = model.time();
    const mesh::SurfaceMesh& km = p.mesh;
    // Every vertex copy follows the mean displacement of the mesh vertices whose cells it
    // touches on its side of the cracks (digest §1.14: children follow their parents).
    const std::size_t nk = km.num_vertices();
    std::vector<std::vector<std::uint32_t>> parents(nk);
    for (std::size_t f = 0; f < km.num_faces(); ++f) {
        const mesh::Face& face = km.faces[face_id(f)];
        const auto cell = static_cast<std::uint32_t>(ix(origin[ix(face.v[0])]));
        for (mesh::VertexId v : face.v)
            parents[ix(v)].push_back(cell);
    }
    auto grown_normal = [&](const Vec3& P0) { return (G.inverse().transpose() * surface.normal(P0)).normalized(); };
    std::vector<Vec3> displacement(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        const Vec3 P0 = dm.positions[vertex_id(v)];
        displacement[v] =
            model.top_position(vertex_id(v)) - G * P0 - model.vertex_thickness(vertex_id(v)) * grown_normal(P0);
    }
    p.deformed.resize(nk);
    p.thickness.resize(nk);
    for (std::size_t k = 0; k < nk; ++k) {
        auto& list = parents[k];
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
        Vec3 u = Vec3::Zero();
        double h = 0;
        for (std::uint32_t c : list) {
            u += displacement[c];
            h += model.vertex_thickness(vertex_id(c));
        }
        const double n = static_cast<double>(std::max<std::size_t>(list.size(), 1));
        const Vec3 P0 = km.positions[vertex_id(k)];
        p.thickness[k] = h / n;
        p.deformed[k] = G * P0 + u / n + (h / n) * grown_normal(P0);
    }
    for (std::size_t i = 0; i < 2; ++i)
        p.deformed_period[i] = model.growth().period_shift(km.period_vectors[i], t);
}

/// A crack lip on each side of every opened dual segment.
void open_lips(const std::vector<std::array<std::size_t, 2>>& lips, CrackPattern& p) {
    const mesh::SurfaceMesh& km = p.mesh;
    // Crack lips: the dual segments of broken edges, opened by the distance between the deformed
    // midpoints of the two lips; full depth (every Gauss layer loses the strain).
    for (std::size_t i = 0; i < lips.size(); ++i) {
        const auto [f0, f1] = lips[i];
        auto mid = [&](std::size_t f) -> Vec3 {
            return 0.5 * (p.deformed_corner(face_id(f), 1) + p.deformed_corner(face_id(f), 2));
        };
        const double opening = (mid(f0) - mid(f1)).norm();
        double depth = 0;
        for (std::size_t f : {f0, f1})
            depth += 0.5 * p.thickness[ix(km.faces[face_id(f)].v[0])];
        for (std::size_t f : {f0, f1}) {
            if (km.neighbor(face_id(f), 1).face != mesh::NO_FACE) continue; // nothing opened
            CrackEdge c;
            c.face = face_id(f);
            c.edge = 1;
            c.opening = opening;
            c.depth = depth;
            p.cracks.push_back(c);
        }
    }
}

} // namespace

CrackPattern graph_pattern(const sim::FemModel& model, const EdgeGraph& graph, std::size_t elements_initial) {
    const mesh::SurfaceMesh& dm = model.mesh();
    const mesh::Surface& surface = model.surface();
    const std::size_t nv = dm.num_vertices();
    const double t = model.time();
    const Mat3 G = Mat3::Identity() + t * model.growth().tensor();

    CrackPattern p;
    p.method = "graph-fem";
    p.surface = surface;
    p.final_time = t;
    p.elements_initial = elements_initial;
    p.growth_map = G;
    p.poisson_ratio = model.poisson_ratio();
    mesh::SurfaceMesh& km = p.mesh;
    km.periodic = dm.periodic;
    km.period = dm.period;
    km.period_vectors = dm.period_vectors;
    // Vertices: the mesh's, one centroid per face, then one midpoint per broken edge.
    for (std::size_t v = 0; v < nv; ++v) {
        km.positions.push_back(dm.positions[vertex_id(v)]);
        if (dm.periodic) km.domain.push_back(dm.domain[vertex_id(v)]);
    }
    const std::vector<Vec2i> centroid_offset = dual_points(model, km);
    const Kites kites = kite_mesh(model, graph, centroid_offset, p);
    follow_parents(model, G, kites.origin, p);
    p.removed.assign(km.num_faces(), 0);
    label_fragments(p);
    open_lips(kites.lips, p);
    return p;
}

} // namespace crackle::fracture
