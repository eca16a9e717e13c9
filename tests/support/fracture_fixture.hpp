#pragma once
/// @file Small fracture runs for tests.

#include "fracture/fem_remove/fem_remove.hpp"
#include "fracture/fem_split/fem_split.hpp"
#include "fracture/graph_fem/graph_fem.hpp"
#include "fracture/statistics.hpp"
#include "support/fem_fixture.hpp"

namespace crackle::test {

struct FractureRun {
    fracture::CrackPattern pattern;
    fracture::PatternStatistics stats;
    fracture::RunStats run;
    fracture::SplitStats split;     ///< fem-split runs
    fracture::RemovalStats removal; ///< fem-remove runs
    fracture::GraphFemStats graph;  ///< graph-fem runs
};

inline FractureRun run_removal(const LayerSpec& spec, double duration = 1.0, double min_element_size = 0.0,
                               const sim::VariationOptions* threshold_variation = nullptr) {
    LayerSpec s = spec;
    if (threshold_variation) s.threshold_variation = *threshold_variation;
    Layer layer(s);
    fracture::FractureOptions o;
    o.duration = duration;
    o.min_element_size = min_element_size;
    Rng rng(s.seed, RngStream::Fracture);
    FractureRun r;
    r.pattern = fracture::run_fem_remove(*layer.model, o, rng, &r.run, &r.removal);
    r.stats = fracture::pattern_statistics(r.pattern);
    return r;
}

/// A fem-split run on the layer; invariants are checked after every topology change unless
/// `check_invariants` is false (O(mesh) per event: slow on big runs).
inline FractureRun run_split(const LayerSpec& spec, double duration = 1.0, fracture::SplitOptions split = {},
                             fracture::FractureOptions options = {}, bool check_invariants = true) {
    Layer layer(spec);
    options.duration = duration;
    split.check_invariants = check_invariants;
    Rng rng(spec.seed, RngStream::Fracture);
    FractureRun r;
    r.pattern = fracture::run_fem_split(*layer.model, options, split, rng, &r.run, &r.split);
    r.stats = fracture::pattern_statistics(r.pattern);
    return r;
}

/// A graph-fem run on the layer.
inline FractureRun run_graph(const LayerSpec& spec, double duration = 1.0, fracture::GraphFemOptions graph = {},
                             fracture::FractureOptions options = {}) {
    Layer layer(spec);
    options.duration = duration;
    Rng rng(spec.seed, RngStream::Fracture);
    FractureRun r;
    r.pattern = fracture::run_graph_fem(*layer.model, options, graph, rng, &r.run, &r.graph);
    r.stats = fracture::pattern_statistics(r.pattern);
    return r;
}

} // namespace crackle::test
