#include "mesh/discretize.hpp"

#include "mesh/remesh_model.hpp"
#include "mesh/triangulate.hpp"

namespace crackle::mesh {

std::size_t points_for_elements(SurfaceKind kind, std::size_t elements) {
    if (kind == SurfaceKind::Sphere) return std::max<std::size_t>(4, (elements + 4) / 2);
    return std::max<std::size_t>(3, elements / 2);
}

SurfaceMesh discretize(const Surface& surface, const DiscretizeOptions& options, const SpacingOverUv& spacing, Rng& rng,
                       StepTimes* times) {
    SamplingOptions sampling = options.sampling;
    sampling.count = points_for_elements(surface.kind(), options.elements);
    Timer timer;
    SurfaceMesh mesh;
    if (surface.kind() == SurfaceKind::Mesh) {
        // The artist's model: remeshed isotropically (the spacing field is not followed yet).
        if (times) times->emplace_back("sampling", 0.0);
        RemeshOptions remesh;
        remesh.elements = options.elements;
        mesh = remesh_model(*surface.model(), remesh, rng);
    } else if (surface.periodic()) {
        SpacingField2 field;
        if (spacing) field = [&](const Vec2& d) { return spacing(surface.uv_of_domain(d)); };
        const std::vector<Vec2> pts = sample_periodic(surface.period(), sampling, field, rng);
        if (times) times->emplace_back("sampling", timer.seconds());
        timer.reset();
        mesh = triangulate_periodic(pts, surface);
    } else {
        SpacingField3 field;
        if (spacing) field = [&](const Vec3& p) { return spacing(surface.uv(p)); };
        const std::vector<Vec3> pts = sample_sphere(surface.radius(), sampling, field, rng);
        if (times) times->emplace_back("sampling", timer.seconds());
        timer.reset();
        mesh = triangulate_sphere(pts, surface);
    }
    if (times) times->emplace_back("triangulation", timer.seconds());
    return mesh;
}

} // namespace crackle::mesh
