#pragma once
/// @file The wedge-FEM layer (Federl 2002, §5.3–5.6): one 6-node wedge per surface triangle,
/// bottom nodes pinned to the growing background, top nodes free. Assembles the global
/// stiffness of the free (top) nodes, solves the equilibrium, evaluates stresses, and
/// changes topology by element removal (Alg. 7) and Rivara bisection (Alg. 9).
///
/// Unknowns are the canonical top-node positions x_v, three per surface vertex, and with a
/// through-thickness order p > 1 (FemOptions::thickness_order, wedge_modes.hpp) the p − 1 mode
/// amplitudes of each vertex: p "slots" of three unknowns per vertex, slot p·v + j (j = 0: the
/// top node). The bottom nodes are eliminated (digest §3.6, "symmetry pitfall"), so the system
/// K_tt·x = b stays symmetric positive definite. On periodic surfaces a face corner with lattice offset o uses
/// x_v + s(o, t), where the period shift s grows with the background; nodes across the seam
/// are the same unknowns.
///
/// With the stiffness fixed, the loads are affine in time (linear growth, Eq. 3.4; linear
/// shrinkage, §3.3.2), so the equilibrium is too: x(t) = x(t₀) + (t − t₀)·ẋ. The fracture
/// loop uses that to find the time of the next fracture (Alg. 5) without re-solving at every
/// trial time. Shrinkage changes the reference shapes and so K; the stiffness is rebuilt
/// whenever the shrinkage scale has moved by more than `stiffness_refresh` since the last
/// build (digest §1.10 [I]).
///
/// The implementation is split by responsibility: fem_model.cpp (construction, positions), fem_assembly.cpp,
/// fem_solver.cpp, fem_local.cpp, fem_time.cpp, fem_stress.cpp, fem_topology.cpp and fem_trial.cpp, sharing
/// fem_model_internal.hpp.

#include "mesh/refine.hpp"
#include "mesh/surface.hpp"
#include "mesh/surface_mesh.hpp"
#include "sim/fem_options.hpp"
#include "sim/growth_field.hpp"
#include "sim/layer_fields.hpp"
#include "sim/property_field.hpp"
#include "sim/reference_shape.hpp"
#include "sim/wedge_element.hpp"
#include "sim/wedge_modes.hpp"

#include <Eigen/SparseCore>

#include <array>
#include <memory>
#include <vector>

namespace crackle::sim {

struct SolveStats {
    int iterations = 0;
    double residual = 0; ///< final residual relative to the load
    double seconds = 0;
    std::size_t nodes = 0;  ///< nodes solved for (all, or the local set)
    bool fell_back = false; ///< a local relaxation that had to solve globally
    /// Strain energy the solve released (J): ½ rᵀΔx, exact for each linear solve (the energy is
    /// quadratic in the top positions). Meaningful for positions, not rates.
    double energy_release = 0;
};

/// Adaptive local relaxation (Federl 2002, §5.8; digest §3.10): after a local change, solve
/// only for the nodes within a graph radius of it, holding the rest, and grow the radius
/// until the remaining residual is small next to the change's own.
struct LocalRelaxOptions {
    /// Largest force pushed out of the solved set, relative to the change's largest nodal force.
    /// 1e-2 needs about 7 hops on thin layers (error ∝ exp(−r/1.6h), docs/perf-limits.md).
    double tolerance = 1e-2;
    double max_fraction = 0.25; ///< solve globally when the local set passes this share of nodes
    int min_radius = 2;         ///< hops
};

/// σ at the three Gauss points nearest the top face (Voigt order, Pa).
using TopStress = std::array<wedge::Vec6, 3>;

class FemModel {
public:
    FemModel(mesh::SurfaceMesh mesh, const mesh::Surface& surface, const GrowthField& growth,
             const ShrinkageOptions& shrinkage, const LayerFields& fields, const FemOptions& options = {});
    ~FemModel();
    /// Copies are whole snapshots (fem-split rolls back rejected crack extensions with one);
    /// the copy's solver is rebuilt on its first solve.
    FemModel(const FemModel&) = default;
    FemModel& operator=(const FemModel&) = default;
    FemModel(FemModel&&) = default;
    FemModel& operator=(FemModel&&) = default;

    // === State
    const mesh::SurfaceMesh& mesh() const { return m_mesh; }
    const mesh::Surface& surface() const { return m_surface; }
    const GrowthField& growth() const { return m_growth; }
    double time() const { return m_time; }
    bool alive(mesh::FaceId f) const { return m_alive[mesh::ix(f)] != 0; }
    std::size_t num_alive() const { return m_num_alive; }
    const ElementMaterial& material(mesh::FaceId f) const { return m_material[mesh::ix(f)]; }
    double poisson_ratio() const { return m_fields.poisson_ratio; }
    double vertex_thickness(mesh::VertexId v) const { return m_thickness[mesh::ix(v)]; }
    /// Through-thickness order p of the displacement (1: the thesis' linear wedge).
    int thickness_order() const { return m_order; }

    // === Time and equilibrium
    /// Moves the background and the reference shapes to time t, leaving the top nodes where
    /// they are (they then need relax()). Rebuilds the stiffness when shrinkage has changed the
    /// reference shapes enough.
    void set_time(double t);
    /// Moves to time t along the exact affine solution: x += (t − t₀)·ẋ, with the tracked
    /// residuals carried along (no solve). Falls back to set_time() + invalidated residuals
    /// when the stiffness has to be rebuilt at t.
    void advance_time(double t);
    /// The time at which the shrinkage will have moved by `stiffness_refresh` since the last
    /// build (∞ without shrinkage, or with a refresh of 0): advance_time() rebuilds on reaching
    /// it, so the fracture loops end a time step there.
    double stiffness_horizon() const;
    /// True when the stiffness changed since the last relax() (a refresh or a topology change).
    bool stiffness_changed() const { return m_stiffness_dirty_for_x; }
    /// How many times shrinkage made the whole stiffness be rebuilt (refreshes, not topology).
    std::size_t stiffness_builds() const { return m_stiffness_builds; }

    /// Solves the equilibrium at the current time, warm-started from the current positions
    /// (the increment solves the tracked residual). Throws NumericError when the solver fails.
    SolveStats relax();
    /// Solves for ẋ = ∂x/∂t at the current time with the current stiffness (warm-started).
    SolveStats solve_rate();
    /// Relaxes the positions only around `seeds` (§5.8): the nodes within `radius` hops along
    /// intact elements (so the set does not leak across cracks, Fig. 5.25) are solved with the
    /// rest held; while the largest remaining nodal force exceeds `tolerance` × the change's,
    /// the radius doubles, and past `max_fraction` of the nodes it solves globally. `radius`
    /// adapts in place (§5.8.3): shrunk by 10 % after a first-try success, doubled when more
    /// was needed.
    SolveStats relax_local(const std::vector<std::size_t>& seeds, double& radius,
                           const LocalRelaxOptions& options = {});
    /// The same for the rate solution ẋ (a removal changes it only nearby, too).
    SolveStats relax_rate_local(const std::vector<std::size_t>& seeds, double& radius,
                                const LocalRelaxOptions& options = {});
    /// Moves the top nodes along the rate solution: x += dt·ẋ (exact while K is fixed).
    void advance_along_rate(double dt);
    /// Per-vertex size of the last solve's update (m, or m per unit time for rates).
    const std::vector<double>& last_update() const { return m_last_update; }
    /// The vertices the last solve changed.
    const std::vector<std::size_t>& last_updated_vertices() const { return m_updated; }
    /// Largest nodal force left in the position residual (N).
    double max_residual_force();
    /// The vertices whose position residual force exceeds `force` (N), ascending.
    std::vector<std::size_t> vertices_over_residual(double force);
    /// The same for the rate solution ẋ (N per unit time).
    double max_rate_residual_force();
    /// A nodal force that cracks an element: mean threshold × thickness × edge length (N).
    double force_scale() const { return m_force_scale; }
    /// Faces around a vertex (alive or not).
    const std::vector<std::uint32_t>& incident_faces(std::size_t v) const { return m_incident[v]; }

    // === Positions
    Vec3 top_position(mesh::VertexId v) const { return m_x.values[slot(mesh::ix(v))]; }
    Vec3 top_rate(mesh::VertexId v) const { return m_xdot.values[slot(mesh::ix(v))]; }
    /// The amplitude of through-thickness mode k ∈ [2, p] at a vertex (m; 0 at rest).
    Vec3 mode_amplitude(mesh::VertexId v, int k) const { return m_x.values[slot(mesh::ix(v), k - 1)]; }
    Vec3 bottom_position(mesh::VertexId v) const;
    /// The shortest vector from one node's bottom to another's now, over periodic images: two
    /// neighbours on either side of a seam lie a period apart in their own positions.
    Vec3 bottom_step(mesh::VertexId from, mesh::VertexId to) const;
    /// Current node positions of an element (periodic shifts applied).
    wedge::Nodes current_nodes(mesh::FaceId f) const;
    /// Reference shape Q_e at the current time.
    wedge::Nodes reference_nodes(mesh::FaceId f) const;

    // === Stress (§5.6.1)
    TopStress top_stress(mesh::FaceId f) const;
    /// dσ/dt at the top Gauss points, from the current rate solution.
    TopStress top_stress_rate(mesh::FaceId f) const;
    /// Largest top principal stress over threshold (> 1 means a fracture candidate).
    double stress_ratio(mesh::FaceId f) const;
    /// ½ Σ qᵀ K q over the alive elements (J).
    double strain_energy() const;
    /// The same over some elements only (the dead ones count zero).
    double strain_energy(const std::vector<mesh::FaceId>& faces) const;

    // === Topology (§5.6.3–5.6.4)
    /// Removes an element: zeroes its blocks and re-adds the remaining elements' share of
    /// them (Alg. 7: exact and local). Top nodes left without elements stay where they are.
    void remove_element(mesh::FaceId f);
    /// Rivara bisection of `f` (Alg. 9); children inherit alive status, get fresh material
    /// averages (§5.9) and stiffness; new top nodes start at the midpoints. Returns every face
    /// created or changed.
    std::vector<mesh::FaceId> subdivide(mesh::FaceId f);
    /// Between these two, topology edits update the mesh, materials and element stiffness at
    /// once but K's rows and the residuals only at the end, for every vertex touched: a run of
    /// bisections (a tip sub-model, §5.7.8) rebuilds each row once instead of once per edit.
    /// K and the residuals are the same as without: each row is rebuilt from scratch from its
    /// final elements, and a block off the diagonal sums at most the two faces on its edge.
    /// Nothing may read K or a residual in between.
    void defer_updates();
    void flush_updates();
    /// Splits edge `edge` of `f` (and the face across it) at parameter t ∈ (0, 1) from the
    /// edge's first corner: a new vertex on the background surface, its top node interpolated
    /// between the edge's top nodes. Returns the new vertex and every face created or changed.
    std::pair<mesh::VertexId, std::vector<mesh::FaceId>> split_edge(mesh::FaceId f, int edge, double t);
    /// Opens cracks along edges (one side (face, edge) of each): vertices on a crack are
    /// duplicated so the faces on either side no longer share the edge (mesh::cut_edges, local);
    /// copies inherit position, top node and rate. Returns (copy, origin) per new vertex.
    std::vector<std::pair<mesh::VertexId, mesh::VertexId>> cut(const std::vector<std::pair<mesh::FaceId, int>>& edges);
    /// Moves vertex v's background point to `to` (same topology; periodic offsets of its faces
    /// follow), its top node and rate to the given values; rebuilds its elements. This is the
    /// thesis' edge collapse onto a fracture plane (§5.7.5) seen from the surviving vertex.
    void move_vertex(mesh::VertexId v, const mesh::NewVertex& to, const Vec3& top, const Vec3& rate);
    /// Flips edge `edge` of f with the face across it (mesh::flip_edge) and rebuilds both
    /// elements and their rows of K. Returns the other face, or NO_FACE on a border edge.
    mesh::FaceId flip_edge(mesh::FaceId f, int edge);
    /// The point at parameter t of a face's edge (as split_edge would place it) and its
    /// interpolated top node and rate, in the point's canonical frame.
    mesh::NewVertex edge_point(mesh::FaceId f, int edge, double t, Vec3* top = nullptr, Vec3* rate = nullptr) const;
    /// The same for a point inside a face, given by barycentric coordinates (corner order).
    mesh::NewVertex face_point(mesh::FaceId f, const Vec3& bary, Vec3* top = nullptr, Vec3* rate = nullptr) const;
    /// Starts a trial: every change from here on (topology, stiffness, positions) can be undone
    /// by rollback() — fem-split's Griffith test of a tip extension (Alg. 11) — at the cost of
    /// copying the per-vertex state and recording the elements and matrix rows that change.
    /// A stiffness-only trial (the tip sub-model's, §5.7.8, which reads only displacements and
    /// stresses) gives the elements it creates no strength: their threshold stress and
    /// toughness are the fields' lower bounds instead of face averages of the variation.
    void begin_trial(bool stiffness_only = false);
    /// Undoes everything since begin_trial().
    void rollback();
    /// Keeps the changes since begin_trial().
    void commit();
    // === Edge damage (graph-fem; digest §1.6–1.7, §7)
    /// Broken-edge bits of an element (bit k: edge k, corner k → k + 1); 0 unless graph-fem
    /// broke them. Topology edits (split, cut, subdivide) start their elements intact.
    unsigned broken_edges(mesh::FaceId f) const { return m_broken[mesh::ix(f)]; }
    /// Breaks graph edges, one side (face, edge) each: the bit is set on both faces sharing the
    /// edge, their stiffness is rebuilt with the edge-damaged material (wedge::edge_projector)
    /// and the rows of K around them are updated in place: the unknowns and the nonzeros stay
    /// as they are. Undone by rollback().
    void break_edges(const std::vector<std::pair<mesh::FaceId, int>>& sides);
    /// The element's material matrix: D, or ΠᵀDΠ with broken edges (stiffness and stress use it).
    wedge::Mat6 element_elasticity(mesh::FaceId f) const;

    /// Longest edge of the element's bottom triangle at t = 0 (m).
    double element_size(mesh::FaceId f) const;

    /// The assembled K_tt (3pV × 3pV, full symmetric storage) for tests and benchmarks.
    const Eigen::SparseMatrix<double, Eigen::RowMajor>& stiffness() const { return m_K; }
    /// Rebuilds K from scratch from the element stiffnesses (tests compare it with the
    /// locally updated one).
    Eigen::SparseMatrix<double, Eigen::RowMajor> assemble_from_scratch() const;

private:
    struct Solver;

    /// An unknown field over the top nodes with its tracked residual b − K·values.
    enum class Unknown { Position, Rate };
    struct Field {
        std::vector<Vec3> values; ///< per slot (p per vertex): top node, then mode amplitudes
        Eigen::VectorXd residual;
        bool residual_valid = false;
        double load_norm = -1; ///< scale of the tolerance (‖b‖ with the top nodes at rest)
    };
    Field& field(Unknown u) { return u == Unknown::Position ? m_x : m_xdot; }

    void init_vertex(std::size_t v);
    /// Layer thickness from the field at a surface point (domain coordinates on periodic surfaces).
    double thickness_at(const Vec3& p, const Vec2& domain) const;
    /// Where a top node sits, now, above the background point p0 (normal n0, thickness h, at
    /// t = 0) in a layer that follows the background without strain: (1 − s̄)·h along the grown
    /// normal. Topology changes interpolate displacements from it (point_in_face).
    Vec3 rest_top(const Vec3& p0, const Vec3& n0, double h) const;
    /// Its time derivative.
    Vec3 rest_top_rate(const Vec3& p0, const Vec3& n0, double h) const;
    void init_element(std::size_t f);
    void build_element_stiffness(std::size_t f);
    void assemble();
    void rebuild_incidence();
    /// Incidence and alive degrees after `faces` changed; `vertices` lists every vertex that
    /// may have lost a face.
    void refresh_incidence(const std::vector<mesh::FaceId>& faces, const std::vector<std::size_t>& vertices);
    /// Rebuilds the rows and columns of K at these vertices from their elements.
    void reassemble_around(const std::vector<std::size_t>& vertices);
    Vec3 shift(const Vec2i& offset, double t) const;
    Vec3 shift_rate(const Vec2i& offset) const;
    wedge::Nodes reference_nodes_at(std::size_t f, double s_top, double s_bot) const;
    /// The element's DOFs q = P − Q (9 + 9p: bottom, top, then the modes' amplitudes).
    VecX displacement(std::size_t f) const;
    VecX displacement_rate(std::size_t f) const;
    /// σ at the top Gauss points of element f for nodal displacements q (or their rates); on
    /// the top face itself (ζ = 1) at the same points with modes (p > 1).
    TopStress top_stress_of(std::size_t f, const VecX& q) const;
    /// K_e,free·q (positions) or K_e,free·q̇ (rates): the element's forces on its free DOFs
    /// (9p: slot-major, [slot j][corner k][xyz]).
    VecX element_force(std::size_t f, Unknown u) const;
    /// The element's full K_e ((9 + 9p)²) on the reference shape the stiffness was built with.
    MatX element_stiffness(std::size_t f) const;
    /// ½ qᵀ K_e q of one element (J).
    double element_energy(std::size_t f) const;
    /// Slot j of vertex v (j = 0: its top node; j ≥ 1: mode j + 1).
    std::size_t slot(std::size_t v, int j = 0) const {
        return static_cast<std::size_t>(m_order) * v + static_cast<std::size_t>(j);
    }
    /// Rows of K_e for the element's free DOFs, 9p × (9 + 9p), stored flat for every element.
    std::size_t k_stride() const { return static_cast<std::size_t>(9 * m_order * wedge::element_dofs(m_order)); }
    Eigen::Map<MatX> k_free(std::size_t f) {
        return {m_k_free.data() + f * k_stride(), 9 * m_order, wedge::element_dofs(m_order)};
    }
    Eigen::Map<const MatX> k_free(std::size_t f) const {
        return {m_k_free.data() + f * k_stride(), 9 * m_order, wedge::element_dofs(m_order)};
    }
    /// The 3 × 3 block of K_e between free DOF slots (j_a, corner a) and (j_b, corner b).
    Mat3 k_block(std::size_t f, int j_a, std::size_t a, int j_b, std::size_t b) const {
        return k_free(f).block<3, 3>(9 * j_a + 3 * static_cast<Eigen::Index>(a),
                                     9 + 9 * j_b + 3 * static_cast<Eigen::Index>(b));
    }
    /// r −= the element's free forces, at every slot of its corners (only those marked).
    void subtract_element_force(std::size_t f, const VecX& force, Eigen::VectorXd& r,
                                const std::vector<char>* only = nullptr) const;
    /// |r|² over a vertex's slots: the force left on it (N², generalised forces for the modes).
    double vertex_force_squared(const Field& fd, std::size_t v) const {
        const auto at = static_cast<Eigen::Index>(3 * slot(v));
        return m_order == 1 ? fd.residual.segment<3>(at).squaredNorm()
                            : fd.residual.segment(at, 3 * m_order).squaredNorm();
    }
    Eigen::VectorXd full_residual(Unknown u) const;
    void ensure_residual(Unknown u);
    /// Recomputes the residual at the given vertices from their elements.
    void recompute_residual_at(Unknown u, const std::vector<std::size_t>& vertices);
    double load_norm(Unknown u);
    double max_residual(Unknown u);
    SolveStats solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x, double abs_tolerance);
    SolveStats relax_field(Unknown u);
    SolveStats relax_field_local(Unknown u, const std::vector<std::size_t>& seeds, double& radius,
                                 const LocalRelaxOptions& options);
    // The steps of one round of relax_field_local (§5.8): the set, its solve, the update.
    /// The breadth-first ball of `radius` hops along intact elements from `sources` (marks hop[]).
    std::vector<std::size_t> local_ball(const std::vector<std::size_t>& sources, double radius);
    /// Δ solving K_SS Δ = r_S with the rest held (§5.5's elimination; marks local_index[]), and r_S.
    Eigen::VectorXd solve_local_set(const Field& fd, const std::vector<std::size_t>& set, Eigen::VectorXd& rhs);
    /// x_S += Δ, r −= K[:, S] Δ; the nodes outside the set that this pushed a force onto.
    std::vector<std::size_t> apply_local_step(Field& fd, const std::vector<std::size_t>& set,
                                              const Eigen::VectorXd& dx);
    /// K's block between slots a and b.
    void set_block(std::size_t a, std::size_t b, const Mat3& block);
    /// A block of K between two slots, summed over the faces their vertices share.
    struct StiffnessBlock {
        std::size_t a, b;
        Mat3 K;
    };
    /// The blocks of these vertices' rows from their current elements (reassemble_around).
    std::vector<StiffnessBlock> stiffness_blocks(const std::vector<std::size_t>& vertices) const;
    /// Room in K's rows for the blocks it does not hold yet, made in one move.
    void reserve_stiffness_room(const std::vector<StiffnessBlock>& blocks);
    /// Appends a new vertex's slots to both fields (and zero rows to valid residuals).
    void push_vertex_slots();
    /// After a local topology or shape change: the rows of K of these vertices (sorted,
    /// unique) and the tracked residuals at them.
    void update_around(const std::vector<std::size_t>& vertices);
    /// Adds rows and columns up to n (uncompressed, with room in every row).
    void grow_rows(Eigen::Index n);
    void invalidate_residuals();

    mesh::SurfaceMesh m_mesh;
    mesh::Surface m_surface;
    GrowthField m_growth;
    ShrinkageOptions m_shrinkage;
    LayerFields m_fields;
    FemOptions m_options;

    double m_time = 0;
    double m_stiffness_s_top = 0, m_stiffness_s_bot = 0; // shrinkage at the last stiffness build
    bool m_stiffness_dirty_for_x = true;
    std::size_t m_stiffness_builds = 0;
    /// Throws InputError (inverted at the start: the layer's shape) or NumericError (later).
    [[noreturn]] void refuse_inverted(std::size_t f, const wedge::Nodes& q, double det) const;
    double m_residual_floor = 0;
    double m_force_scale = 1; // threshold × thickness × edge length: a nodal force that cracks

    // per vertex
    std::vector<Vec3> m_normal;      // surface normal at t = 0
    std::vector<double> m_thickness; // layer thickness
    Field m_x;                       // current canonical top positions
    Field m_xdot;                    // their rate ẋ
    std::vector<double> m_last_update;
    std::vector<std::size_t> m_updated;
    std::vector<int> m_scratch_hop, m_scratch_index;
    std::vector<char> m_scratch_touched;
    std::vector<Vec3> m_scratch_pushed;
    std::vector<std::vector<std::uint32_t>> m_incident; // faces around each vertex
    std::vector<int> m_alive_degree;                    // alive faces around each vertex

    // per element
    std::vector<char> m_alive;
    std::size_t m_num_alive = 0;
    std::vector<ElementMaterial> m_material;
    std::vector<std::uint8_t> m_broken; // graph-fem's broken-edge bits
    int m_order = 1;                    // through-thickness order: slots per vertex
    std::vector<double> m_k_free;       // rows of K_e for the free DOFs, k_stride() per element

    Eigen::SparseMatrix<double, Eigen::RowMajor> m_K;
    /// Owns the solver; a copy starts with a fresh one of the same kind, set up on first use.
    struct SolverSlot {
        std::unique_ptr<Solver> solver;
        explicit SolverSlot(SolverKind kind);
        SolverSlot(const SolverSlot& other);
        SolverSlot& operator=(const SolverSlot& other);
        SolverSlot(SolverSlot&&) noexcept;
        SolverSlot& operator=(SolverSlot&&) noexcept;
        ~SolverSlot();
        Solver* operator->() const { return solver.get(); }
    };
    SolverSlot m_solver;
    /// What a trial must restore; copies of the model start without one.
    struct Trial;
    struct TrialSlot {
        std::unique_ptr<Trial> trial;
        bool active = false;
        bool stiffness_only = false;
        TrialSlot();
        TrialSlot(const TrialSlot&);
        TrialSlot& operator=(const TrialSlot&);
        TrialSlot(TrialSlot&&) noexcept;
        TrialSlot& operator=(TrialSlot&&) noexcept;
        ~TrialSlot();
    };
    TrialSlot m_trial;
    bool m_defer_updates = false;
    std::vector<std::size_t> m_deferred_vertices;
    void record_element(std::size_t f);
    void record_row(Eigen::Index row);
    void record_incidence(std::size_t v);
    /// A vertex a topology change is making: its top node and rate, normal and thickness, and
    /// its modes' amplitudes and rates (interpolated like the displacements).
    struct NewNode {
        Vec3 top = Vec3::Zero(), rate = Vec3::Zero(), normal = Vec3::Zero();
        double thickness = 0;
        std::array<Vec3, wedge::MAX_THICKNESS_ORDER - 1> mode{Vec3::Zero(), Vec3::Zero()};
        std::array<Vec3, wedge::MAX_THICKNESS_ORDER - 1> mode_rate{Vec3::Zero(), Vec3::Zero()};
    };
    /// Adopts the vertices and faces that mesh-level splits created (subdivide, split_edge);
    /// `nodes` holds each new vertex's top node and rate, in split order.
    std::vector<mesh::FaceId> adopt_splits(const std::vector<mesh::EdgeSplit>& splits,
                                           const std::vector<NewNode>& nodes);
    /// The new vertex at parameter t of a face's edge, and its interpolated node. `pending`:
    /// vertices made earlier in the same change and not adopted yet (ids from num adopted on).
    mesh::NewVertex point_on_edge(const mesh::SurfaceMesh& m, mesh::FaceId face, int edge, double t, NewNode& node,
                                  const std::vector<NewNode>* pending = nullptr) const;
    mesh::NewVertex point_in_face(const mesh::SurfaceMesh& m, mesh::FaceId face, const Vec3& bary, NewNode& node,
                                  const std::vector<NewNode>* pending = nullptr) const;
};

} // namespace crackle::sim
