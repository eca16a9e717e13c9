/// @file FemModel topology edits: removal, bisection, split, flip, move, cut (Federl 2002, Alg. 7, Alg. 9, §5.7.5).
#include "core/error.hpp"
#include "core/math.hpp"
#include "mesh/cut.hpp"
#include "mesh/refine.hpp"
#include "sim/fem_model_internal.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::sim {

// === Topology

void FemModel::remove_element(FaceId f) {
    const std::size_t fi = ix(f);
    CRACKLE_ASSERT(m_alive[fi], "element " << fi << " is already removed");
    const mesh::Face& face = m_mesh.faces[f];
    // The element's forces leave the sums r = −Σ_alive f_e, for positions and rates alike.
    for (Unknown u : {Unknown::Position, Unknown::Rate}) {
        Field& fd = field(u);
        if (!fd.residual_valid) continue;
        subtract_element_force(fi, -element_force(fi, u), fd.residual);
    }
    m_alive[fi] = 0;
    --m_num_alive;
    for (VertexId v : face.v) {
        // A node left without elements feels no force: it stays where it is.
        if (--m_alive_degree[ix(v)] == 0)
            for (Field* fd : {&m_x, &m_xdot})
                if (fd->residual_valid)
                    fd->residual.segment(static_cast<Eigen::Index>(3 * slot(ix(v))), 3 * m_order).setZero();
    }
    // Alg. 7: every block (a, b) between nodes of the removed element is rebuilt from the
    // alive elements that still share both nodes: exact, no subtraction round-off (F12).
    for (std::size_t a = 0; a < 3; ++a)
        for (std::size_t b = 0; b < 3; ++b)
            for (int ja = 0; ja < m_order; ++ja)
                for (int jb = 0; jb < m_order; ++jb) {
                    const std::size_t va = ix(face.v[a]), vb = ix(face.v[b]);
                    Mat3 block = Mat3::Zero();
                    for (std::uint32_t g : m_incident[va]) {
                        if (!m_alive[g]) continue;
                        const mesh::Face& other = m_mesh.faces[face_id(g)];
                        for (std::size_t i = 0; i < 3; ++i)
                            for (std::size_t j = 0; j < 3; ++j)
                                if (ix(other.v[i]) == va && ix(other.v[j]) == vb) block += k_block(g, ja, i, jb, j);
                    }
                    if (va == vb && ja == jb && m_alive_degree[va] == 0) block = Mat3::Identity();
                    set_block(slot(va, ja), slot(vb, jb), block);
                }
    m_solver->invalidate(false);
    m_stiffness_dirty_for_x = true;
}

double FemModel::element_size(FaceId f) const {
    const auto p = m_mesh.face_positions(f);
    return std::max({(p[1] - p[0]).norm(), (p[2] - p[1]).norm(), (p[0] - p[2]).norm()});
}

mesh::NewVertex FemModel::point_on_edge(const mesh::SurfaceMesh& m, FaceId face, int edge, double t, NewNode& node,
                                        const std::vector<NewNode>* pending) const {
    Vec3 bary = Vec3::Zero();
    bary[edge] = 1 - t;
    bary[(edge + 1) % 3] = t;
    return point_in_face(m, face, bary, node, pending);
}

mesh::NewVertex FemModel::point_in_face(const mesh::SurfaceMesh& m, FaceId face, const Vec3& bary, NewNode& node,
                                        const std::vector<NewNode>* pending) const {
    const mesh::Face& fc = m.faces[face];
    mesh::NewVertex nv;
    if (m.periodic) {
        // In the unrolled domain, mapped onto the surface.
        Vec2 d = Vec2::Zero();
        for (int k = 0; k < 3; ++k)
            d += bary[k] * m.corner_domain(face, k);
        nv.domain = Vec2(wrap(d.x(), m.period.x()), wrap(d.y(), m.period.y()));
        nv.position = m_surface.position(nv.domain);
    } else {
        Vec3 p = Vec3::Zero();
        for (int k = 0; k < 3; ++k)
            p += bary[k] * m.corner_position(face, k);
        nv.position = m_surface.project(p);
    }
    // The top node and its rate: the corners' displacements from rest are interpolated, not
    // their positions. On a curved surface the chord between two top nodes runs inside the
    // layer by (R + h)·θ²/8, and a resampled thickness differs from the interpolated one:
    // either would give the new node a misfit that relaxing releases as if a crack had.
    // (Displacements do not depend on the periodic frame: a shift moves a node and its rest
    // alike.)
    node.thickness = m_fields.vertex_thickness ? 0.0 : thickness_at(nv.position, nv.domain);
    node.normal = m_surface.normal(nv.position);
    node.top = rest_top(nv.position, node.normal, node.thickness);
    node.rate = rest_top_rate(nv.position, node.normal, node.thickness);
    const std::size_t adopted = m_normal.size();
    for (std::size_t k = 0; k < 3; ++k) {
        const auto w = static_cast<Eigen::Index>(k);
        const std::size_t c = ix(fc.v[k]);
        const Vec3& p0 = m.positions[fc.v[k]];
        if (c < adopted) {
            node.top += bary[w] * (m_x.values[slot(c)] - rest_top(p0, m_normal[c], m_thickness[c]));
            node.rate += bary[w] * (m_xdot.values[slot(c)] - rest_top_rate(p0, m_normal[c], m_thickness[c]));
            for (int j = 1; j < m_order; ++j) {
                node.mode[static_cast<std::size_t>(j - 1)] += bary[w] * m_x.values[slot(c, j)];
                node.mode_rate[static_cast<std::size_t>(j - 1)] += bary[w] * m_xdot.values[slot(c, j)];
            }
        } else {
            // A midpoint an earlier bisection of the same Rivara cascade made.
            CRACKLE_ASSERT(pending && c - adopted < pending->size(), "interpolating from unknown vertex " << c);
            const NewNode& q = (*pending)[c - adopted];
            node.top += bary[w] * (q.top - rest_top(p0, q.normal, q.thickness));
            node.rate += bary[w] * (q.rate - rest_top_rate(p0, q.normal, q.thickness));
            for (std::size_t j = 0; j < q.mode.size(); ++j) {
                node.mode[j] += bary[w] * q.mode[j];
                node.mode_rate[j] += bary[w] * q.mode_rate[j];
            }
        }
    }
    return nv;
}

mesh::NewVertex FemModel::face_point(FaceId f, const Vec3& bary, Vec3* top, Vec3* rate) const {
    NewNode node;
    const mesh::NewVertex nv = point_in_face(m_mesh, f, bary, node);
    if (top) *top = node.top;
    if (rate) *rate = node.rate;
    return nv;
}

std::vector<FaceId> FemModel::subdivide(FaceId f) {
    std::vector<NewNode> nodes; // per new vertex, in split order
    const mesh::MidpointRule rule = [&](const mesh::SurfaceMesh& m, FaceId face, int edge) {
        NewNode node;
        const mesh::NewVertex nv = point_on_edge(m, face, edge, 0.5, node, &nodes);
        nodes.push_back(node);
        return nv;
    };
    std::vector<mesh::EdgeSplit> splits;
    mesh::rivara_bisect(m_mesh, f, rule, splits);
    return adopt_splits(splits, nodes);
}

std::pair<VertexId, std::vector<FaceId>> FemModel::split_edge(FaceId f, int edge, double t) {
    CRACKLE_ASSERT(t > 0 && t < 1, "split parameter " << t << " outside (0, 1)");
    std::vector<NewNode> nodes(1);
    const mesh::NewVertex nv = point_on_edge(m_mesh, f, edge, t, nodes[0]);
    const std::vector<mesh::EdgeSplit> splits{mesh::split_edge(m_mesh, f, edge, nv)};
    std::vector<FaceId> touched = adopt_splits(splits, nodes);
    return {splits[0].vertex, std::move(touched)};
}

std::vector<FaceId> FemModel::adopt_splits(const std::vector<mesh::EdgeSplit>& splits,
                                           const std::vector<NewNode>& nodes) {
    CRACKLE_ASSERT(nodes.size() == splits.size(), "one new vertex per split");
    std::vector<FaceId> touched;
    for (std::size_t i = 0; i < splits.size(); ++i) {
        const mesh::EdgeSplit& split = splits[i];
        const std::size_t v = ix(split.vertex);
        CRACKLE_ASSERT(slot(v) == m_x.values.size(), "split order and vertex ids disagree");
        m_normal.emplace_back();
        m_thickness.emplace_back();
        push_vertex_slots();
        m_last_update.emplace_back(0.0);
        init_vertex(v);
        m_x.values[slot(v)] = nodes[i].top;
        m_xdot.values[slot(v)] = nodes[i].rate;
        for (int j = 1; j < m_order; ++j) {
            m_x.values[slot(v, j)] = nodes[i].mode[static_cast<std::size_t>(j - 1)];
            m_xdot.values[slot(v, j)] = nodes[i].mode_rate[static_cast<std::size_t>(j - 1)];
        }
        // Children: the kept id keeps the parent's status, the new id copies it.
        for (const auto& [kid, nid] : split.children) {
            const char status = m_alive[ix(kid)];
            m_alive.push_back(status);
            if (status) ++m_num_alive;
            m_material.emplace_back();
            m_broken.push_back(0);
            m_k_free.resize(m_k_free.size() + k_stride());
            touched.push_back(kid);
            touched.push_back(nid);
        }
    }
    // Material (§5.9: recomputed whenever elements are created) and stiffness of every face
    // the refinement touched, once it is finished.
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    for (FaceId t : touched)
        init_element(ix(t));
    std::vector<std::size_t> vertices;
    for (FaceId t : touched)
        for (VertexId w : m_mesh.faces[t].v)
            vertices.push_back(ix(w));
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    refresh_incidence(touched, vertices);
    update_around(vertices); // only the residuals at the refined faces' nodes change
    return touched;
}

mesh::NewVertex FemModel::edge_point(FaceId f, int edge, double t, Vec3* top, Vec3* rate) const {
    NewNode node;
    const mesh::NewVertex nv = point_on_edge(m_mesh, f, edge, t, node);
    if (top) *top = node.top;
    if (rate) *rate = node.rate;
    return nv;
}

FaceId FemModel::flip_edge(FaceId f, int edge) {
    std::vector<std::size_t> vertices;
    for (VertexId w : m_mesh.faces[f].v)
        vertices.push_back(ix(w));
    const FaceId g = mesh::flip_edge(m_mesh, f, edge);
    if (g == mesh::NO_FACE) return g;
    for (VertexId w : m_mesh.faces[g].v)
        vertices.push_back(ix(w));
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    refresh_incidence({f, g}, vertices);
    init_element(ix(f));
    init_element(ix(g));
    update_around(vertices);
    return g;
}

void FemModel::move_vertex(VertexId v, const mesh::NewVertex& to, const Vec3& top, const Vec3& rate) {
    const std::size_t vi = ix(v);
    if (m_mesh.periodic) {
        // Each face keeps v's corner where it was in its own frame, moved by the same step.
        Vec2 step = to.domain - m_mesh.domain[v];
        for (int i = 0; i < 2; ++i)
            step[i] -= m_mesh.period[i] * std::round(step[i] / m_mesh.period[i]);
        for (std::uint32_t f : m_incident[vi]) {
            mesh::Face& face = m_mesh.faces[face_id(f)];
            for (std::size_t k = 0; k < 3; ++k) {
                if (face.v[k] != v) continue;
                const Vec2 unwrapped = m_mesh.corner_domain(face_id(f), static_cast<int>(k)) + step;
                face.offset[k] =
                    Vec2i(static_cast<int>(std::lround((unwrapped.x() - to.domain.x()) / m_mesh.period.x())),
                          static_cast<int>(std::lround((unwrapped.y() - to.domain.y()) / m_mesh.period.y())));
            }
        }
        m_mesh.domain[v] = to.domain;
    }
    m_mesh.positions[v] = to.position;
    const Vec3 keep_top = top;
    init_vertex(vi); // normal and thickness at the new place
    m_x.values[slot(vi)] = keep_top;
    m_xdot.values[slot(vi)] = rate; // the modes keep their amplitudes
    std::vector<std::size_t> vertices;
    for (std::uint32_t f : m_incident[vi]) {
        init_element(f);
        for (VertexId w : m_mesh.faces[face_id(f)].v)
            vertices.push_back(ix(w));
    }
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    update_around(vertices);
}

std::vector<std::pair<VertexId, VertexId>> FemModel::cut(const std::vector<std::pair<FaceId, int>>& edges) {
    const std::size_t nv_before = m_mesh.num_vertices();
    const auto copies = mesh::cut_edges(
        m_mesh, edges, [&](VertexId v) -> const std::vector<std::uint32_t>& { return m_incident[ix(v)]; });
    const std::size_t nv = m_mesh.num_vertices();
    if (nv == nv_before) {
        // Nothing opened (a cut with both ends inside the mesh): the topology is unchanged.
        return copies;
    }
    // Copies inherit everything per vertex; the faces moved to them change nothing else.
    std::vector<std::size_t> vertices;
    std::vector<FaceId> faces;
    for (const auto& [copy, origin] : copies) {
        const std::size_t v = ix(copy), o = ix(origin);
        CRACKLE_ASSERT(v == m_normal.size(), "vertex copies are appended in order");
        m_normal.push_back(m_normal[o]);
        m_thickness.push_back(m_thickness[o]);
        push_vertex_slots();
        for (int j = 0; j < m_order; ++j) {
            m_x.values[slot(v, j)] = m_x.values[slot(o, j)];
            m_xdot.values[slot(v, j)] = m_xdot.values[slot(o, j)];
        }
        m_last_update.push_back(0.0);
        vertices.push_back(o);
        vertices.push_back(v);
        for (std::uint32_t f : m_incident[o])
            faces.push_back(face_id(f)); // the origin's faces, some now at the copy
    }
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    refresh_incidence(faces, vertices);
    update_around(vertices);
    return copies;
}

} // namespace crackle::sim
