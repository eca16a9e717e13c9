#pragma once
/// @file What the layer is made of (Federl 2002, §5.9): the material fields the simulation samples per element
/// and per vertex, or explicit per-face and per-vertex values in their place. Used by the wedge FEM
/// (sim::FemModel), the mass-spring model and post-processing, without needing the whole model.

#include "sim/property_field.hpp"

#include <vector>

namespace crackle::sim {

/// The material of one element (Federl 2002, §5.9): the average of the fields over its area.
struct ElementMaterial {
    double young_modulus = 0; ///< E (Pa): sets the element's stiffness; always needed
    /// The fracture material, optional: only the fracture criteria read them (stress_ratio() and the
    /// crack tests), and force_scale() with the local relaxation scaled by it. A model that is only
    /// relaxed globally, as post-processing's, leaves them 0 (force_scale() is then 0).
    double threshold_stress = 0; ///< σ₁ at which an element cracks (Pa)
    double toughness = 0;        ///< K_IC of fem-split's Griffith test (Alg. 11): G_IC = (1 − ν²)·K_IC²/E
};

/// The layer's physical fields (§5.9), sampled per element (E, threshold, toughness) and per
/// vertex (thickness). Every value comes either from a field or from an explicit list:
/// - thickness: the `thickness` field, or `vertex_thickness` (which wins when both are given);
/// - material: the three fields `young_modulus`, `threshold_stress` and `toughness`, or
///   `face_material` (which wins when given; then the three fields are optional and unread).
/// The mass-spring model reads the fields only.
struct LayerFields {
    const PropertyField* thickness = nullptr;        ///< m; optional with `vertex_thickness`
    const PropertyField* young_modulus = nullptr;    ///< Pa; optional with `face_material`
    const PropertyField* threshold_stress = nullptr; ///< Pa; optional with `face_material`
    const PropertyField* toughness = nullptr;        ///< optional with `face_material`
    double poisson_ratio = 0.3;
    /// Explicit values instead of the fields (post-processing a finished pattern): thickness per
    /// vertex (#V) and material per face (#F). Models built this way cannot be subdivided.
    const std::vector<double>* vertex_thickness = nullptr;
    const std::vector<ElementMaterial>* face_material = nullptr;
};

} // namespace crackle::sim
