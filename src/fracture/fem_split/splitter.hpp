#pragma once
/// @file Private to fem_split/*.cpp: the Splitter loop's state and the geometry helpers it shares (Federl 2002, §5.7).

#include "fracture/fem_split/fem_split.hpp"
#include "fracture/toolkit/fem_loop.hpp"

#include <Eigen/Eigenvalues>

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <utility>
#include <vector>

namespace crackle::fracture::split_detail {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;
using mesh::vertex_id;
using mesh::VertexId;

/// Corner index of vertex v in face f (−1 if absent).
int corner_of(const mesh::SurfaceMesh& m, std::size_t f, std::size_t v);

/// The current tangent plane at a node (orthonormal e1, e2 of the grown surface) and the
/// inverse growth map back to t = 0.
struct NodeFrame {
    Vec3 e1, e2, n;
    Mat3 G_inv;
};

NodeFrame node_frame(const sim::FemModel& model, std::size_t v);
/// The same with the growth map G at the model's time and its inverse given (one per time step).
NodeFrame node_frame(const sim::FemModel& model, std::size_t v, const Mat3& G, const Mat3& G_inv);

/// A 3D stress tensor projected on the tangent plane (2×2, symmetric).
Mat2 project(const NodeFrame& fr, const Mat3& sigma);

/// Largest eigenvalue of a symmetric 2×2 matrix, closed form.
double max_eigenvalue(const Mat2& T);

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

/// The in-surface principal stress of a node's stress tensor (§5.7.2): the largest eigenvalue of
/// the projected tensor over the threshold in `means`, and the crack direction normal to it (in
/// the plane), mapped back to t = 0 by the inverse growth map.
NodalStress principal_of(const sim::FemModel& model, std::size_t v, const Mat3& sigma, NodalStress means);

/// The in-surface principal stress of a node (§5.7.1–5.7.2): the largest eigenvalue of the
/// projected tensor over the threshold, and the crack direction normal to it (in the plane),
/// mapped back to t = 0 by the inverse growth map.
template <class StressOf> NodalStress nodal_from(const sim::FemModel& model, std::size_t v, StressOf&& stress_of) {
    NodalStress out;
    Mat3 sigma;
    if (!nodal_tensor(model, v, stress_of, sigma, out)) return out;
    return principal_of(model, v, sigma, out);
}

/// 2D coordinates of a face's corners around one of its corners, in the frame of the surface
/// at t = 0: the unrolled domain on periodic surfaces, the tangent plane at the corner on the
/// sphere.
std::array<Vec2, 3> local_corners(const sim::FemModel& model, std::size_t f, int k0, const mesh::TangentFrame& fr);

double cross2(const Vec2& a, const Vec2& b);

/// Where a ray from vertex v leaves the fan of its alive faces: face, edge (opposite v) and
/// the parameter along that edge from its first corner.
struct RayHit {
    std::size_t face = 0;
    int edge = -1;
    double t = 0;
};

bool cast_ray(const sim::FemModel& model, std::size_t v, const Vec3& direction0, RayHit& hit);

/// Smallest angle of a triangle (degrees).
double min_angle(const Vec3& a, const Vec3& b, const Vec3& c);

/// True if vertex v lies on a crack or the mesh border: some face edge at v has no neighbour.
bool on_border(const sim::FemModel& model, std::size_t v);

/// A crack tip: a vertex on exactly one crack edge, i.e. two border edges at it that run the
/// same way (the two lips of a slit; one lip may have been subdivided, so compare
/// directions, not end points).
bool is_tip(const sim::FemModel& model, std::size_t v);

class NonlocalStress;

/// The loop's state.
class Splitter {
public:
    Splitter(sim::FemModel& model, const FractureOptions& options, const SplitOptions& split, Rng& rng, RunStats& stats,
             SplitStats& counts);
    ~Splitter();

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
    /// The stress a node's criterion reads: averaged over simulation's initiation length
    /// (nonlocal.hpp), or the thesis' nodal average (§5.7.1).
    NodalStress node_stress(std::size_t v) const;
    void make_nonlocal();
    /// The length a new crack starts with (m): the initiation length at node v.
    double nucleus_length(std::size_t v) const;
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
    std::unique_ptr<NonlocalStress> m_nonlocal; // null: the thesis' nodal stress
    std::map<std::size_t, double> m_nucleus;    // tip → length its nucleus still has to grow (m)
};

} // namespace crackle::fracture::split_detail
