#pragma once
/// @file Fracture by element splitting (Federl 2002, §5.7; digest §3.9), the thesis' preferred
/// method: a crack starts at the node with the highest in-surface principal stress over
/// threshold and cuts the elements around it along the plane normal to that stress, through
/// the whole layer; its two tips then extend, first in first out, for as long as Griffith's
/// energy balance allows (a rejected extension is rolled back and leaves an exclusion zone);
/// cuts that would leave slivers move the nearby vertex onto the plane instead (edge
/// collapse); the equilibrium is re-solved locally after every change (§5.8); between events
/// time jumps to the next fracture (Alg. 5).

#include "core/rng.hpp"
#include "core/settings.hpp"
#include "fracture/crack_pattern.hpp"
#include "fracture/run.hpp"
#include "sim/fem_model.hpp"

#include <vector>

namespace crackle::fracture {

struct SplitOptions {
    /// A cut closer than this share of an edge to one of its vertices goes through the vertex.
    double snap_fraction = 0.2;
    /// Smallest triangle angle a cut may leave (degrees); below it the cut goes through the
    /// nearer vertex, moved onto the fracture plane when it is free to move (§5.7.5).
    double min_angle_deg = 12.0;
    /// Radius of the zone around an arrested tip where no new fracture may start (m); < 0:
    /// the mean layer thickness (Ch. 6 gives no value).
    double exclusion_radius = -1;
    /// Griffith's test at tips (Alg. 11); false: tips always extend while stress > threshold.
    bool griffith = true;
    /// Angle-based smoothing (§5.7.9) of the free nodes within this distance of every new tip
    /// (m); < 0: 1.5 × the mean starting edge length; 0: off (the default: on the mud preset
    /// it cost 35 % more time and did not raise the worst angle, which the cuts set).
    double smoothing_radius = 0;
    /// Adaptive refinement by the von Mises indicator (§5.7.7, Alg. 13), once per time step:
    /// the elements around a node are subdivided (down to FractureOptions::min_element_size)
    /// when the spread of the von Mises stresses they report at it exceeds this share of the
    /// largest principal stress. 0: off.
    double vm_threshold = 0;
    /// The crack direction at a tip from a temporary local sub-model refined this many times
    /// (each halving the element size) around it (§5.7.8); nothing of it stays. 0: off.
    int tip_submodel_levels = 0;
    /// The stress a new fracture starts from, averaged over this radius along the surface (m;
    /// fem_split/nonlocal.hpp): 0 = the thesis' nodal stress (§5.7.1), which sees sharper peaks on
    /// finer meshes. With `initiation_fraction` > 0 the radius is that share of the local layer
    /// thickness instead (material.initiation_length = "auto": 1).
    double initiation_length = 0;
    double initiation_fraction = 0;
    /// Check the mesh invariants (check_split_invariants) after every topology change and
    /// throw InvariantError on the first violation: O(mesh) per event, for tests and debugging.
    bool check_invariants = false;
    bool operator==(const SplitOptions&) const = default; ///< every field: the options test compares whole structs
};

/// What element splitting did.
struct SplitStats {
    /// New fractures, accepted and rejected (Griffith) tip extensions, cuts moved onto a vertex
    /// by edge collapse, cuts snapped to a vertex that could not move.
    std::size_t splits = 0, extensions = 0, arrests = 0, collapses = 0, snaps = 0;
    std::size_t subdivisions = 0;   ///< bisections around tips and new cracks (§5.7.6, §5.7.7)
    std::size_t smoothed = 0;       ///< node moves by angle-based smoothing (§5.7.9)
    std::size_t vm_refinements = 0; ///< bisections by the von Mises indicator (§5.7.7)
    std::size_t submodels = 0;      ///< temporary tip sub-models (§5.7.8)
    std::size_t flips = 0;          ///< edge flips of slivers near cuts (§5.7.5)
    /// Where and when each crack tip stopped (Griffith, Alg. 11), kind "arrest", position the
    /// tip's reference point, ratio its stress over threshold then.
    std::vector<Event> arrests_at;
};

/// The options from the method's [simulation] keys.
SplitOptions split_options(const Settings& settings);

/// The invariants a fem-split model keeps through every topology change: the surface mesh is
/// valid (conforming, manifold, consistently oriented, adjacency symmetric), every alive
/// element has a positive reference volume and a positively oriented bottom triangle, and
/// vertex→face incidence matches the faces. Returns "" when they hold, else the first problem.
std::string check_split_invariants(const sim::FemModel& model);

/// Runs the splitting model from the model's current time to `options.duration`; ties between
/// equally stressed nodes are broken with `rng`. Returns the pattern (cracks are open mesh
/// edges; every lip is a CrackEdge, its depth the layer thickness).
CrackPattern run_fem_split(sim::FemModel& model, const FractureOptions& options, const SplitOptions& split, Rng& rng,
                           RunStats* stats = nullptr, SplitStats* split_stats = nullptr);

/// In-surface stress at the top of a node: the average over its elements of each one's stress
/// at its top Gauss point nearest the node (§5.7.1), projected on the current tangent plane.
struct NodalStress {
    double ratio = 0;                ///< largest in-surface principal stress / threshold
    Vec3 crack = Vec3::Zero();       ///< unit crack direction at t = 0 (normal to that stress)
    double threshold = 0;            ///< mean threshold of the node's elements (Pa)
    double toughness = 0, young = 0; ///< means of the node's elements
};
NodalStress nodal_stress(const sim::FemModel& model, std::size_t vertex);

/// The crack tips of a model: vertices on exactly one crack edge pair (the end of a slit).
std::vector<std::size_t> crack_tips(const sim::FemModel& model);

} // namespace crackle::fracture
