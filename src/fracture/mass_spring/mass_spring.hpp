#pragma once
/// @file Mass–spring fracture on growing surfaces (Federl 2002, Ch. 4; digest §2): point masses
/// joined by material springs, each anchored to the background by a zero-rest-length anchor
/// spring that slides past a maximum length. Background growth moves the anchors (Eq. 3.4),
/// shrinkage shortens the rest lengths (Eq. 3.6), a spring breaks past its threshold strain:
/// only the most over-stretched one, then the network relaxes again; time jumps to the next
/// break (as Alg. 5). Kept as the fast baseline and for its failure modes: cracks follow the
/// lattice (Fig. 4.5), and on a random lattice the pattern depends on resolution (Fig. 4.9).

#include "core/rng.hpp"
#include "core/settings.hpp"
#include "fracture/crack_pattern.hpp"
#include "fracture/run.hpp"
#include "mesh/sampling.hpp"
#include "mesh/surface.hpp"
#include "mesh/surface_mesh.hpp"
#include "sim/growth_field.hpp"
#include "sim/layer_fields.hpp"
#include "sim/reference_shape.hpp"

#include <cstdint>
#include <memory>
#include <vector>

namespace crackle::fracture {

enum class Lattice {
    Random, ///< repelled points; Delaunay springs, Voronoi cells (§4.4)
    Regular ///< triangular lattice, hexagonal cells (§4.1)
};

struct MassSpringOptions {
    Lattice lattice = Lattice::Random;
    int layers = 1;                  ///< stacked material layers (§4.3); only the bottom one is anchored
    double anchor_slide = 0.5;       ///< maximum anchor length / mean spring length; 0 = never slides
    double break_jitter = 0.0;       ///< break strains perturbed uniformly by ±jitter (relative)
    double tolerance = 1e-8;         ///< Newton: largest nodal force / (k·L·ε_b) of a typical spring
    int max_newton_iterations = 100; ///< per relaxation
    bool operator==(const MassSpringOptions&) const = default; ///< every field: the options test compares whole structs
};

/// Per-run statistics particular to mass–spring.
struct MassSpringStats {
    std::size_t breaks = 0, slides = 0, newton_solves = 0, newton_iterations = 0, time_steps = 0;
    std::size_t factorizations = 0, downdates = 0; ///< of the stiffness factor
    std::vector<int> crack_depth_layers;           ///< per open crack edge: broken layers counted from the top
};

/// The spring network and its nonlinear equilibrium.
class MassSpringModel {
public:
    /// @param mesh  Delaunay triangulation of the masses (repelled points or a lattice)
    MassSpringModel(const mesh::SurfaceMesh& mesh, const mesh::Surface& surface, const sim::GrowthField& growth,
                    const sim::ShrinkageOptions& shrinkage, const sim::LayerFields& fields,
                    const MassSpringOptions& options, Rng& rng);
    ~MassSpringModel();
    MassSpringModel(const MassSpringModel&) = delete;
    MassSpringModel& operator=(const MassSpringModel&) = delete;

    struct Spring {
        std::uint32_t a = 0, b = 0;   ///< mass indices (layer · V + vertex)
        Vec2i offset = Vec2i::Zero(); ///< periodic offset of b relative to a
        int layer = 0;
        std::uint32_t face = 0; ///< a Delaunay face with this edge, and the edge's index in it
        int edge = 0;
        double k = 0;     ///< stiffness (N/m)
        double rest0 = 0; ///< rest length at t = 0 (m)
        double break_strain = 0;
        bool broken = false;
    };

    // === State
    double time() const { return m_time; }
    const std::vector<Spring>& springs() const { return m_springs; }
    std::size_t num_vertices() const { return m_mesh.num_vertices(); }
    int layers() const { return m_options.layers; }
    const mesh::SurfaceMesh& mesh() const { return m_mesh; }
    const mesh::Surface& surface() const { return m_surface; }
    const sim::GrowthField& growth() const { return m_growth; }
    Vec3 position(std::size_t mass) const { return m_x[mass]; }
    double layer_thickness() const { return m_layer_thickness; }
    double vertex_thickness(std::size_t v) const { return m_thickness[v]; }
    double young_modulus(std::size_t v) const { return m_young[v]; }
    double poisson_ratio() const { return m_poisson; }

    // === Mechanics
    void set_time(double t);
    /// What the loading path leaves behind: positions and slid anchors (sliding is plastic, so
    /// it depends on the path). The time search of run_mass_spring probes later times and
    /// comes back to the last state below the next break before probing an earlier one.
    struct State {
        double time = 0;
        std::vector<Vec3> x, anchor0;
    };
    State state() const { return {m_time, m_x, m_anchor0}; }
    void restore(const State& s);
    /// Newton's method with a line search to the nonlinear equilibrium; slides anchors that
    /// are over-stretched and relaxes again. Throws NumericError (iterations, residual, time)
    /// when it fails to converge or meets NaN.
    void relax(MassSpringStats* stats = nullptr);
    /// Strain over break strain of an intact spring (> 1 breaks).
    double ratio(std::size_t s) const;
    /// d(ratio)/dt at the current equilibrium, from the tangent-linear rate of the masses.
    std::vector<double> ratio_rates();
    /// Breaks spring s (and downdates the stiffness factor).
    void break_spring(std::size_t s);
    /// Largest nodal force of the current configuration (N).
    double max_force() const;
    /// The force scale of the tolerance: k·L·ε_b of a typical spring (N).
    double force_scale() const { return m_force_scale; }
    /// Factorizations and rank-1 downdates of the stiffness factor so far.
    std::size_t factorizations() const;
    std::size_t downdates() const;

private:
    struct Solver;
    double rest_length(const Spring& s, double t) const;
    Vec3 shift(const Vec2i& offset, double t) const;
    Vec3 anchor(std::size_t v, double t) const;
    /// Everything the loads depend on at time t (anchors, rest lengths, periodic shifts),
    /// cached for the latest t.
    struct Loads {
        double t = 0;
        bool valid = false;
        std::vector<Vec3> anchor, shift, layer_rest;
        std::vector<double> rest;
    };
    const Loads& loads(double t) const;
    /// Energy, gradient and (projected, PSD) Hessian at positions x and time t.
    double energy(const std::vector<Vec3>& x, double t) const;
    void gradient(const std::vector<Vec3>& x, double t, Eigen::VectorXd& g) const;
    /// Factors the material stiffness M at the current configuration.
    void factorize();
    Eigen::VectorXd solve_stiffness(const Eigen::VectorXd& b);
    /// out = H v with H the projected Hessian at the current positions.
    void hessian_times(const Eigen::VectorXd& v, double t, Eigen::VectorXd& out) const;
    /// Slides the anchors stretched past the allowed length by more than `force_tolerance` can
    /// tell (§4.1); true if any moved.
    bool slide_anchors(double force_tolerance);

    mesh::SurfaceMesh m_mesh;
    mesh::Surface m_surface;
    sim::GrowthField m_growth;
    sim::ShrinkageOptions m_shrinkage;
    MassSpringOptions m_options;
    double m_poisson = 0.3;
    double m_time = 0;
    double m_layer_thickness = 0;
    double m_force_scale = 1;
    double m_mean_spring = 1;

    std::vector<double> m_thickness, m_young, m_area; // per vertex
    std::vector<Vec3> m_x;                            // layers · V masses (canonical copies)
    std::vector<Vec3> m_anchor0;                      // per vertex: anchor, pulled back to t = 0
    std::vector<double> m_anchor_k, m_layer_k;        // per vertex
    std::vector<Spring> m_springs;
    std::unique_ptr<Solver> m_solver;
    mutable Loads m_loads;
};

/// Builds the model's starting mesh: repelled points or a regular lattice, triangulated.
mesh::SurfaceMesh mass_spring_mesh(const mesh::Surface& surface, std::size_t masses, Lattice lattice,
                                   const mesh::SamplingOptions& sampling, Rng& rng);

/// The model's options from its [simulation] keys (and the shared solver keys, in their
/// mass-spring meaning).
MassSpringOptions mass_spring_options(const Settings& settings);

/// Runs the mass–spring model to `options.duration`; the pattern's pieces are the masses'
/// (Voronoi) cells, split along broken top-layer springs.
CrackPattern run_mass_spring(MassSpringModel& model, const FractureOptions& options, Rng& rng, RunStats* run = nullptr,
                             MassSpringStats* stats = nullptr);

} // namespace crackle::fracture
