#pragma once
/// @file Small fracture runs for tests.

#include "fracture/fem_remove.hpp"
#include "fracture/fem_split.hpp"
#include "fracture/statistics.hpp"
#include "support/fem_fixture.hpp"

namespace crackle::test {

struct FractureRun {
    fracture::CrackPattern pattern;
    fracture::PatternStatistics stats;
    fracture::RunStats run;
};

inline FractureRun run_removal(const LayerSpec& spec, double duration = 1.0, double min_element_size = 0.0,
                               const sim::VariationOptions* threshold_variation = nullptr) {
    LayerSpec s = spec;
    Layer layer(s);
    if (threshold_variation) {
        // Rebuild with a varying threshold field.
        layer.threshold = sim::PropertyField(s.threshold, *threshold_variation, layer.surface, s.seed, 3);
        sim::LayerFields fields{&layer.thickness, &layer.young, &layer.threshold, &layer.toughness, s.poisson};
        layer.model = std::make_unique<sim::FemModel>(make_mesh(layer.surface, s.elements, s.seed), layer.surface,
                                                      sim::GrowthField(s.growth, s.kind), s.shrinkage, fields, s.fem);
    }
    fracture::FractureOptions o;
    o.duration = duration;
    o.min_element_size = min_element_size;
    Rng rng(s.seed, RngStream::Fracture);
    FractureRun r;
    r.pattern = fracture::run_fem_remove(*layer.model, o, rng, &r.run);
    r.stats = fracture::pattern_statistics(r.pattern);
    return r;
}

/// A fem-split run on the layer; invariants are checked after every topology change.
inline FractureRun run_split(const LayerSpec& spec, double duration = 1.0, fracture::SplitOptions split = {},
                             fracture::FractureOptions options = {}) {
    Layer layer(spec);
    options.duration = duration;
    split.check_invariants = true;
    Rng rng(spec.seed, RngStream::Fracture);
    FractureRun r;
    r.pattern = fracture::run_fem_split(*layer.model, options, split, rng, &r.run);
    r.stats = fracture::pattern_statistics(r.pattern);
    return r;
}

} // namespace crackle::test
