#pragma once
/// @file Semi-random point distributions by particle repulsion with randomly perturbed radii
/// (Federl 2002, §5.2.1, Eq. 5.1, Algs. 2–3): roughly uniform triangles with random
/// orientation, neither a lattice (Fig. 5.1) nor degenerate random triangles (Fig. 5.2).

#include "core/math.hpp"
#include "core/rng.hpp"

#include <cstddef>
#include <functional>
#include <vector>

namespace crackle::mesh {

struct SamplingOptions {
    std::size_t count = 1000; ///< number of points
    /// δ of the radius perturbation r_i = r̄·(1 + δ·U[−1, 1]) (digest §3.2 [I]: 0.2–0.3).
    /// Without it the points settle into a hexagonal lattice.
    double jitter = 0.25;
    int max_iterations = 100; ///< repulsion iterations at most
    /// Stop when no point moves more than tolerance·r̄ in one iteration.
    double tolerance = 0.03;
};

/// Local spacing scale s > 0 relative to the mean spacing; point density ∝ 1/s².
/// Periodic surfaces pass domain coordinates, the sphere passes 3D points.
using SpacingField2 = std::function<double(const Vec2&)>;
using SpacingField3 = std::function<double(const Vec3&)>;

/// Repelled points on the torus [0, Lx) × [0, Ly) (plane and unrolled cylinder; wrapping
/// boundary handling of §5.2.1). Forces use the minimum-image distance, so the result has
/// no seam. `spacing` may be empty (uniform).
std::vector<Vec2> sample_periodic(const Vec2& period, const SamplingOptions& options, const SpacingField2& spacing,
                                  Rng& rng);

/// Repelled points on a sphere of the given radius: repel in 3D, project back onto the
/// sphere after every iteration (§5.2.1).
std::vector<Vec3> sample_sphere(double radius, const SamplingOptions& options, const SpacingField3& spacing, Rng& rng);

/// Uniformly random points on the torus (the degenerate baseline of Fig. 5.2).
std::vector<Vec2> sample_uniform_random(const Vec2& period, std::size_t count, Rng& rng);

/// Mean repulsion radius r̄ = ½·√(3.2·A/(n·π)) (digest §3.2: r_sum below √(3.2A/(nπ))).
double mean_repulsion_radius(double area, std::size_t count);

} // namespace crackle::mesh
