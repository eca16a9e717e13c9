#pragma once
/// @file Runs for the thesis-claim tests (tests/unit/claims): fem-split and fem-remove on a
/// layer whose thickness and threshold vary by a FieldVariations (§5.9).

#include "support/fracture_fixture.hpp"

namespace crackle::test {

/// Perturbations of the layer's fields (§5.9, Fig. 5.31); None leaves a field as the spec has it.
struct FieldVariations {
    sim::VariationOptions thickness, threshold;
};

/// The spec with `variations` on its thickness and threshold fields.
inline LayerSpec with_variations(LayerSpec spec, const FieldVariations& variations) {
    spec.thickness_variation = variations.thickness;
    spec.threshold_variation = variations.threshold;
    return spec;
}

/// run_split on a varied layer; `check_invariants` as in SplitOptions.
inline FractureRun run_split_varied(const LayerSpec& spec, const FieldVariations& variations, bool check_invariants,
                                    double duration = 1.0, fracture::SplitOptions split = {},
                                    fracture::FractureOptions options = {}) {
    return run_split(with_variations(spec, variations), duration, split, options, check_invariants);
}

/// run_removal on a varied layer.
inline FractureRun run_removal_varied(const LayerSpec& spec, const FieldVariations& variations, double duration = 1.0) {
    return run_removal(with_variations(spec, variations), duration);
}

} // namespace crackle::test
