// fem-split's initiation stress averaged over a physical length (fem_split/nonlocal.hpp): the
// criterion must not depend on the element size. Next to a crack tip the stress is singular, so
// the thesis' nodal stress (§5.7.1) finds higher peaks on every finer mesh; the average over the
// layer's thickness converges.

#include "fracture/fem_split/nonlocal.hpp"
#include "support/accuracy.hpp"
#include "support/fracture_fixture.hpp"
#include "support/scripted_crack.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <string>
#include <vector>

using namespace crackle;

namespace {

/// The largest criterion ratio over a layer's nodes next to a slit, with radius R (0: the
/// thesis' nodal average), and the mean ratio of the nodes far from it.
struct Peak {
    double largest = 0, far = 0;
};

Peak slit_peak(mesh::SurfaceKind kind, std::size_t elements, const std::vector<double>& radii, std::vector<Peak>& out) {
    test::LayerSpec s;
    s.kind = kind;
    s.size = Vec2(0.2, 0.2);
    s.elements = elements;
    s.thickness = 0.01;
    s.growth = {sim::GrowthKind::Anisotropic, 1e-4, 0.0, 0.0}; // stretch across the slit
    test::Layer layer(s);
    sim::FemModel& m = *layer.model;
    m.set_time(1.0);
    m.relax();
    const double h = mesh::mesh_quality(m.mesh()).edge_mean;
    test::cut_path(m, test::edge_path(m, Vec2(0.1, 0.06), Vec2(0.1, 0.14), h)); // 8 thicknesses along v
    m.relax();
    auto stress = [&](std::size_t f) { return m.top_stress(mesh::face_id(f)); };
    out.clear();
    for (double R : radii) {
        fracture::split_detail::NonlocalStress nonlocal(m, [R](std::size_t) { return R; });
        nonlocal.rebuild_all();
        Peak p;
        int n = 0;
        for (std::size_t v = 0; v < m.mesh().num_vertices(); ++v) {
            if (m.incident_faces(v).empty()) continue;
            const double r = nonlocal.nodal(v, stress).ratio;
            p.largest = std::max(p.largest, r);
            const Vec2 d = m.mesh().domain[mesh::vertex_id(v)];
            if (std::abs(d.x() - 0.1) > 0.08 || std::abs(d.y() - 0.1) > 0.09) {
                p.far += r;
                ++n;
            }
        }
        p.far /= n;
        out.push_back(p);
    }
    return out.front();
}

} // namespace

TEST_SUITE("fracture") {
    TEST_CASE("nonlocal: the stress a crack starts from converges under refinement next to a crack tip, where the "
              "thesis' nodal stress keeps rising (plane and cylinder)") {
        // A slit across a uniform stretch, at 1600, 6400 and 25600 elements (edges 0.8, 0.4 and
        // 0.2 layer thicknesses): the thesis' largest nodal ratio grows like the singularity it
        // samples; averaged over the thickness (material.initiation_length = "auto") it settles.
        const double h = 0.01;
        for (mesh::SurfaceKind kind : {mesh::SurfaceKind::Plane, mesh::SurfaceKind::Cylinder}) {
            CAPTURE(std::string(mesh::to_string(kind)));
            std::vector<double> thesis, averaged, far;
            for (std::size_t elements : {1600u, 6400u, 25600u}) {
                std::vector<Peak> peaks;
                slit_peak(kind, elements, {0.0, h}, peaks);
                thesis.push_back(peaks[0].largest);
                averaged.push_back(peaks[1].largest);
                far.push_back(peaks[1].far);
                // Far from the slit the field is uniform: the average is the nodal stress there (to
                // the scatter of a coarse polygonal cylinder's facets, 0.7 % at edges of 0.8 h).
                CHECK(std::abs(peaks[1].far / peaks[0].far - 1) < (elements < 5000 ? 1e-2 : 2e-3));
            }
            const std::string on = mesh::to_string(kind);
            const double thesis_rise = thesis[2] / thesis[1] - 1, averaged_change = averaged[2] / averaged[1] - 1;
            CAPTURE(thesis_rise);
            CAPTURE(averaged_change);
            CHECK(thesis[1] > thesis[0]);
            CHECK(thesis_rise > 0.2);
            CHECK(std::abs(averaged_change) < 0.03);
            CHECK(averaged[2] > far[2]); // the tip still concentrates the averaged stress
            test::record_claim("initiation", "the initiation stress is objective: it converges under refinement",
                               "largest nodal ratio next to a slit, 25600 / 6400 elements - 1, thesis' nodal stress, "
                                   + on,
                               thesis_rise, "> 0.2 (rises with the mesh)");
            test::record_claim("initiation", "the initiation stress is objective: it converges under refinement",
                               "the same, averaged over the layer thickness, " + on, averaged_change, "|.| < 0.03");
        }
    }

    TEST_CASE("nonlocal: on a sphere a uniform stress averages to itself, and a neighbourhood's elements grow with "
              "the radius squared") {
        test::LayerSpec s;
        s.kind = mesh::SurfaceKind::Sphere;
        s.size = Vec2(0.06, 0.06);
        s.elements = 3000;
        s.shrinkage = {1e-3, 1e-3};
        test::Layer layer(s);
        sim::FemModel& m = *layer.model;
        m.set_time(1.0);
        m.relax();
        auto stress = [&](std::size_t f) { return m.top_stress(mesh::face_id(f)); };
        std::vector<double> mean_faces;
        for (double R : {0.006, 0.012}) {
            fracture::split_detail::NonlocalStress nonlocal(m, [R](std::size_t) { return R; });
            nonlocal.rebuild_all();
            double worst = 0, faces = 0;
            for (std::size_t v = 0; v < m.mesh().num_vertices(); ++v) {
                const double local = fracture::nodal_stress(m, v).ratio, averaged = nonlocal.nodal(v, stress).ratio;
                worst = std::max(worst, std::abs(averaged / local - 1));
            }
            for (std::size_t f = 0; f < m.mesh().num_faces(); ++f)
                faces += double(nonlocal.readers(f).size());
            mean_faces.push_back(faces / double(m.mesh().num_vertices()));
            CAPTURE(R);
            CHECK(worst < 0.03); // the facets scatter the uniform field by a few per cent
        }
        CHECK(mean_faces[1] / mean_faces[0] == doctest::Approx(4.0).epsilon(0.25));
    }
}

TEST_SUITE("fracture") {
    TEST_CASE("nonlocal: a new crack starts as long as the layer is thick at every resolution (its nucleus), not two "
              "elements long") {
        // A shrinking layer so tough that every tip stops at once (Griffith): what is left are the
        // cracks as they started. With the averaged criterion each is about one initiation length
        // long (two arms of half of it) whatever the element size; the thesis' starts two elements long.
        auto stubs = [](std::size_t elements, double fraction) {
            test::LayerSpec s;
            s.size = Vec2(0.2, 0.2);
            s.elements = elements;
            s.thickness = 0.01;
            s.toughness = 1e7; // arrests everything
            s.shrinkage = {3e-4, 3e-4};
            fracture::SplitOptions split;
            split.initiation_fraction = fraction;
            fracture::FractureOptions options;
            options.max_events = 40; // a few cracks: they all start at once on the uniform layer
            const auto run = test::run_split(s, 1.0, split, options, false);
            REQUIRE(run.split.splits >= 3);
            CHECK(run.split.extensions + run.split.splits > 0);
            return run.stats.crack_length_per_area * 0.04 / double(run.split.splits); // m per crack
        };
        const double coarse = stubs(3200, 1.0), fine = stubs(12800, 1.0);
        const double thesis_coarse = stubs(3200, 0.0), thesis_fine = stubs(12800, 0.0);
        CAPTURE(coarse);
        CAPTURE(fine);
        CAPTURE(thesis_coarse);
        CAPTURE(thesis_fine);
        CHECK(coarse > 0.009); // at least one initiation length (1 cm), plus the last step past it
        CHECK(fine > 0.009);
        CHECK(std::abs(fine / coarse - 1) < 0.25);
        CHECK(thesis_fine < 0.75 * thesis_coarse); // two elements: halves with the edge
        test::record_claim("initiation", "a new crack starts one initiation length long at every resolution",
                           "mean length of a crack that stopped at once [m], 12800 / 3200 elements - 1 (h = 1 cm)",
                           fine / coarse - 1, "|.| < 0.25");
        test::record_claim("initiation", "a new crack starts one initiation length long at every resolution",
                           "the same with the thesis' criterion (two elements)", thesis_fine / thesis_coarse - 1,
                           "< -0.25");
    }
}
