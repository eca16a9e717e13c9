#include "mesh/surface_mesh.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <map>
#include <sstream>
#include <tuple>

namespace crackle::mesh {

Vec3 SurfaceMesh::corner_position(FaceId f, int k) const {
    const Face& face = faces[f];
    const Vec2i& o = face.offset[static_cast<size_t>(k)];
    return positions[face.v[static_cast<size_t>(k)]] + o.x() * period_vectors[0] + o.y() * period_vectors[1];
}

Vec3 SurfaceMesh::nearest_step(const Vec3& from, const Vec3& to) const {
    Vec3 best = to - from;
    if (!periodic) return best;
    for (int i = -1; i <= 1; ++i)
        for (int j = -1; j <= 1; ++j) {
            const Vec3 d = to + i * period_vectors[0] + j * period_vectors[1] - from;
            if (d.squaredNorm() < best.squaredNorm()) best = d;
        }
    return best;
}

std::array<Vec3, 3> SurfaceMesh::face_positions(FaceId f) const {
    return {corner_position(f, 0), corner_position(f, 1), corner_position(f, 2)};
}

Vec2 SurfaceMesh::corner_domain(FaceId f, int k) const {
    const Face& face = faces[f];
    const Vec2i& o = face.offset[static_cast<size_t>(k)];
    return domain[face.v[static_cast<size_t>(k)]] + Vec2(o.x() * period.x(), o.y() * period.y());
}

Vec3 SurfaceMesh::face_normal(FaceId f) const {
    const auto p = face_positions(f);
    return (p[1] - p[0]).cross(p[2] - p[0]).normalized();
}

double SurfaceMesh::face_area(FaceId f) const {
    const auto p = face_positions(f);
    return 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
}

std::array<double, 3> SurfaceMesh::face_angles(FaceId f) const {
    const auto p = face_positions(f);
    std::array<double, 3> angles{};
    for (size_t k = 0; k < 3; ++k) {
        const Vec3 a = p[(k + 1) % 3] - p[k];
        const Vec3 b = p[(k + 2) % 3] - p[k];
        angles[k] = std::atan2(a.cross(b).norm(), a.dot(b));
    }
    return angles;
}

double SurfaceMesh::total_area() const {
    double a = 0;
    for (size_t f = 0; f < num_faces(); ++f)
        a += face_area(face_id(f));
    return a;
}

namespace {
/// An undirected edge with its periodic offset difference, oriented from the smaller vertex id.
using EdgeKey = std::tuple<std::uint32_t, std::uint32_t, int, int>;

EdgeKey edge_key(const Face& face, int k, bool& forward) {
    const size_t a = static_cast<size_t>(k), b = static_cast<size_t>((k + 1) % 3);
    const auto va = static_cast<std::uint32_t>(face.v[a]);
    const auto vb = static_cast<std::uint32_t>(face.v[b]);
    Vec2i d = face.offset[b] - face.offset[a];
    forward = va < vb || (va == vb && (d.x() > 0 || (d.x() == 0 && d.y() > 0)));
    if (forward) return {va, vb, d.x(), d.y()};
    return {vb, va, -d.x(), -d.y()};
}

struct HalfEdge {
    EdgeKey key;
    bool forward;
    std::uint32_t face;
    int edge;
};

/// Sorts half-edges by key (deterministic, no hash-map order) and links each matching pair
/// in `neighbors`; returns the number of distinct edges and counts the unpaired ones.
/// Throws InvariantError on a non-manifold or inconsistently oriented edge.
std::size_t pair_half_edges(std::vector<HalfEdge>& half_edges, IdVector<FaceId, std::array<FaceNeighbor, 3>>& neighbors,
                            std::size_t& unpaired) {
    std::sort(half_edges.begin(), half_edges.end(), [](const HalfEdge& a, const HalfEdge& b) {
        return std::tie(a.key, a.face, a.edge) < std::tie(b.key, b.face, b.edge);
    });
    std::size_t edges = 0;
    unpaired = 0;
    for (std::size_t i = 0; i < half_edges.size();) {
        std::size_t j = i + 1;
        while (j < half_edges.size() && half_edges[j].key == half_edges[i].key)
            ++j;
        ++edges;
        if (j - i == 1) {
            ++unpaired;
        } else {
            const HalfEdge& a = half_edges[i];
            const HalfEdge& b = half_edges[i + 1];
            CRACKLE_ASSERT(j - i == 2, "non-manifold edge " << std::get<0>(a.key) << "-" << std::get<1>(a.key)
                                                            << " shared by " << (j - i) << " faces");
            CRACKLE_ASSERT(a.forward != b.forward,
                           "faces " << a.face << " and " << b.face << " disagree in orientation across an edge");
            neighbors[face_id(a.face)][static_cast<size_t>(a.edge)] = {face_id(b.face), b.edge};
            neighbors[face_id(b.face)][static_cast<size_t>(b.edge)] = {face_id(a.face), a.edge};
        }
        i = j;
    }
    return edges;
}
} // namespace

void SurfaceMesh::rebuild_adjacency() {
    m_neighbors = IdVector<FaceId, std::array<FaceNeighbor, 3>>(num_faces());
    m_vertex_face = IdVector<VertexId, FaceId>(num_vertices(), NO_FACE);
    std::vector<HalfEdge> half_edges;
    half_edges.reserve(3 * num_faces());
    for (size_t fi = 0; fi < num_faces(); ++fi) {
        const Face& face = faces[face_id(fi)];
        for (int k = 0; k < 3; ++k) {
            bool forward = false;
            const EdgeKey key = edge_key(face, k, forward);
            half_edges.push_back({key, forward, static_cast<std::uint32_t>(fi), k});
            if (m_vertex_face[face.v[static_cast<size_t>(k)]] == NO_FACE)
                m_vertex_face[face.v[static_cast<size_t>(k)]] = face_id(fi);
        }
    }
    m_num_edges = pair_half_edges(half_edges, m_neighbors, m_num_boundary_edges);
}

void SurfaceMesh::update_adjacency(const std::vector<FaceId>& changed) {
    // The changed faces can only pair with each other or with their old neighbours (a face
    // added since the last update has none; its parent is among `changed`). Everything else
    // keeps its links, so re-pairing the half-edges of this small set is exact.
    const std::size_t old_faces = m_neighbors.size();
    m_neighbors.resize(num_faces());
    for (std::size_t f = old_faces; f < num_faces(); ++f)
        m_neighbors[face_id(f)] = {};
    m_vertex_face.resize(num_vertices(), NO_FACE);
    std::vector<std::uint32_t> set;
    for (FaceId f : changed) {
        set.push_back(static_cast<std::uint32_t>(ix(f)));
        for (const FaceNeighbor& nb : m_neighbors[f])
            if (nb.face != NO_FACE) set.push_back(static_cast<std::uint32_t>(ix(nb.face)));
    }
    std::sort(set.begin(), set.end());
    set.erase(std::unique(set.begin(), set.end()), set.end());
    auto in_set = [&](FaceId f) {
        return std::binary_search(set.begin(), set.end(), static_cast<std::uint32_t>(ix(f)));
    };
    // Edge counts in half units over the set's half-edges: a paired one is half an edge.
    // (Faces added since the last update did not exist before: they count only after.)
    auto tally = [&](long& halves, long& boundary, std::size_t faces_then) {
        for (std::uint32_t f : set)
            if (f < faces_then)
                for (const FaceNeighbor& nb : m_neighbors[face_id(f)]) {
                    halves += nb.face == NO_FACE ? 2 : 1;
                    boundary += nb.face == NO_FACE;
                }
    };
    long halves_before = 0, boundary_before = 0;
    tally(halves_before, boundary_before, old_faces);
    // Unlink every edge inside the set, keep the links to faces outside it.
    std::vector<HalfEdge> half_edges;
    for (std::uint32_t fi : set) {
        const FaceId f = face_id(fi);
        for (int k = 0; k < 3; ++k) {
            FaceNeighbor& nb = m_neighbors[f][static_cast<size_t>(k)];
            if (nb.face != NO_FACE && !in_set(nb.face)) continue;
            nb = {};
            bool forward = false;
            const EdgeKey key = edge_key(faces[f], k, forward);
            half_edges.push_back({key, forward, fi, k});
        }
    }
    std::size_t unpaired = 0;
    pair_half_edges(half_edges, m_neighbors, unpaired);
    long halves_after = 0, boundary_after = 0;
    tally(halves_after, boundary_after, num_faces());
    m_num_edges = static_cast<std::size_t>(static_cast<long>(m_num_edges) + (halves_after - halves_before) / 2);
    m_num_boundary_edges =
        static_cast<std::size_t>(static_cast<long>(m_num_boundary_edges) + boundary_after - boundary_before);
    // Vertex → face links that no longer hold.
    for (std::uint32_t fi : set)
        for (VertexId v : faces[face_id(fi)].v) {
            const FaceId g = m_vertex_face[v];
            bool holds = g != NO_FACE;
            if (holds) {
                const Face& face = faces[g];
                holds = face.v[0] == v || face.v[1] == v || face.v[2] == v;
            }
            if (!holds) m_vertex_face[v] = face_id(fi);
        }
}

std::vector<FaceId> SurfaceMesh::vertex_faces(VertexId v) const {
    // Walk the fan around v through the neighbour links; fall back to a scan at boundaries.
    std::vector<FaceId> fan;
    const FaceId start = m_vertex_face[v];
    if (start == NO_FACE) return fan;
    FaceId f = start;
    for (size_t guard = 0; guard < 4 * num_faces() + 4; ++guard) {
        fan.push_back(f);
        const Face& face = faces[f];
        int k = 0;
        while (face.v[static_cast<size_t>(k)] != v)
            ++k;
        // Next face counter-clockwise around v: across the edge entering corner k.
        const FaceNeighbor& nb = m_neighbors[f][static_cast<size_t>((k + 2) % 3)];
        if (nb.face == NO_FACE) {
            fan.clear();
            for (size_t g = 0; g < num_faces(); ++g)
                for (VertexId w : faces[face_id(g)].v)
                    if (w == v) fan.push_back(face_id(g));
            return fan;
        }
        f = nb.face;
        if (f == start) break;
    }
    return fan;
}

long SurfaceMesh::euler_characteristic() const {
    return static_cast<long>(num_vertices()) - static_cast<long>(m_num_edges) + static_cast<long>(num_faces());
}

std::string SurfaceMesh::validate() const {
    std::ostringstream os;
    if (m_neighbors.size() != num_faces()) return "adjacency is out of date (call rebuild_adjacency)";
    for (size_t fi = 0; fi < num_faces(); ++fi) {
        const FaceId f = face_id(fi);
        const Face& face = faces[f];
        for (int k = 0; k < 3; ++k) {
            if (ix(face.v[static_cast<size_t>(k)]) >= num_vertices()) {
                os << "face " << fi << " references vertex " << ix(face.v[static_cast<size_t>(k)]);
                return os.str();
            }
        }
        if (face_area(f) <= 0.0) {
            os << "face " << fi << " is degenerate (zero area)";
            return os.str();
        }
        for (int k = 0; k < 3; ++k) {
            const FaceNeighbor& nb = m_neighbors[f][static_cast<size_t>(k)];
            if (nb.face == NO_FACE) continue;
            const FaceNeighbor& back = m_neighbors[nb.face][static_cast<size_t>(nb.edge)];
            if (back.face != f || back.edge != k) {
                os << "adjacency of face " << fi << " edge " << k << " is not symmetric";
                return os.str();
            }
            // Shared edge: same endpoints in opposite order, same geometric edge.
            const Face& other = faces[nb.face];
            const auto a = static_cast<size_t>(k), b = static_cast<size_t>((k + 1) % 3);
            const auto c = static_cast<size_t>(nb.edge), d = static_cast<size_t>((nb.edge + 1) % 3);
            if (face.v[a] != other.v[d] || face.v[b] != other.v[c]) {
                os << "faces " << fi << " and " << ix(nb.face) << " do not share the edge they link";
                return os.str();
            }
            const Vec2i shift_a = other.offset[d] - face.offset[a];
            const Vec2i shift_b = other.offset[c] - face.offset[b];
            if (shift_a != shift_b) {
                os << "faces " << fi << " and " << ix(nb.face) << " disagree on the periodic offset of their edge";
                return os.str();
            }
        }
    }
    return {};
}

MeshQuality mesh_quality(const SurfaceMesh& mesh) {
    MeshQuality q;
    if (mesh.num_faces() == 0) return q;
    q.min_angle_deg = 180.0;
    size_t below = 0;
    double sum_min = 0;
    double edge_sum = 0, edge_sum2 = 0;
    size_t edge_count = 0;
    q.edge_min = std::numeric_limits<double>::infinity();
    for (size_t fi = 0; fi < mesh.num_faces(); ++fi) {
        const FaceId f = face_id(fi);
        const auto angles = mesh.face_angles(f);
        const double min_deg = *std::min_element(angles.begin(), angles.end()) * RAD_TO_DEG;
        q.min_angle_deg = std::min(q.min_angle_deg, min_deg);
        sum_min += min_deg;
        if (min_deg < 10.0) ++below;
        const auto p = mesh.face_positions(f);
        for (int k = 0; k < 3; ++k) {
            // Count each interior edge once (from the face with the smaller id) and boundary edges.
            const FaceNeighbor& nb = mesh.neighbor(f, k);
            if (nb.face != NO_FACE && ix(nb.face) < fi) continue;
            const double len = (p[static_cast<size_t>((k + 1) % 3)] - p[static_cast<size_t>(k)]).norm();
            q.edge_min = std::min(q.edge_min, len);
            q.edge_max = std::max(q.edge_max, len);
            edge_sum += len;
            edge_sum2 += len * len;
            ++edge_count;
        }
    }
    const auto n = static_cast<double>(mesh.num_faces());
    q.mean_min_angle_deg = sum_min / n;
    q.fraction_below_10deg = static_cast<double>(below) / n;
    const auto m = static_cast<double>(edge_count);
    q.edge_mean = edge_sum / m;
    q.edge_std = safe_sqrt(edge_sum2 / m - sqr(q.edge_mean));
    return q;
}

} // namespace crackle::mesh
