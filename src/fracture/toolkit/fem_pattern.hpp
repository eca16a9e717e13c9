#pragma once
/// @file The crack pattern of a wedge-FEM model's current state: the contract the FEM methods
/// (fem-remove, fem-split, graph-fem) hand to statistics, post-processing and export.

#include "fracture/crack_pattern.hpp"
#include "sim/fem_model.hpp"

#include <string>

namespace crackle::fracture {

/// Builds the crack pattern of a model's current state: mesh, deformed top nodes, removed
/// elements and their crack lips, fragments. (fem-split adds its cut edges itself.)
CrackPattern pattern_from_model(const sim::FemModel& model, const std::string& method, std::size_t elements_initial);

} // namespace crackle::fracture
