#pragma once
/// @file A small FEM layer for tests: surface, fields and model in one object.

#include "sim/fem_model.hpp"
#include "support/mesh_fixtures.hpp"

#include <memory>

namespace crackle::test {

struct LayerSpec {
    mesh::SurfaceKind kind = mesh::SurfaceKind::Plane;
    Vec2 size = Vec2(0.2, 0.2);
    std::size_t elements = 300;
    double young = 1e9, poisson = 0.3, threshold = 1e5, toughness = 100, thickness = 0.01;
    double thickness_end = -1; ///< < 0: uniform; else thickness runs linearly along v to this
    sim::VariationOptions thickness_variation, threshold_variation;
    sim::GrowthOptions growth = {sim::GrowthKind::None, 0.0, 0.0, 0.0};
    sim::ShrinkageOptions shrinkage;
    sim::VariationOptions young_variation;
    sim::FemOptions fem;
    std::uint64_t seed = 1;
};

struct Layer {
    explicit Layer(const LayerSpec& s)
        : spec(s), surface(make_surface(s.kind, s.size.x(), s.size.y())),
          thickness(s.thickness, s.thickness_end < 0 ? s.thickness : s.thickness_end, s.thickness_variation, surface,
                    s.seed, 1),
          young(s.young, s.young_variation, surface, s.seed, 2),
          threshold(s.threshold, s.threshold_variation, surface, s.seed, 3),
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

} // namespace crackle::test
