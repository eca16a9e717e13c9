#pragma once
/// @file Fracture by element removal (Federl 2002, §5.6): remove the element with the highest
/// stress/threshold ratio, re-relax, repeat; when none is over threshold, jump to the time of
/// the next fracture (Alg. 5); subdivide coarse elements instead of removing them (Alg. 8).

#include "core/rng.hpp"
#include "fracture/crack_pattern.hpp"
#include "fracture/run.hpp"
#include "sim/fem_model.hpp"

namespace crackle::fracture {

/// What element removal did.
struct RemovalStats {
    std::size_t removals = 0;     ///< elements removed (§5.6.3)
    std::size_t subdivisions = 0; ///< candidates too coarse to remove, bisected instead (Alg. 8)
};

/// Runs the element-removal model from the model's current time to `options.duration`.
/// Ties between equally stressed candidates are broken with `rng`.
CrackPattern run_fem_remove(sim::FemModel& model, const FractureOptions& options, Rng& rng, RunStats* stats = nullptr,
                            RemovalStats* removal = nullptr);

} // namespace crackle::fracture
