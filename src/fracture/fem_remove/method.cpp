// fem-remove as a fracture method: the wedge FEM layer, element removal (§5.6), its report.
#include "fracture/method.hpp"

#include "core/log.hpp"
#include "fracture/fem_remove/fem_remove.hpp"
#include "fracture/toolkit/fem_method.hpp"

namespace crackle::fracture {

namespace {

class FemRemove : public Method {
public:
    MethodResult run(const MethodInputs& in, StepTimes& times) const override {
        return run_on_wedge_layer(in, times, [&](sim::FemModel& model, Rng& rng, MethodResult& r) {
            // Element removal takes out whole elements: on elements much wider than the layer is
            // thick, most of the layer goes (thesis Fig. 5.11, failure mode F6).
            const double edge = mesh::mesh_quality(model.mesh()).edge_mean;
            const double h = 0.5 * (in.fields.thickness->min_value() + in.fields.thickness->max_value());
            if (edge > 1.5 * h && in.options.min_element_size == 0.0)
                log::warn("elements (", edge * 100, " cm) are much wider than the layer is thick (", h * 100,
                          " cm): element removal will take out most of the layer; raise simulation.elements or "
                          "set simulation.min_element_size");
            RemovalStats removal;
            r.pattern = run_fem_remove(model, in.options, rng, &r.run, &removal);
            r.details["removals"] = removal.removals;
            r.details["subdivisions"] = removal.subdivisions;
            r.summary = "elements     " + std::to_string(r.elements_initial) + " initial, "
                        + std::to_string(model.num_alive()) + " intact at the end (" + std::to_string(removal.removals)
                        + " removed, " + std::to_string(removal.subdivisions) + " subdivisions)";
        });
    }
};

} // namespace

MethodInfo fem_remove_method() {
    MethodInfo info;
    info.name = "fem-remove";
    info.description = "fem-remove (element removal, §5.6: wide cracks)";
    info.make = [](const Settings&) { return std::make_unique<FemRemove>(); };
    info.bytes_per_element = wedge_layer_bytes_per_element;
    info.study = {{"fem-remove", {}, 1.0, 0}};
    return info;
}

} // namespace crackle::fracture
