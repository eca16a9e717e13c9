#pragma once
/// @file Runs for the thesis-claim tests (tests/unit/claims): fem-split on a layer whose
/// thickness and threshold may vary too (LayerSpec varies only Young's modulus), §5.9.

#include "support/fracture_fixture.hpp"

namespace crackle::test {

/// Perturbations of the layer's fields (§5.9, Fig. 5.31); None leaves a field as the spec has it.
struct FieldVariations {
    sim::VariationOptions thickness, threshold;
};

/// A layer whose thickness and threshold fields carry `variations` (same streams as Layer).
inline std::unique_ptr<Layer> varied_layer(const LayerSpec& spec, const FieldVariations& variations) {
    auto layer = std::make_unique<Layer>(spec);
    const LayerSpec& s = layer->spec;
    layer->thickness = sim::PropertyField(s.thickness, s.thickness_end < 0 ? s.thickness : s.thickness_end,
                                          variations.thickness, layer->surface, s.seed, 1);
    layer->threshold = sim::PropertyField(s.threshold, variations.threshold, layer->surface, s.seed, 3);
    sim::LayerFields fields{&layer->thickness, &layer->young, &layer->threshold, &layer->toughness, s.poisson};
    layer->model = std::make_unique<sim::FemModel>(make_mesh(layer->surface, s.elements, s.seed), layer->surface,
                                                   sim::GrowthField(s.growth, s.kind), s.shrinkage, fields, s.fem);
    return layer;
}

/// run_split on a varied layer.
inline FractureRun run_split_varied(const LayerSpec& spec, const FieldVariations& variations, double duration = 1.0,
                                    fracture::SplitOptions split = {}, fracture::FractureOptions options = {}) {
    auto layer = varied_layer(spec, variations);
    options.duration = duration;
    split.check_invariants = true;
    Rng rng(spec.seed, RngStream::Fracture);
    FractureRun r;
    r.pattern = fracture::run_fem_split(*layer->model, options, split, rng, &r.run);
    r.stats = fracture::pattern_statistics(r.pattern);
    return r;
}

} // namespace crackle::test
