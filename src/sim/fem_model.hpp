#pragma once
/// @file The wedge-FEM layer (Federl 2002, §5.3–5.6): one 6-node wedge per surface triangle,
/// bottom nodes pinned to the growing background, top nodes free. Assembles the global
/// stiffness of the free (top) nodes, solves the equilibrium, evaluates stresses, and
/// changes topology by element removal (Alg. 7) and Rivara bisection (Alg. 9).
///
/// Unknowns are the canonical top-node positions x_v, three per surface vertex. The bottom
/// nodes are eliminated (digest §3.6, "symmetry pitfall"), so the system K_tt·x = b stays
/// symmetric positive definite. On periodic surfaces a face corner with lattice offset o uses
/// x_v + s(o, t), where the period shift s grows with the background; nodes across the seam
/// are the same unknowns.
///
/// With the stiffness fixed, the loads are affine in time (linear growth, Eq. 3.4; linear
/// shrinkage, §3.3.2), so the equilibrium is too: x(t) = x(t₀) + (t − t₀)·ẋ. The fracture
/// loop uses that to find the time of the next fracture (Alg. 5) without re-solving at every
/// trial time. Shrinkage changes the reference shapes and so K; the stiffness is rebuilt
/// whenever the shrinkage scale has moved by more than `stiffness_refresh` since the last
/// build (digest §1.10 [I]).

#include <array>
#include <memory>
#include <vector>

#include <Eigen/SparseCore>

#include "mesh/surface.hpp"
#include "mesh/surface_mesh.hpp"
#include "sim/growth_field.hpp"
#include "sim/property_field.hpp"
#include "sim/reference_shape.hpp"
#include "sim/wedge_element.hpp"

namespace crackle::sim {

enum class SolverKind {
    Cg,     ///< conjugate gradient, Jacobi preconditioned, warm-started (the thesis' choice)
    Direct  ///< sparse Cholesky (CHOLMOD supernodal), refactorized when K changes
};

struct FemOptions {
    SolverKind solver = SolverKind::Cg;
    double tolerance = 1e-9;    ///< CG: residual norm relative to the load's norm
    int max_iterations = 20000; ///< CG iterations before a NumericError
    double stiffness_refresh = 0.01;  ///< rebuild K when the shrinkage scale moved this much
};

/// The layer's physical fields (§5.9), sampled per element (E, threshold, toughness) and per
/// vertex (thickness).
struct LayerFields {
    const PropertyField* thickness = nullptr;
    const PropertyField* young_modulus = nullptr;
    const PropertyField* threshold_stress = nullptr;
    const PropertyField* toughness = nullptr;
    double poisson_ratio = 0.3;
};

struct ElementMaterial {
    double young_modulus = 0;
    double threshold_stress = 0;
    double toughness = 0;
};

struct SolveStats {
    int iterations = 0;
    double residual = 0;  ///< final residual relative to the load
    double seconds = 0;
};

/// σ at the three Gauss points nearest the top face (Voigt order, Pa).
using TopStress = std::array<wedge::Vec6, 3>;

class FemModel {
public:
    FemModel(mesh::SurfaceMesh mesh, const mesh::Surface& surface, const GrowthField& growth,
             const ShrinkageOptions& shrinkage, const LayerFields& fields, const FemOptions& options = {});
    ~FemModel();
    FemModel(const FemModel&) = delete;
    FemModel& operator=(const FemModel&) = delete;

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

    // === Time and equilibrium
    /// Moves the background and the reference shapes to time t. Rebuilds the stiffness when
    /// shrinkage has changed the reference shapes enough; the positions then need relax().
    void set_time(double t);
    /// The latest time up to which the current stiffness stays valid (∞ without shrinkage).
    double stiffness_horizon() const;
    /// True when the stiffness changed since the last relax() (a refresh or a topology change).
    bool stiffness_changed() const { return m_stiffness_dirty_for_x; }
    /// Solves the equilibrium at the current time, warm-started from the current positions.
    /// Throws NumericError when the solver fails (with iterations and residual).
    SolveStats relax();
    /// Solves for ẋ = ∂x/∂t at the current time with the current stiffness.
    SolveStats solve_rate();
    /// Moves the top nodes along the rate solution: x += dt·ẋ (exact while K is fixed).
    void advance_along_rate(double dt);
    /// Per-vertex size of the last relax()'s update (m).
    const std::vector<double>& last_update() const { return m_last_update; }

    // === Positions
    Vec3 top_position(mesh::VertexId v) const { return m_top[mesh::ix(v)]; }
    Vec3 bottom_position(mesh::VertexId v) const;
    /// Current node positions of an element (periodic shifts applied).
    wedge::Nodes current_nodes(mesh::FaceId f) const;
    /// Reference shape Q_e at the current time.
    wedge::Nodes reference_nodes(mesh::FaceId f) const;

    // === Stress (§5.6.1)
    TopStress top_stress(mesh::FaceId f) const;
    /// dσ/dt at the top Gauss points, from the last solve_rate().
    TopStress top_stress_rate(mesh::FaceId f) const;
    /// Largest top principal stress over threshold (> 1 means a fracture candidate).
    double stress_ratio(mesh::FaceId f) const;
    /// ½ Σ qᵀ K q over the alive elements (J).
    double strain_energy() const;

    // === Topology (§5.6.3–5.6.4)
    /// Removes an element: zeroes its blocks and re-adds the remaining elements' share of
    /// them (Alg. 7: exact and local). Top nodes left without elements stay where they are.
    void remove_element(mesh::FaceId f);
    /// Rivara bisection of `f` (Alg. 9); children inherit alive status, get fresh material
    /// averages (§5.9) and stiffness; new top nodes start at the midpoints. Returns every face
    /// created or changed.
    std::vector<mesh::FaceId> subdivide(mesh::FaceId f);
    /// Longest edge of the element's bottom triangle at t = 0 (m).
    double element_size(mesh::FaceId f) const;

    /// The assembled K_tt (3V × 3V, full symmetric storage) for tests and benchmarks.
    const Eigen::SparseMatrix<double, Eigen::RowMajor>& stiffness() const { return m_K; }
    /// Rebuilds K from scratch from the element stiffnesses (tests compare it with the
    /// locally updated one).
    Eigen::SparseMatrix<double, Eigen::RowMajor> assemble_from_scratch() const;

private:
    struct Solver;

    void init_vertex(std::size_t v);
    void init_element(std::size_t f);
    void build_element_stiffness(std::size_t f);
    void assemble();
    void rebuild_incidence();
    Vec3 shift(const Vec2i& offset, double t) const;
    Vec3 shift_rate(const Vec2i& offset) const;
    wedge::Nodes reference_nodes_at(std::size_t f, double s_top, double s_bot) const;
    Eigen::VectorXd residual() const;
    Eigen::VectorXd load_rate() const;
    double load_norm() const;
    SolveStats solve(const Eigen::VectorXd& rhs, Eigen::VectorXd& x, double abs_tolerance);
    wedge::Vec18 displacement(std::size_t f) const;
    void set_block(std::size_t a, std::size_t b, const Mat3& block);

    mesh::SurfaceMesh m_mesh;
    mesh::Surface m_surface;
    GrowthField m_growth;
    ShrinkageOptions m_shrinkage;
    LayerFields m_fields;
    FemOptions m_options;

    double m_time = 0;
    double m_stiffness_s_top = 0, m_stiffness_s_bot = 0;  // shrinkage at the last stiffness build
    bool m_stiffness_dirty_for_x = true;

    // per vertex
    std::vector<Vec3> m_normal;      // surface normal at t = 0
    std::vector<double> m_thickness; // layer thickness
    std::vector<Vec3> m_top;         // current canonical top position
    std::vector<Vec3> m_rate;        // ẋ
    std::vector<double> m_last_update;
    std::vector<std::vector<std::uint32_t>> m_incident;  // faces around each vertex
    std::vector<int> m_alive_degree;                     // alive faces around each vertex

    // per element
    std::vector<char> m_alive;
    std::size_t m_num_alive = 0;
    std::vector<ElementMaterial> m_material;
    std::vector<Eigen::Matrix<double, 9, 18>> m_k_top;  // rows of K_e for the top nodes

    Eigen::SparseMatrix<double, Eigen::RowMajor> m_K;
    std::unique_ptr<Solver> m_solver;
};

}  // namespace crackle::sim
