#pragma once
/// @file Runs for the thesis-claim tests (tests/unit/claims): fem-split and fem-remove on a
/// layer whose thickness and threshold may vary too (LayerSpec varies only Young's modulus), §5.9.

#include "support/fracture_fixture.hpp"

namespace crackle::test {

/// Perturbations of the layer's fields (§5.9, Fig. 5.31); None leaves a field as the spec has it.
struct FieldVariations {
    sim::VariationOptions thickness, threshold;
};

/// Layer with `variations` on its thickness and threshold fields (same seeds and streams as Layer).
struct VariedLayer {
    VariedLayer(const LayerSpec& s, const FieldVariations& variations)
        : spec(s), surface(make_surface(s.kind, s.size.x(), s.size.y())),
          thickness(s.thickness, s.thickness_end < 0 ? s.thickness : s.thickness_end, variations.thickness, surface,
                    s.seed, 1),
          young(s.young, s.young_variation, surface, s.seed, 2),
          threshold(s.threshold, variations.threshold, surface, s.seed, 3),
          toughness(s.toughness, sim::VariationOptions{}, surface, s.seed, 4) {
        sim::LayerFields fields{&thickness, &young, &threshold, &toughness, s.poisson};
        model = std::make_unique<sim::FemModel>(make_mesh(surface, s.elements, s.seed), surface,
                                                sim::GrowthField(s.growth, s.kind), s.shrinkage, fields, s.fem);
    }
    LayerSpec spec;
    mesh::Surface surface;
    sim::PropertyField thickness, young, threshold, toughness;
    std::unique_ptr<sim::FemModel> model;
};

/// run_split on a varied layer; `check_invariants` as in SplitOptions (run_split always checks).
inline FractureRun run_split_varied(const LayerSpec& spec, const FieldVariations& variations, bool check_invariants,
                                    double duration = 1.0, fracture::SplitOptions split = {},
                                    fracture::FractureOptions options = {}) {
    VariedLayer layer(spec, variations);
    options.duration = duration;
    split.check_invariants = check_invariants;
    Rng rng(spec.seed, RngStream::Fracture);
    FractureRun r;
    r.pattern = fracture::run_fem_split(*layer.model, options, split, rng, &r.run);
    r.stats = fracture::pattern_statistics(r.pattern);
    return r;
}

/// run_removal on a varied layer.
inline FractureRun run_removal_varied(const LayerSpec& spec, const FieldVariations& variations, double duration = 1.0) {
    VariedLayer layer(spec, variations);
    fracture::FractureOptions o;
    o.duration = duration;
    Rng rng(spec.seed, RngStream::Fracture);
    FractureRun r;
    r.pattern = fracture::run_fem_remove(*layer.model, o, rng, &r.run);
    r.stats = fracture::pattern_statistics(r.pattern);
    return r;
}

} // namespace crackle::test
