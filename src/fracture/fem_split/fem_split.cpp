#include "fracture/fem_split/fem_split.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/progress.hpp"
#include "core/timer.hpp"
#include "fracture/toolkit/fem_loop.hpp"
#include "fracture/toolkit/fem_pattern.hpp"
#include "fracture/toolkit/next_crossing.hpp"
#include "fracture/toolkit/pick.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <sstream>

namespace crackle::fracture {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;
using mesh::vertex_id;
using mesh::VertexId;

namespace {

/// Corner index of vertex v in face f (−1 if absent).
int corner_of(const mesh::SurfaceMesh& m, std::size_t f, std::size_t v) {
    const mesh::Face& face = m.faces[face_id(f)];
    for (int k = 0; k < 3; ++k)
        if (ix(face.v[static_cast<std::size_t>(k)]) == v) return k;
    return -1;
}

/// The current tangent plane at a node (orthonormal e1, e2 of the grown surface) and the
/// inverse growth map back to t = 0.
struct NodeFrame {
    Vec3 e1, e2, n;
    Mat3 G_inv;
};

NodeFrame node_frame(const sim::FemModel& model, std::size_t v) {
    const Mat3 G = Mat3::Identity() + model.time() * model.growth().tensor();
    const Vec3& p0 = model.mesh().positions[vertex_id(v)];
    const mesh::TangentFrame fr = model.surface().frame(p0);
    NodeFrame out;
    out.G_inv = G.inverse();
    out.n = (out.G_inv.transpose() * fr.n).normalized();
    const Vec3 e1 = G * fr.e_u;
    out.e1 = (e1 - e1.dot(out.n) * out.n).normalized();
    out.e2 = out.n.cross(out.e1);
    return out;
}

/// A 3D stress tensor projected on the tangent plane (2×2, symmetric).
Mat2 project(const NodeFrame& fr, const Mat3& sigma) {
    Mat2 T;
    T << fr.e1.dot(sigma * fr.e1), fr.e1.dot(sigma * fr.e2), fr.e2.dot(sigma * fr.e1), fr.e2.dot(sigma * fr.e2);
    return T;
}

/// Largest eigenvalue of a symmetric 2×2 matrix, closed form.
double max_eigenvalue(const Mat2& T) {
    const double mean = 0.5 * (T(0, 0) + T(1, 1)), half_diff = 0.5 * (T(0, 0) - T(1, 1));
    return mean + std::hypot(half_diff, 0.5 * (T(0, 1) + T(1, 0)));
}

/// Nodal stress tensor (§5.7.1: the mean over the node's elements of each one's top Gauss
/// point nearest the node) from any per-face top-stress source; `means` gets the mean
/// threshold, toughness and stiffness. Returns false for a node with no element.
template <class StressOf>
bool nodal_tensor(const sim::FemModel& model, std::size_t v, StressOf&& stress_of, Mat3& sigma, NodalStress& means) {
    sigma = Mat3::Zero();
    double thr = 0, kic = 0, young = 0;
    int count = 0;
    for (std::uint32_t f : model.incident_faces(v)) {
        if (!model.alive(face_id(f))) continue;
        const int k = corner_of(model.mesh(), f, v);
        sigma += sim::wedge::tensor(stress_of(f)[static_cast<std::size_t>(k)]);
        const auto& mat = model.material(face_id(f));
        thr += mat.threshold_stress;
        kic += mat.toughness;
        young += mat.young_modulus;
        ++count;
    }
    if (count == 0) return false;
    sigma /= count;
    means.threshold = thr / count;
    means.toughness = kic / count;
    means.young = young / count;
    return true;
}

/// The in-surface principal stress of a node (§5.7.1–5.7.2): the largest eigenvalue of the
/// projected tensor over the threshold, and the crack direction normal to it (in the plane),
/// mapped back to t = 0 by the inverse growth map.
template <class StressOf> NodalStress nodal_from(const sim::FemModel& model, std::size_t v, StressOf&& stress_of) {
    NodalStress out;
    Mat3 sigma;
    if (!nodal_tensor(model, v, stress_of, sigma, out)) return out;
    const NodeFrame fr = node_frame(model, v);
    Eigen::SelfAdjointEigenSolver<Mat2> eig(project(fr, sigma));
    const Vec2 d = eig.eigenvectors().col(1);
    const Vec3 normal_dir = d.x() * fr.e1 + d.y() * fr.e2;
    out.ratio = eig.eigenvalues()[1] / out.threshold;
    out.crack = (fr.G_inv * fr.n.cross(normal_dir)).normalized();
    return out;
}

/// 2D coordinates of a face's corners around one of its corners, in the frame of the surface
/// at t = 0: the unrolled domain on periodic surfaces, the tangent plane at the corner on the
/// sphere.
std::array<Vec2, 3> local_corners(const sim::FemModel& model, std::size_t f, int k0, const mesh::TangentFrame& fr) {
    const mesh::SurfaceMesh& m = model.mesh();
    std::array<Vec2, 3> out;
    for (int k = 0; k < 3; ++k) {
        if (m.periodic) {
            out[static_cast<std::size_t>(k)] = m.corner_domain(face_id(f), k) - m.corner_domain(face_id(f), k0);
        } else {
            const Vec3 d = m.corner_position(face_id(f), k) - m.corner_position(face_id(f), k0);
            out[static_cast<std::size_t>(k)] = Vec2(d.dot(fr.e_u), d.dot(fr.e_v));
        }
    }
    return out;
}

double cross2(const Vec2& a, const Vec2& b) {
    return a.x() * b.y() - a.y() * b.x();
}

/// Where a ray from vertex v leaves the fan of its alive faces: face, edge (opposite v) and
/// the parameter along that edge from its first corner.
struct RayHit {
    std::size_t face = 0;
    int edge = -1;
    double t = 0;
};

bool cast_ray(const sim::FemModel& model, std::size_t v, const Vec3& direction0, RayHit& hit) {
    const mesh::SurfaceMesh& m = model.mesh();
    const mesh::TangentFrame fr = model.surface().frame(m.positions[vertex_id(v)]);
    const Vec2 d = Vec2(direction0.dot(fr.e_u), direction0.dot(fr.e_v)).normalized();
    double best = std::numeric_limits<double>::infinity();
    bool found = false;
    for (std::uint32_t f : model.incident_faces(v)) {
        if (!model.alive(face_id(f))) continue;
        const int k = corner_of(m, f, v);
        const auto c = local_corners(model, f, k, fr);
        const Vec2 B = c[static_cast<std::size_t>((k + 1) % 3)], C = c[static_cast<std::size_t>((k + 2) % 3)];
        // s·d = B + τ(C − B): Cramer's rule.
        const Vec2 e = C - B;
        const double det = cross2(d, e);
        if (std::abs(det) < 1e-300) continue;
        const double s = cross2(B, e) / det; // distance along the ray
        const double tau = cross2(B, d) / det;
        if (s <= 0 || tau < -1e-9 || tau > 1 + 1e-9) continue;
        // Several faces can claim a ray through a shared vertex; keep the nearest exit.
        if (s < best) {
            best = s;
            hit.face = f;
            hit.edge = (k + 1) % 3;
            hit.t = std::clamp(tau, 0.0, 1.0);
            found = true;
        }
    }
    return found;
}

/// Smallest angle of a triangle (degrees).
double min_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
    auto angle = [](const Vec3& p, const Vec3& q, const Vec3& r) {
        const Vec3 u = q - p, w = r - p;
        return std::atan2(u.cross(w).norm(), u.dot(w)) * RAD_TO_DEG;
    };
    return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)});
}

/// True if vertex v lies on a crack or the mesh border: some face edge at v has no neighbour.
bool on_border(const sim::FemModel& model, std::size_t v) {
    const mesh::SurfaceMesh& m = model.mesh();
    for (std::uint32_t f : model.incident_faces(v)) {
        const int k = corner_of(m, f, v);
        for (int e : {k, (k + 2) % 3})
            if (m.neighbor(face_id(f), e).face == mesh::NO_FACE) return true;
    }
    return false;
}

/// A crack tip: a vertex on exactly one crack edge, i.e. two border edges at it that run the
/// same way (the two lips of a slit; one lip may have been subdivided, so compare
/// directions, not end points).
bool is_tip(const sim::FemModel& model, std::size_t v) {
    const mesh::SurfaceMesh& m = model.mesh();
    std::vector<Vec3> out;
    for (std::uint32_t f : model.incident_faces(v)) {
        const int k = corner_of(m, f, v);
        const Vec3 p = m.corner_position(face_id(f), k);
        if (m.neighbor(face_id(f), k).face == mesh::NO_FACE)
            out.push_back((m.corner_position(face_id(f), (k + 1) % 3) - p).normalized());
        if (m.neighbor(face_id(f), (k + 2) % 3).face == mesh::NO_FACE)
            out.push_back((m.corner_position(face_id(f), (k + 2) % 3) - p).normalized());
    }
    return out.size() == 2 && out[0].dot(out[1]) > 1 - 1e-9;
}

/// The loop's state.
class Splitter {
public:
    Splitter(sim::FemModel& model, const FractureOptions& options, const SplitOptions& split, Rng& rng, RunStats& stats,
             SplitStats& counts)
        : m_model(model), m_options(options), m_split(split), m_rng(rng), m_stats(stats), m_counts(counts),
          m_cache(model, false), m_events(options) {
        double h = 0;
        for (std::size_t v = 0; v < model.mesh().num_vertices(); ++v)
            h += model.vertex_thickness(vertex_id(v));
        h /= static_cast<double>(std::max<std::size_t>(model.mesh().num_vertices(), 1));
        m_exclusion = split.exclusion_radius >= 0 ? split.exclusion_radius : h;
        m_smoothing =
            split.smoothing_radius >= 0 ? split.smoothing_radius : 1.5 * mesh::mesh_quality(model.mesh()).edge_mean;
        m_local.tolerance = options.local_tolerance;
        m_radius = initial_radius(model, m_local.tolerance);
        m_rate_radius = m_radius;
    }

    /// Runs to the end; returns the event log.
    EventLog& run();

private:
    // === Cutting
    struct CutEnd {
        std::size_t vertex = 0;
        bool ok = false;
    };
    CutEnd cut_towards(std::size_t v, const Vec3& direction, std::vector<FaceId>& touched);
    /// Opens the crack along edges (pairs of vertices); false if nothing could open (a slit
    /// with both ends inside intact material).
    bool open_edges(const std::vector<std::pair<std::size_t, std::size_t>>& edges, std::vector<FaceId>& touched);

    // === Steps
    /// §5.7.6: subdivides the elements around vertex v (its own and one ring of neighbours)
    /// until none is longer than simulation.min_element_size; relaxes and refreshes stresses.
    /// Returns whether anything was subdivided.
    bool refine_vicinity(std::size_t v);
    /// Bisects the elements of v's vicinity (its faces and one ring) until none is longer
    /// than `size`; returns the faces created or changed (no relaxation, no cache update).
    std::vector<FaceId> subdivide_around(std::size_t v, double size, std::size_t* calls = nullptr);
    /// §5.7.8: the crack direction at a tip from a temporary finer sub-model around it (a
    /// trial: refined, relaxed locally with the far nodes held, evaluated, rolled back).
    bool submodel_direction(std::size_t tip, Vec3& crack);
    /// §5.7.7 (Alg. 13): subdivides the elements around nodes whose elements disagree on the
    /// von Mises stress there by more than vm_threshold of the largest principal stress.
    void refine_by_von_mises();
    bool extend_tip(std::size_t tip, Event& ev);
    /// §5.7.9: angle-based smoothing (Zhou & Shimada) of the free nodes near a new tip; each
    /// move keeps the node on the surface, re-interpolates its top node and is taken only if
    /// it improves the worst angle of its elements. Relaxes and refreshes what moved.
    void smooth_near(std::size_t tip);
    /// Local edge flips (§5.7.5 [I]): an edge of a face below the minimum angle is flipped when
    /// that raises the worst angle of its two faces, never across a crack (an open edge has no
    /// face across it). Returns the faces changed.
    std::vector<FaceId> flip_slivers(const std::vector<FaceId>& faces);
    /// Where vertex v would go under one angle-based smoothing step: a face of its fan and
    /// barycentric coordinates in it; false if v is not free or no better place exists.
    bool smoothing_target(std::size_t v, std::size_t& face, Vec3& bary) const;
    enum class Start { Opened, Refined, Blocked };
    Start start_fracture(std::size_t v, double ratio, Event& ev);
    /// Relaxes around the faces; returns the vertices that moved. `released` gets the strain
    /// energy the relaxation released.
    std::vector<std::size_t> relax_near(const std::vector<FaceId>& faces, double* released = nullptr);
    void refresh_after(const std::vector<FaceId>& touched, const std::vector<std::size_t>& moved);
    bool excluded(std::size_t v) const;
    /// Throws InvariantError if a topology change broke the mesh (SplitOptions::check_invariants).
    void check(const char* after) const;
    bool pick_node(std::size_t& node, double& ratio);
    void update_node_ratios();
    void advance_time();

    sim::FemModel& m_model;
    const FractureOptions& m_options;
    const SplitOptions& m_split;
    Rng& m_rng;
    RunStats& m_stats;
    SplitStats& m_counts;
    StressCache m_cache;
    EventLog m_events;
    sim::LocalRelaxOptions m_local;
    double m_radius = 4, m_rate_radius = 4, m_exclusion = 0.01, m_smoothing = 0, m_last_step = 1e-3;
    std::deque<std::size_t> m_tips;
    /// Tips below threshold without Griffith's test: re-examined after every time step.
    std::vector<std::size_t> m_dormant;
    std::vector<Vec3> m_zones; // reference positions of arrested tips
    std::vector<std::size_t> m_rate_seeds;
    bool m_in_trial = false;          ///< a Griffith trial is open: its relaxation may still be undone
    std::vector<double> m_node_ratio; // nodal ratio per vertex, valid where not dirty
    std::vector<char> m_node_dirty;
};

std::vector<std::size_t> Splitter::relax_near(const std::vector<FaceId>& faces, double* released) {
    std::vector<std::size_t> seeds;
    for (FaceId f : faces)
        for (VertexId w : m_model.mesh().faces[f].v)
            seeds.push_back(ix(w));
    std::sort(seeds.begin(), seeds.end());
    seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
    // §5.8.3: no cascade of local relaxations may drift (a trial is checked once accepted).
    return relax_after_change(m_model, seeds, m_radius, m_local, m_options, m_stats, m_rate_seeds, !m_in_trial,
                              released);
}

void Splitter::refresh_after(const std::vector<FaceId>& touched, const std::vector<std::size_t>& moved) {
    Timer timer;
    m_cache.resize();
    for (FaceId f : touched)
        m_cache.refresh(ix(f));
    m_cache.refresh_around(moved);
    m_stats.stress_seconds += timer.seconds();
}

std::vector<FaceId> Splitter::subdivide_around(std::size_t v, double size, std::size_t* calls) {
    std::vector<FaceId> touched;
    for (int round = 0; round < 64; ++round) {
        // The vicinity: v's faces and every face sharing a vertex with them.
        std::vector<std::uint32_t> ring;
        for (std::uint32_t f : m_model.incident_faces(v))
            for (VertexId w : m_model.mesh().faces[face_id(f)].v)
                for (std::uint32_t g : m_model.incident_faces(ix(w)))
                    ring.push_back(g);
        std::sort(ring.begin(), ring.end());
        ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
        constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
        std::uint32_t coarse = none;
        double longest = size;
        for (std::uint32_t f : ring)
            if (m_model.alive(face_id(f)) && m_model.element_size(face_id(f)) > longest) {
                longest = m_model.element_size(face_id(f));
                coarse = f;
            }
        if (coarse == none) break;
        const std::vector<FaceId> faces = m_model.subdivide(face_id(coarse));
        touched.insert(touched.end(), faces.begin(), faces.end());
        if (calls) ++*calls;
    }
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    return touched;
}

bool Splitter::refine_vicinity(std::size_t v) {
    if (m_options.min_element_size <= 0) return false;
    Timer timer;
    const std::vector<FaceId> touched = subdivide_around(v, m_options.min_element_size, &m_counts.subdivisions);
    m_stats.topology_seconds += timer.seconds();
    if (touched.empty()) return false;
    m_cache.resize();
    for (FaceId f : touched)
        m_cache.refresh(ix(f)); // new elements need σ̇ too
    refresh_after(touched, relax_near(touched));
    return true;
}

bool Splitter::submodel_direction(std::size_t tip, Vec3& crack) {
    if (m_split.tip_submodel_levels <= 0) return false;
    Timer timer;
    double size = INFINITY;
    for (std::uint32_t f : m_model.incident_faces(tip))
        size = std::min(size, m_model.element_size(face_id(f)));
    size /= std::pow(2.0, m_split.tip_submodel_levels);
    // A trial: the finer elements, and the solution on them, are gone afterwards (§5.7.8).
    m_model.begin_trial();
    const std::vector<FaceId> touched = subdivide_around(tip, size);
    bool found = false;
    if (!touched.empty()) {
        std::vector<std::size_t> seeds;
        for (FaceId f : touched)
            for (VertexId w : m_model.mesh().faces[f].v)
                seeds.push_back(ix(w));
        std::sort(seeds.begin(), seeds.end());
        seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
        // Nodes outside the relaxed set stay where they are: the sub-model's fixed boundary.
        double radius = m_radius;
        m_model.relax_local(seeds, radius, m_local);
        const NodalStress fine = nodal_stress(m_model, tip);
        if (fine.threshold > 0) {
            crack = fine.crack;
            found = true;
        }
    }
    m_model.rollback();
    ++m_counts.submodels;
    m_stats.stress_seconds += timer.seconds();
    return found;
}

void Splitter::refine_by_von_mises() {
    if (m_split.vm_threshold <= 0 || m_options.min_element_size <= 0) return;
    Timer timer;
    const mesh::SurfaceMesh& m = m_model.mesh();
    auto von_mises = [](const sim::wedge::Vec6& s) {
        return std::sqrt(0.5 * (sqr(s[0] - s[1]) + sqr(s[1] - s[2]) + sqr(s[2] - s[0]))
                         + 3.0 * (sqr(s[3]) + sqr(s[4]) + sqr(s[5])));
    };
    double max_eig = 0;
    for (std::size_t f = 0; f < m.num_faces(); ++f)
        for (const sim::wedge::Vec6& s : m_cache.stress(f))
            max_eig = std::max(max_eig, std::abs(sim::wedge::max_principal(s).value));
    if (max_eig <= 0) return;
    std::vector<std::uint32_t> marked;
    for (std::size_t v = 0; v < m.num_vertices(); ++v) {
        double lo = INFINITY, hi = -INFINITY;
        for (std::uint32_t f : m_model.incident_faces(v)) {
            const double vm = von_mises(m_cache.stress(f)[static_cast<std::size_t>(corner_of(m, f, v))]);
            lo = std::min(lo, vm);
            hi = std::max(hi, vm);
        }
        if (hi - lo > m_split.vm_threshold * max_eig)
            for (std::uint32_t f : m_model.incident_faces(v))
                if (m_model.element_size(face_id(f)) > m_options.min_element_size) marked.push_back(f);
    }
    std::sort(marked.begin(), marked.end());
    marked.erase(std::unique(marked.begin(), marked.end()), marked.end());
    // Longest first, and each only if an earlier bisection has not already made it small.
    std::sort(marked.begin(), marked.end(), [&](std::uint32_t a, std::uint32_t b) {
        return m_model.element_size(face_id(a)) > m_model.element_size(face_id(b));
    });
    std::vector<FaceId> touched;
    for (std::uint32_t f : marked) {
        if (m_model.element_size(face_id(f)) <= m_options.min_element_size) continue;
        const std::vector<FaceId> faces = m_model.subdivide(face_id(f));
        touched.insert(touched.end(), faces.begin(), faces.end());
        ++m_counts.subdivisions;
        ++m_counts.vm_refinements;
    }
    m_stats.topology_seconds += timer.seconds();
    if (touched.empty()) return;
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    m_cache.resize();
    for (FaceId f : touched)
        m_cache.refresh(ix(f));
    refresh_after(touched, relax_near(touched));
}

std::vector<FaceId> Splitter::flip_slivers(const std::vector<FaceId>& faces) {
    Timer timer;
    const mesh::SurfaceMesh& m = m_model.mesh();
    auto worst = [&](const std::array<Vec3, 3>& p) { return min_angle(p[0], p[1], p[2]); };
    auto positive = [&](const std::array<Vec3, 3>& p) {
        const Vec3 c = (p[0] + p[1] + p[2]) / 3.0;
        return (p[1] - p[0]).cross(p[2] - p[0]).dot(m_model.surface().frame(c).n) > 0;
    };
    std::vector<FaceId> changed;
    for (FaceId f : faces) {
        if (ix(f) >= m.num_faces() || worst(m.face_positions(f)) >= m_split.min_angle_deg) continue;
        for (int k = 0; k < 3; ++k) {
            const mesh::FaceNeighbor nb = m.neighbor(f, k);
            if (nb.face == mesh::NO_FACE || nb.face == f) continue;
            // The quad a, d, b, c in f's frame; the flip gives (a, d, c) and (d, b, c).
            const Vec3 a = m.corner_position(f, k), b = m.corner_position(f, (k + 1) % 3),
                       c = m.corner_position(f, (k + 2) % 3);
            const Vec3 d =
                m.corner_position(nb.face, (nb.edge + 2) % 3) + (a - m.corner_position(nb.face, (nb.edge + 1) % 3));
            const std::array<Vec3, 3> n1{a, d, c}, n2{d, b, c};
            if (!positive(n1) || !positive(n2)) continue; // not convex
            const double before = std::min(worst(m.face_positions(f)), worst(m.face_positions(nb.face)));
            if (std::min(worst(n1), worst(n2)) <= before + 1.0) continue;
            const FaceId g = m_model.flip_edge(f, k);
            changed.push_back(f);
            changed.push_back(g);
            ++m_counts.flips;
            break; // f changed: its edges are new
        }
    }
    m_stats.topology_seconds += timer.seconds();
    return changed;
}

bool Splitter::smoothing_target(std::size_t v, std::size_t& face, Vec3& bary) const {
    const mesh::SurfaceMesh& m = m_model.mesh();
    if (on_border(m_model, v)) return false;
    const mesh::TangentFrame fr = m_model.surface().frame(m.positions[vertex_id(v)]);
    // The fan in the plane, v at the origin: per face, its other corners A, B (counter-clockwise).
    struct Wing {
        std::size_t face;
        int k;
        std::size_t a, b;
        Vec2 A, B;
    };
    std::vector<Wing> fan;
    for (std::uint32_t f : m_model.incident_faces(v)) {
        const int k = corner_of(m, f, v);
        const auto c = local_corners(m_model, f, k, fr);
        fan.push_back({f, k, ix(m.faces[face_id(f)].v[static_cast<std::size_t>((k + 1) % 3)]),
                       ix(m.faces[face_id(f)].v[static_cast<std::size_t>((k + 2) % 3)]),
                       c[static_cast<std::size_t>((k + 1) % 3)], c[static_cast<std::size_t>((k + 2) % 3)]});
    }
    auto angle = [](const Vec2& p, const Vec2& q) { return std::atan2(std::abs(cross2(p, q)), p.dot(q)); };
    // Each neighbour j proposes v rotated about j onto the bisector of its two angles in the
    // fan (Zhou & Shimada's torsion springs); the proposals are averaged.
    Vec2 sum = Vec2::Zero();
    int count = 0;
    for (const Wing& w1 : fan) {
        // j = w1's A; its other face has j as B.
        const auto w2 = std::find_if(fan.begin(), fan.end(), [&](const Wing& w) { return w.b == w1.a; });
        if (w2 == fan.end()) return false; // an open fan: not a free node
        const Vec2 j = w1.A, to_v = -j;
        const double next = angle(w1.B - j, to_v), prev = angle(w2->A - j, to_v);
        const double delta = 0.5 * (next - prev), sign = cross2(to_v, w1.B - j) > 0 ? 1.0 : -1.0;
        const double c = std::cos(sign * delta), s = std::sin(sign * delta);
        sum += j + Vec2(c * to_v.x() - s * to_v.y(), s * to_v.x() + c * to_v.y());
        ++count;
    }
    if (count == 0) return false;
    const Vec2 q = sum / count;
    // Only if it makes the worst angle of the fan better.
    auto tri_min = [](const Vec2& p0, const Vec2& p1, const Vec2& p2) {
        if (cross2(p1 - p0, p2 - p0) <= 0) return -1.0;
        auto at = [](const Vec2& a, const Vec2& b, const Vec2& c) {
            const Vec2 u = b - a, w = c - a;
            return std::atan2(std::abs(cross2(u, w)), u.dot(w));
        };
        return std::min({at(p0, p1, p2), at(p1, p2, p0), at(p2, p0, p1)});
    };
    double before = INFINITY, after = INFINITY;
    for (const Wing& w : fan) {
        before = std::min(before, tri_min(Vec2::Zero(), w.A, w.B));
        after = std::min(after, tri_min(q, w.A, w.B));
    }
    if (!(after > before + 1.0 * DEG_TO_RAD)) return false; // worth a re-assembly: at least 1°
    for (const Wing& w : fan) {
        const double area = cross2(w.A, w.B);
        const double la = cross2(q, w.B) / area, lb = cross2(w.A, q) / area, l0 = 1 - la - lb;
        if (l0 < -1e-12 || la < -1e-12 || lb < -1e-12) continue;
        face = w.face;
        bary[w.k] = l0;
        bary[(w.k + 1) % 3] = la;
        bary[(w.k + 2) % 3] = lb;
        return true;
    }
    return false;
}

void Splitter::smooth_near(std::size_t tip) {
    if (m_smoothing <= 0) return;
    Timer timer;
    const mesh::SurfaceMesh& m = m_model.mesh();
    const Vec3 centre = m.positions[vertex_id(tip)];
    // The nodes within the radius, reached through the elements around the tip.
    std::vector<std::size_t> near{tip}, frontier{tip};
    while (!frontier.empty()) {
        std::vector<std::size_t> next;
        for (std::size_t u : frontier)
            for (std::uint32_t f : m_model.incident_faces(u))
                for (VertexId w : m.faces[face_id(f)].v) {
                    const std::size_t x = ix(w);
                    if ((m.positions[w] - centre).norm() > m_smoothing) continue;
                    if (std::find(near.begin(), near.end(), x) != near.end()) continue;
                    near.push_back(x);
                    next.push_back(x);
                }
        frontier.swap(next);
    }
    std::vector<FaceId> touched;
    for (int round = 0; round < 2; ++round)
        for (std::size_t v : near) {
            std::size_t f = 0;
            Vec3 bary = Vec3::Zero();
            if (!smoothing_target(v, f, bary)) continue;
            Vec3 top, rate;
            const mesh::NewVertex target = m_model.face_point(face_id(f), bary, &top, &rate);
            m_model.move_vertex(vertex_id(v), target, top, rate);
            for (std::uint32_t g : m_model.incident_faces(v))
                touched.push_back(face_id(g));
            ++m_counts.smoothed;
        }
    m_stats.topology_seconds += timer.seconds();
    if (touched.empty()) return;
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    refresh_after(touched, relax_near(touched));
}

Splitter::CutEnd Splitter::cut_towards(std::size_t v, const Vec3& direction, std::vector<FaceId>& touched) {
    CutEnd end;
    RayHit hit;
    if (!cast_ray(m_model, v, direction, hit)) return end;
    const mesh::SurfaceMesh& m = m_model.mesh();
    const FaceId f = face_id(hit.face);
    const int kb = hit.edge, kc = (hit.edge + 1) % 3, kv = (hit.edge + 2) % 3;
    const std::size_t b = ix(m.faces[f].v[static_cast<std::size_t>(kb)]);
    const std::size_t c = ix(m.faces[f].v[static_cast<std::size_t>(kc)]);
    // A point of a face's edge where a topology change puts it: on the surface, in the face's
    // frame (on a curved surface the chord runs inside it by up to a sagitta, which next to a
    // thin triangle can fold it).
    const mesh::Surface& surface = m_model.surface();
    auto on_surface = [&](FaceId g, int ka, int kb2, double t) -> Vec3 {
        if (m.periodic) return surface.position((1 - t) * m.corner_domain(g, ka) + t * m.corner_domain(g, kb2));
        return surface.project((1 - t) * m.corner_position(g, ka) + t * m.corner_position(g, kb2));
    };
    // Would the split leave slivers? Check the four new triangles at t = 0.
    const Vec3 V = m.corner_position(f, kv), B = m.corner_position(f, kb), C = m.corner_position(f, kc);
    const Vec3 P = on_surface(f, kb, kc, hit.t);
    double worst = std::min(min_angle(V, B, P), min_angle(V, P, C));
    const mesh::FaceNeighbor nb = m.neighbor(f, hit.edge);
    if (nb.face != mesh::NO_FACE) {
        const Vec3 W = m.corner_position(nb.face, (nb.edge + 2) % 3);
        const Vec3 Bn = m.corner_position(nb.face, (nb.edge + 1) % 3), Cn = m.corner_position(nb.face, nb.edge);
        const Vec3 Pn = on_surface(nb.face, (nb.edge + 1) % 3, nb.edge, hit.t);
        worst = std::min({worst, min_angle(W, Bn, Pn), min_angle(W, Pn, Cn)});
    }
    const bool near_vertex = hit.t < m_split.snap_fraction || hit.t > 1 - m_split.snap_fraction;
    if (!near_vertex && worst >= m_split.min_angle_deg) {
        const auto [nv, faces] = m_model.split_edge(f, hit.edge, hit.t);
        touched.insert(touched.end(), faces.begin(), faces.end());
        end.vertex = ix(nv);
        end.ok = true;
        return end;
    }
    // Edge collapse seen from the survivor (§5.7.5): move the nearer vertex onto the plane if it
    // is free (not on a crack) and its elements stay well shaped; else cut through it as it is.
    const bool to_b = hit.t < 0.5;
    const std::size_t x = to_b ? b : c;
    if (!on_border(m_model, x)) {
        Vec3 top, rate;
        const mesh::NewVertex target = m_model.edge_point(f, hit.edge, hit.t, &top, &rate);
        // Where x lands, seen from each of its faces (move_vertex moves it by the same step in
        // every face's frame): each face must stay well shaped and facing out of the surface.
        Vec2 step = Vec2::Zero();
        if (m.periodic) {
            step = target.domain - m.domain[vertex_id(x)];
            for (int i = 0; i < 2; ++i)
                step[i] -= m.period[i] * std::round(step[i] / m.period[i]);
        }
        bool fine = true;
        for (std::uint32_t g : m_model.incident_faces(x)) {
            const int kx = corner_of(m, g, x);
            std::array<Vec3, 3> q;
            for (int k = 0; k < 3; ++k)
                q[static_cast<std::size_t>(k)] = m.corner_position(face_id(g), k);
            q[static_cast<std::size_t>(kx)] =
                m.periodic ? surface.position(m.corner_domain(face_id(g), kx) + step) : target.position;
            const Vec3 n_after = (q[1] - q[0]).cross(q[2] - q[0]);
            const Vec3 outward = surface.frame(Vec3((q[0] + q[1] + q[2]) / 3.0)).n;
            if (n_after.normalized().dot(outward) < 0.5 || min_angle(q[0], q[1], q[2]) < 0.5 * m_split.min_angle_deg) {
                fine = false;
                break;
            }
        }
        if (fine) {
            m_model.move_vertex(vertex_id(x), target, top, rate);
            for (std::uint32_t g : m_model.incident_faces(x))
                touched.push_back(face_id(g));
            ++m_counts.collapses;
            end.vertex = x;
            end.ok = true;
            return end;
        }
    }
    ++m_counts.snaps;
    end.vertex = x;
    end.ok = true;
    return end;
}

bool Splitter::open_edges(const std::vector<std::pair<std::size_t, std::size_t>>& edges, std::vector<FaceId>& touched) {
    const mesh::SurfaceMesh& m = m_model.mesh();
    std::vector<std::pair<FaceId, int>> sides;
    for (const auto& [a, b] : edges)
        for (std::uint32_t f : m_model.incident_faces(a)) {
            const mesh::Face& face = m.faces[face_id(f)];
            for (int k = 0; k < 3; ++k) {
                const std::size_t p = ix(face.v[static_cast<std::size_t>(k)]);
                const std::size_t q = ix(face.v[static_cast<std::size_t>((k + 1) % 3)]);
                if ((p == a && q == b) || (p == b && q == a)) {
                    sides.emplace_back(face_id(f), k);
                    touched.push_back(face_id(f));
                }
            }
        }
    const auto copies = m_model.cut(sides);
    // Faces moved onto new copies changed their nodes: refresh them too.
    for (const auto& [copy, origin] : copies)
        for (std::uint32_t f : m_model.incident_faces(ix(copy)))
            touched.push_back(face_id(f));
    return !copies.empty();
}

Splitter::Start Splitter::start_fracture(std::size_t v, double ratio, Event& ev) {
    // Fine elements around the node first (§5.7.6); its stress is then looked at again.
    if (refine_vicinity(v)) return Start::Refined;
    Timer timer;
    const NodalStress ns = nodal_from(m_model, v, [&](std::size_t f) { return m_cache.stress(f); });
    std::vector<FaceId> touched;
    const Vec3 p0 = m_model.mesh().positions[vertex_id(v)];
    // Both ways from the node (§5.7.2): two straddling elements, two new tips.
    std::vector<std::pair<std::size_t, std::size_t>> edges;
    std::vector<std::size_t> ends;
    for (double sign : {1.0, -1.0}) {
        const CutEnd e = cut_towards(v, sign * ns.crack, touched);
        if (e.ok && e.vertex != v) {
            edges.emplace_back(v, e.vertex);
            ends.push_back(e.vertex);
        }
    }
    if (edges.empty() || !open_edges(edges, touched)) {
        // Nothing opened: refresh what the cutting changed; the caller fences the node off.
        m_stats.topology_seconds += timer.seconds();
        refresh_after(touched, relax_near(touched));
        return Start::Blocked;
    }
    m_stats.topology_seconds += timer.seconds();
    const std::vector<FaceId> flipped = flip_slivers(touched);
    touched.insert(touched.end(), flipped.begin(), flipped.end());
    const std::vector<std::size_t> moved = relax_near(touched);
    refresh_after(touched, moved);
    for (std::size_t e : ends)
        if (is_tip(m_model, e)) {
            m_tips.push_back(e);
            smooth_near(e);
        }
    ev.time = m_model.time();
    ev.position = p0;
    ev.kind = "split";
    ev.ratio = ratio;
    ++m_counts.splits;
    return Start::Opened;
}

bool Splitter::extend_tip(std::size_t tip, Event& ev) {
    if (tip >= m_model.mesh().num_vertices() || !is_tip(m_model, tip)) return false;
    if (refine_vicinity(tip)) {
        m_tips.push_front(tip); // look again, on the finer mesh
        return false;
    }
    const NodalStress ns = nodal_from(m_model, tip, [&](std::size_t f) { return m_cache.stress(f); });
    if (ns.threshold <= 0) return false;
    if (!m_split.griffith && ns.ratio < 1.0) {
        // Without Griffith's test a tip runs on its stress alone: below threshold it waits for
        // the load to rise, and Alg. 5's time step ends when it crosses (advance_time()).
        m_dormant.push_back(tip);
        return false;
    }
    // Onwards: away from the crack behind the tip (its lips' far ends).
    const mesh::SurfaceMesh& m = m_model.mesh();
    Vec3 behind = Vec3::Zero();
    for (std::uint32_t f : m_model.incident_faces(tip)) {
        const int k = corner_of(m, f, tip);
        if (m.neighbor(face_id(f), k).face == mesh::NO_FACE)
            behind = m.corner_position(face_id(f), (k + 1) % 3) - m.corner_position(face_id(f), k);
    }
    Vec3 dir = ns.crack;
    submodel_direction(tip, dir); // keeps ns.crack when off
    if (dir.dot(behind) > 0) dir = -dir;

    Timer timer;
    // A trial, so a rejected extension rolls back exactly (digest §3.9.4 caveat 2). The stress
    // cache is refreshed only once an extension is accepted, so it needs no undo.
    const bool trial = m_split.griffith;
    if (trial) m_model.begin_trial();
    m_in_trial = trial;
    // What a rolled-back cut counted is not kept.
    const std::size_t collapses = m_counts.collapses, snaps = m_counts.snaps;
    auto roll_back = [&] {
        m_model.rollback();
        m_counts.collapses = collapses;
        m_counts.snaps = snaps;
    };
    std::vector<FaceId> touched;
    const CutEnd end = cut_towards(tip, dir, touched);
    if (!end.ok || end.vertex == tip) {
        m_in_trial = false;
        if (trial)
            roll_back();
        else if (!touched.empty())
            refresh_after(touched, relax_near(touched));
        return false;
    }
    const Vec3 a0 = m_model.bottom_position(vertex_id(tip)), b0 = m_model.bottom_position(vertex_id(end.vertex));
    const double area = (b0 - a0).norm() * 0.5
                        * (m_model.vertex_thickness(vertex_id(tip)) + m_model.vertex_thickness(vertex_id(end.vertex)));
    const bool opened = open_edges({{tip, end.vertex}}, touched);
    m_stats.topology_seconds += timer.seconds();
    if (!opened) {
        // The cut ran along an edge that was already cracked: the tip has nowhere to go.
        m_in_trial = false;
        if (trial)
            roll_back();
        else
            refresh_after(touched, relax_near(touched));
        return false;
    }
    double released = 0;
    std::vector<std::size_t> moved = relax_near(touched, &released);
    m_in_trial = false;

    if (m_split.griffith) {
        // Alg. 11 with the physical ½F·u (digest caveat 1): cutting at fixed positions keeps
        // the strain energy (a duplicated node; a node split into an edge at its rest position
        // plus the interpolated displacement, which on a curved surface releases next to nothing
        // itself: < 3 % of a cut's release on coarse meshes, less on fine ones), so what the cut
        // releases is what the relaxation after it releases, ½ rᵀΔx, exact for the linear
        // solves and local to the change (tests compare it with the energy sums).
        timer.reset();
        const double G = released / std::max(area, 1e-300);
        const double nu = m_model.poisson_ratio();
        const double G_ic = (1 - nu * nu) * sqr(ns.toughness) / ns.young;
        m_stats.stress_seconds += timer.seconds();
        if (!(G > G_ic)) {
            roll_back();
            m_zones.push_back(m_model.mesh().positions[vertex_id(tip)]);
            ++m_counts.arrests;
            Event arrest;
            arrest.time = m_model.time();
            arrest.position = m_zones.back();
            arrest.kind = "arrest";
            arrest.ratio = ns.ratio;
            m_counts.arrests_at.push_back(arrest);
            return false;
        }
    }
    if (trial) {
        m_model.commit();
        if (check_drift(m_model, m_options, m_radius, m_stats)) moved = m_model.last_updated_vertices();
    }
    refresh_after(touched, moved);
    // After the energy test: flips change the discrete energy at fixed nodes.
    const std::vector<FaceId> flipped = flip_slivers(touched);
    if (!flipped.empty()) refresh_after(flipped, relax_near(flipped));
    if (is_tip(m_model, end.vertex)) {
        m_tips.push_back(end.vertex);
        smooth_near(end.vertex);
    }
    ev.time = m_model.time();
    ev.position = m_model.mesh().positions[vertex_id(end.vertex)];
    ev.kind = "extend";
    ev.ratio = ns.ratio;
    ++m_counts.extensions;
    return true;
}

void Splitter::check(const char* after) const {
    if (!m_split.check_invariants) return;
    const std::string problem = check_split_invariants(m_model);
    if (!problem.empty()) throw InvariantError(std::string("fem-split, after ") + after + ": " + problem);
}

bool Splitter::excluded(std::size_t v) const {
    const Vec3& p = m_model.mesh().positions[vertex_id(v)];
    for (const Vec3& z : m_zones)
        if ((p - z).norm() < m_exclusion) return true;
    return false;
}

void Splitter::update_node_ratios() {
    // Only nodes of faces whose stress changed since the last pick need a new value.
    const std::size_t nv = m_model.mesh().num_vertices();
    std::vector<std::uint32_t> faces;
    const bool all = m_cache.take_changes(faces);
    m_node_ratio.resize(nv, 0.0);
    m_node_dirty.resize(nv, 1);
    if (all) std::fill(m_node_dirty.begin(), m_node_dirty.end(), 1);
    for (std::uint32_t f : faces)
        if (f < m_model.mesh().num_faces())
            for (VertexId w : m_model.mesh().faces[face_id(f)].v)
                m_node_dirty[ix(w)] = 1;
    for (std::size_t v = 0; v < nv; ++v) {
        if (!m_node_dirty[v]) continue;
        m_node_dirty[v] = 0;
        m_node_ratio[v] = nodal_from(m_model, v, [&](std::size_t f) { return m_cache.stress(f); }).ratio;
    }
}

bool Splitter::pick_node(std::size_t& node, double& ratio) {
    Timer timer;
    update_node_ratios();
    // Intact nodes and crack lips (a new crack may start at an old one's side); tips have their
    // own queue, and arrested ones their exclusion zones.
    const bool found = pick_most_over(
        m_model.mesh().num_vertices(), [&](std::size_t v) { return m_node_ratio[v]; },
        [&](std::size_t v) { return !m_model.incident_faces(v).empty() && !is_tip(m_model, v) && !excluded(v); }, m_rng,
        node, ratio);
    m_stats.stress_seconds += timer.seconds();
    return found;
}

void Splitter::advance_time() {
    Timer timer;
    settle_time_step(m_model, m_cache, m_options, m_local, m_rate_radius, m_rate_seeds, m_stats);

    // === Alg. 5 on nodal stresses: each node's in-surface ratio is convex in time along the
    // affine solution, so bracket the first crossing and bisect.
    timer.reset();
    const double t0 = m_model.time();
    const double horizon = std::min(m_options.duration, m_model.stiffness_horizon());
    const double dt_min = m_options.time_tolerance * m_options.duration;
    const std::size_t nv = m_model.mesh().num_vertices();
    // Each node's projected tensor is affine in time (the frame is held at t0 over the step):
    // T(t0 + τ) = T0 + τ·T1, so a probe costs a closed-form 2×2 eigenvalue per node.
    struct NodeLine {
        std::size_t v;
        Mat2 T0, T1;
        double threshold;
    };
    std::vector<NodeLine> lines;
    std::vector<char> dormant(nv, 0);
    for (std::size_t t : m_dormant)
        if (t < nv) dormant[t] = 1;
    for (std::size_t v = 0; v < nv; ++v) {
        // Waiting tips take part too: the step ends when one of them reaches the threshold.
        if (m_model.incident_faces(v).empty() || (is_tip(m_model, v) && !dormant[v]) || excluded(v)) continue;
        NodalStress means;
        Mat3 s0, s1;
        if (!nodal_tensor(
                m_model, v, [&](std::size_t f) -> const sim::TopStress& { return m_cache.stress(f); }, s0, means))
            continue;
        nodal_tensor(
            m_model, v, [&](std::size_t f) -> const sim::TopStress& { return m_cache.rate(f); }, s1, means);
        const NodeFrame fr = node_frame(m_model, v);
        lines.push_back({v, project(fr, s0), project(fr, s1), means.threshold});
    }
    auto over = [&](double t, std::vector<NodeLine>* which) {
        const double tau = t - t0;
        bool any = false;
        for (const NodeLine& l : lines)
            if (max_eigenvalue(l.T0 + tau * l.T1) > l.threshold) {
                any = true;
                if (!which) return true;
                which->push_back(l);
            }
        return any;
    };
    const double t_next = next_crossing(
        t0, horizon, dt_min, m_last_step, [&](double t) { return over(t, nullptr); },
        [&](double t_hi) {
            std::vector<NodeLine> candidates;
            over(t_hi, &candidates);
            lines = std::move(candidates);
        });
    m_stats.stress_seconds += timer.seconds();
    advance_model(m_model, m_cache, t_next, m_stats);
}

EventLog& Splitter::run() {
    {
        Timer setup, timer;
        m_stats.solver_iterations += m_model.relax().iterations + m_model.solve_rate().iterations;
        m_stats.solves += 2;
        m_stats.solve_seconds += timer.seconds();
        timer.reset();
        m_cache.refresh_all();
        m_stats.stress_seconds += timer.seconds();
        m_stats.setup_seconds = setup.seconds();
    }
    Progress progress("fracture", m_options.duration);
    while (true) {
        progress.update(m_model.time());
        if (m_events.full(m_model.time())) break;
        // Tips first, first in first out (§5.7.4, Fig. 5.20).
        if (!m_tips.empty()) {
            const std::size_t tip = m_tips.front();
            m_tips.pop_front();
            Event ev;
            if (extend_tip(tip, ev)) m_events.add(ev, m_model);
            check("a crack-tip step");
            continue;
        }
        std::size_t node = 0;
        double ratio = 0;
        if (pick_node(node, ratio)) {
            Event ev;
            const Start started = start_fracture(node, ratio, ev);
            if (started == Start::Opened)
                m_events.add(ev, m_model);
            else if (started == Start::Blocked)
                m_zones.push_back(m_model.mesh().positions[vertex_id(node)]); // nowhere to cut
            check("a new fracture");
            continue;
        }
        if (m_model.time() >= m_options.duration) break;
        advance_time();
        // Tips that waited for the load look again, in the order they stopped.
        m_tips.insert(m_tips.end(), m_dormant.begin(), m_dormant.end());
        m_dormant.clear();
        refine_by_von_mises();
        check("von Mises refinement");
    }
    progress.finish();
    return m_events;
}

} // namespace

std::string check_split_invariants(const sim::FemModel& model) {
    const mesh::SurfaceMesh& m = model.mesh();
    std::string problem = m.validate();
    if (!problem.empty()) return problem;
    std::ostringstream os;
    for (std::size_t f = 0; f < m.num_faces(); ++f) {
        for (VertexId w : m.faces[face_id(f)].v) {
            const auto& list = model.incident_faces(ix(w));
            if (std::find(list.begin(), list.end(), static_cast<std::uint32_t>(f)) == list.end()) {
                os << "face " << f << " is missing from the incidence list of its vertex " << ix(w);
                return os.str();
            }
        }
        if (!model.alive(face_id(f))) continue;
        const auto p = m.face_positions(face_id(f));
        const Vec3 c = (p[0] + p[1] + p[2]) / 3.0;
        if ((p[1] - p[0]).cross(p[2] - p[0]).dot(model.surface().frame(c).n) <= 0) {
            os << "face " << f << " is inverted or degenerate at t = 0";
            return os.str();
        }
        if (!(sim::wedge::volume(model.reference_nodes(face_id(f))) > 0)) {
            os << "element " << f << " has a non-positive reference volume";
            return os.str();
        }
    }
    for (std::size_t v = 0; v < m.num_vertices(); ++v)
        for (std::uint32_t f : model.incident_faces(v))
            if (corner_of(m, f, v) < 0) {
                os << "vertex " << v << " lists face " << f << " which does not contain it";
                return os.str();
            }
    return {};
}

std::vector<std::size_t> crack_tips(const sim::FemModel& model) {
    std::vector<std::size_t> tips;
    for (std::size_t v = 0; v < model.mesh().num_vertices(); ++v)
        if (!model.incident_faces(v).empty() && is_tip(model, v)) tips.push_back(v);
    return tips;
}

NodalStress nodal_stress(const sim::FemModel& model, std::size_t vertex) {
    return nodal_from(model, vertex, [&](std::size_t f) { return model.top_stress(face_id(f)); });
}

CrackPattern run_fem_split(sim::FemModel& model, const FractureOptions& options, const SplitOptions& split, Rng& rng,
                           RunStats* stats_out, SplitStats* split_out) {
    RunStats stats;
    SplitStats counts;
    Timer total;
    const std::size_t elements_initial = model.num_alive();
    Splitter splitter(model, options, split, rng, stats, counts);
    EventLog& events = splitter.run();
    CrackPattern pattern = pattern_from_model(model, "fem-split", elements_initial);
    // Crack openings: the distance between the deformed midpoints of the two lips of an edge.
    std::map<std::array<double, 6>, std::vector<std::size_t>> lips;
    for (std::size_t i = 0; i < pattern.cracks.size(); ++i) {
        const CrackEdge& c = pattern.cracks[i];
        const mesh::Face& face = pattern.mesh.faces[c.face];
        Vec3 a = pattern.mesh.positions[face.v[static_cast<std::size_t>(c.edge)]];
        Vec3 b = pattern.mesh.positions[face.v[static_cast<std::size_t>((c.edge + 1) % 3)]];
        if (std::lexicographical_compare(b.data(), b.data() + 3, a.data(), a.data() + 3)) std::swap(a, b);
        lips[{a.x(), a.y(), a.z(), b.x(), b.y(), b.z()}].push_back(i);
    }
    for (const auto& [key, ids] : lips) {
        if (ids.size() != 2) continue;
        auto mid = [&](const CrackEdge& c) -> Vec3 {
            const Vec3 p = pattern.deformed_corner(c.face, c.edge);
            const Vec3 q = pattern.deformed_corner(c.face, (c.edge + 1) % 3);
            return 0.5 * (p + q);
        };
        const double w = (mid(pattern.cracks[ids[0]]) - mid(pattern.cracks[ids[1]])).norm();
        pattern.cracks[ids[0]].opening = pattern.cracks[ids[1]].opening = w;
    }
    pattern.events_capped = events.capped();
    pattern.events = events.take();
    stats.total_seconds = total.seconds();
    if (stats_out) *stats_out = stats;
    if (split_out) *split_out = counts;
    return pattern;
}

} // namespace crackle::fracture
