#pragma once
/// @file The baking tests' standard crack pattern: a 0.2 m plate shrinking 0.03 % and cracked by
/// element removal (a few dozen pieces in a second).

#include "fracture/fem_remove/fem_remove.hpp"
#include "support/fem_fixture.hpp"

namespace crackle::test {

inline fracture::CrackPattern cracked_plate(std::size_t elements, std::uint64_t fracture_seed) {
    LayerSpec spec;
    spec.size = Vec2(0.2, 0.2);
    spec.elements = elements;
    spec.shrinkage = {3e-4, 3e-4};
    Layer layer(spec);
    Rng rng(fracture_seed, RngStream::Fracture);
    return fracture::run_fem_remove(*layer.model, fracture::FractureOptions{}, rng);
}

} // namespace crackle::test
