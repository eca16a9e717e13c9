/// @file The mass-spring lattice: repelled points (§4.4) or a regular triangular lattice (§4.1), triangulated.
#include "mesh/lattice.hpp"

#include "core/log.hpp"
#include "fracture/mass_spring/mass_spring.hpp"
#include "mesh/sampling.hpp"
#include "mesh/triangulate.hpp"

#include <cmath>

namespace crackle::fracture {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;
using mesh::vertex_id;

// === Discretization

mesh::SurfaceMesh mass_spring_mesh(const mesh::Surface& surface, std::size_t masses, Lattice lattice,
                                   const mesh::SamplingOptions& sampling, Rng& rng) {
    if (lattice == Lattice::Regular) {
        if (surface.periodic()) {
            // Columns along v: springs run along v and ±30° from u. So growth along v, which
            // the lattice has springs for, shows the failure of Fig. 4.6 (cracks follow the
            // lattice, not the load); growth around a trunk (u) happens to suit it.
            double stretch = 1;
            const Vec2 period = surface.period();
            auto pts = mesh::triangular_lattice(Vec2(period.y(), period.x()), masses, &stretch);
            for (Vec2& q : pts)
                q = Vec2(q.y(), q.x());
            if (std::abs(stretch - 1) > 0.05)
                log::warn("the regular lattice is stretched by ", 100 * (stretch - 1),
                          " % along u to fit the tile; cracks will favour its directions even more");
            return mesh::triangulate_periodic(pts, surface);
        }
        return mesh::triangulate_sphere(mesh::icosphere_points(surface.radius(), mesh::icosphere_level(masses)),
                                        surface);
    }
    mesh::SamplingOptions o = sampling;
    o.count = masses;
    if (surface.periodic())
        return mesh::triangulate_periodic(mesh::sample_periodic(surface.period(), o, {}, rng), surface);
    return mesh::triangulate_sphere(mesh::sample_sphere(surface.radius(), o, {}, rng), surface);
}

} // namespace crackle::fracture
