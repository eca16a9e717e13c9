#pragma once
/// @file Graph-based FEM fracture (Mandal, Chaudhuri & Chaudhuri; graph-fem digest), adapted to
/// Federl's wedge layer (digest §7): the top-surface triangle edges are the bonds of a graph; an
/// edge breaks when the element stress projected on it (tension only, optionally averaged over a
/// radius R_d in metres) reaches the threshold, and every element sharing a broken edge loses
/// the in-plane strain along it (sim::wedge::edge_projector). The unknowns and the sparsity of
/// K never change. The driver is Federl's: one break per relaxation, ties drawn from the seed,
/// local relaxation (§5.8), and the next break time in closed form (stresses are affine in time
/// while K is fixed: digest §7.5, thesis Alg. 5 without the bisection).

#include "core/rng.hpp"
#include "core/settings.hpp"
#include "fracture/crack_pattern.hpp"
#include "fracture/run.hpp"
#include "fracture/toolkit/stress_cache.hpp"
#include "sim/fem_model.hpp"

#include <array>
#include <cstdint>
#include <vector>

namespace crackle::fracture {

struct GraphFemOptions {
    /// R_d (m): the criterion reads the area-weighted mean stress of the faces whose centroids lie
    /// within this distance (measured along the surface, not across broken edges); 0 = the
    /// element's own stress (digest §1.5, Eq. 13). Metres, so refining the mesh keeps the physics.
    double damage_radius = 0.0;
    /// Griffith (not in the paper; digest §7.5, thesis Alg. 11): cracks start where the stress
    /// reaches the threshold, then their tips run on through the tip face's most stressed edge
    /// while the energy a break releases pays for the new crack wall (G_c × dual-edge length ×
    /// thickness; a trial, rolled back when it does not: the tip is arrested). A stress-driven
    /// break next to an existing crack must pay the same (else it waits until the load has grown
    /// enough for it to pay, estimated from the trial: released energy ∝ load²).
    /// false: the paper's pure stress criterion.
    bool griffith = true;
    bool operator==(const GraphFemOptions&) const = default;
};
/// The method's options from its [simulation] keys (method.cpp).
GraphFemOptions graph_fem_options(const Settings& settings);

struct GraphFemStats {
    std::size_t breaks = 0;                               ///< edges broken
    std::size_t griffith_rejections = 0;                  ///< breaks undone by the Griffith test (gate or extension)
    std::size_t extensions = 0;                           ///< Griffith-driven tip extensions (kind "extend")
    std::size_t arrests = 0;                              ///< tip extensions that did not pay
    std::size_t edges = 0;                                ///< graph edges (top-surface triangle edges)
    std::size_t nonzeros_initial = 0, nonzeros_final = 0; ///< of K: the same, by construction
    /// Where and when each tip stopped (kind "arrest", position the midpoint of the edge whose
    /// break did not pay, ratio its stress over threshold then), as fem-split's.
    std::vector<Event> arrests_at;
};

/// The graph: one entry per top-surface triangle edge, with its one or two sides (face, edge).
class EdgeGraph {
public:
    struct Side {
        std::uint32_t face;
        int edge;
    };
    struct Edge {
        std::array<Side, 2> side;
        int sides = 1;
    };
    explicit EdgeGraph(const mesh::SurfaceMesh& mesh);
    std::size_t size() const { return m_edges.size(); }
    const Edge& edge(std::size_t e) const { return m_edges[e]; }
    std::size_t edge_of(std::size_t face, int k) const { return m_of_face[face][static_cast<std::size_t>(k)]; }
    bool broken(const sim::FemModel& model, std::size_t e) const {
        const Side& s = m_edges[e].side[0];
        return ((model.broken_edges(mesh::face_id(s.face)) >> s.edge) & 1u) != 0;
    }

private:
    std::vector<Edge> m_edges;
    std::vector<std::array<std::size_t, 3>> m_of_face;
};

/// The breaking criterion (digest §1.5, Eq. 14 with errata E2, E3): per side (face f, edge k),
/// r = d_kᵀ σ̄_f d_k / σ_th,f with σ̄_f the mean of f's three top Gauss-point stresses, averaged
/// over R_d, and d_k the edge's unit direction on the reference shape (small strain: rest
/// directions). An edge's ratio is the larger of its two sides' ("any element votes"). Affine
/// in time: r(t₀ + τ) = a + b·τ, so the next crossing is closed form.
class EdgeCriterion {
public:
    EdgeCriterion(const sim::FemModel& model, const StressCache& cache, const EdgeGraph& graph, double radius);
    /// Re-reads every stress and rate from the cache.
    void refresh_all();
    /// Re-reads the faces whose stress or rate changed (and, with R_d, those averaging them).
    void refresh(const std::vector<std::uint32_t>& faces);
    /// After edge e broke: the averaging neighbourhoods that crossed it are rebuilt.
    void broke(std::size_t e);
    /// Ratio of an intact edge τ after the cache's time (the larger side).
    double ratio_at(std::size_t e, double tau) const;
    double ratio(std::size_t e) const { return ratio_at(e, 0.0); }
    /// Closed form: the smallest τ ≥ 0 at which an intact edge's rising ratio reaches its level
    /// (`level[e]`; 1 for every edge when empty), ∞ when none rises, and which edge.
    double next_crossing(const std::vector<double>& level, std::size_t* edge = nullptr) const;
    /// The faces R_d-averaging face f (f itself when R_d = 0), with their weights.
    const std::vector<std::pair<std::uint32_t, double>>& neighbourhood(std::size_t f) const { return m_hood[f]; }

private:
    void build_hood(std::size_t f);
    void update_face(std::size_t f);

    const sim::FemModel& m_model;
    const StressCache& m_cache;
    const EdgeGraph& m_graph;
    double m_radius;
    std::vector<std::array<Vec3, 3>> m_dir;                            // unit edge directions
    std::vector<sim::wedge::Vec6> m_mean, m_mean_rate;                 // per face, before averaging
    std::vector<std::array<double, 3>> m_a, m_b;                       // per side: ratio and its rate
    std::vector<std::vector<std::pair<std::uint32_t, double>>> m_hood; // R_d neighbourhoods
    std::vector<std::uint32_t> m_stamp_of;
    std::uint32_t m_stamp = 0;
};

/// The crack pattern of a graph-fem run on the mesh's dual (digest §7.6): each face is cut into
/// kites around its corners through its centroid and, on broken edges, the edge midpoint; the
/// kite mesh is opened along the dual segments (midpoint → centroid) of every broken edge, and
/// each vertex copy follows the mean displacement of the corners on its side. Where a crack
/// passes through a face the dual point moves onto the line between its two edge midpoints
/// (rendering only), so cracks do not kink at every centroid.
CrackPattern graph_pattern(const sim::FemModel& model, const EdgeGraph& graph, std::size_t elements_initial);

/// Runs graph-fem from the model's current time to `options.duration`.
CrackPattern run_graph_fem(sim::FemModel& model, const FractureOptions& options, const GraphFemOptions& graph, Rng& rng,
                           RunStats* stats = nullptr, GraphFemStats* graph_stats = nullptr);

} // namespace crackle::fracture
