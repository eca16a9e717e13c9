// The fast paths of FemModel (issue 15) against the slow ones they replace, on every surface:
// deferred row updates during a run of bisections, stiffness-only trials, and local solves
// that do not depend on explicit zeros left in K by earlier edits.
#include "core/rng.hpp"
#include "sim/fem_model.hpp"
#include "support/fem_fixture.hpp"

#include <doctest/doctest.h>

using namespace crackle;
using mesh::SurfaceKind;
using test::Layer;
using test::LayerSpec;

namespace {

/// A shrinking layer (top faster than bottom) with a varying threshold, loaded and relaxed.
LayerSpec loaded(SurfaceKind kind) {
    LayerSpec spec;
    spec.kind = kind;
    spec.size = kind == SurfaceKind::Sphere ? Vec2(0.06, 0.06) : Vec2(0.2, 0.2);
    spec.elements = 400;
    spec.shrinkage = {0.003, 0.001};
    spec.threshold_variation.pattern = sim::PatternKind::Noise;
    spec.threshold_variation.amplitude = 0.3;
    spec.threshold_variation.scale = 0.03;
    spec.fem.tolerance = 1e-10;
    return spec;
}

void load(sim::FemModel& m) {
    m.set_time(0.5);
    m.relax();
}

/// The faces to bisect: a deterministic walk over the first faces.
std::vector<mesh::FaceId> some_faces(const sim::FemModel& m, int count) {
    Rng rng(21, RngStream::Test);
    std::vector<mesh::FaceId> faces;
    for (int i = 0; i < count; ++i)
        faces.push_back(mesh::face_id(rng.uniform_int(static_cast<std::uint32_t>(m.mesh().num_faces()))));
    return faces;
}

/// The vertices of some faces, sorted and unique: the seeds of a local solve.
std::vector<std::size_t> vertices_of(const sim::FemModel& m, const std::vector<mesh::FaceId>& faces) {
    std::vector<std::size_t> seeds;
    for (mesh::FaceId f : faces)
        for (mesh::VertexId w : m.mesh().faces[f].v)
            seeds.push_back(mesh::ix(w));
    std::sort(seeds.begin(), seeds.end());
    seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
    return seeds;
}

bool same_positions(const sim::FemModel& a, const sim::FemModel& b) {
    if (a.mesh().num_vertices() != b.mesh().num_vertices()) return false;
    for (std::size_t v = 0; v < a.mesh().num_vertices(); ++v)
        if (a.top_position(mesh::vertex_id(v)) != b.top_position(mesh::vertex_id(v))) return false;
    return true;
}

std::string name(SurfaceKind k) {
    return k == SurfaceKind::Plane ? "plane" : k == SurfaceKind::Cylinder ? "cylinder" : "sphere";
}

} // namespace

TEST_SUITE("sim") {
    TEST_CASE("fem fast paths: bisections with deferred row updates give bit-identical K, residual and next solve, on "
              "every surface") {
        for (SurfaceKind kind : {SurfaceKind::Plane, SurfaceKind::Cylinder, SurfaceKind::Sphere}) {
            CAPTURE(name(kind));
            Layer a(loaded(kind)), b(loaded(kind));
            load(*a.model);
            load(*b.model);
            const std::vector<mesh::FaceId> faces = some_faces(*a.model, 12);
            for (mesh::FaceId f : faces)
                a.model->subdivide(f);
            b.model->defer_updates();
            for (mesh::FaceId f : faces)
                b.model->subdivide(f);
            b.model->flush_updates();
            REQUIRE(a.model->mesh().num_faces() == b.model->mesh().num_faces());
            CHECK(a.model->mesh().num_faces() > 400 + 12);
            // K as values (explicit zeros aside) and against a full reassembly.
            const Eigen::MatrixXd Ka(a.model->stiffness()), Kb(b.model->stiffness());
            CHECK(Ka == Kb);
            const Eigen::MatrixXd full(a.model->assemble_from_scratch());
            CHECK((Kb - full).cwiseAbs().maxCoeff() <= 1e-12 * full.cwiseAbs().maxCoeff());
            CHECK(a.model->max_residual_force() == b.model->max_residual_force());
            CHECK(a.model->max_residual_force() > 0); // the new nodes start off equilibrium
            a.model->relax();
            b.model->relax();
            CHECK(same_positions(*a.model, *b.model));
        }
    }

    TEST_CASE("fem fast paths: a stiffness-only trial rolls back to the exact state, and its solve equals a full "
              "trial's, on every surface") {
        for (SurfaceKind kind : {SurfaceKind::Plane, SurfaceKind::Cylinder, SurfaceKind::Sphere}) {
            CAPTURE(name(kind));
            Layer a(loaded(kind)), b(loaded(kind));
            load(*a.model);
            load(*b.model);
            const Eigen::MatrixXd K0(a.model->stiffness());
            const Eigen::Index stored0 = a.model->stiffness().nonZeros();
            const std::size_t faces0 = a.model->mesh().num_faces();
            const std::vector<mesh::FaceId> faces = some_faces(*a.model, 8);
            a.model->begin_trial(/*stiffness_only=*/true);
            b.model->begin_trial();
            for (sim::FemModel* m : {a.model.get(), b.model.get()}) {
                m->defer_updates();
                for (mesh::FaceId f : faces)
                    m->subdivide(f);
                m->flush_updates();
            }
            const std::vector<std::size_t> seeds = vertices_of(*a.model, faces);
            double ra = 4, rb = 4;
            a.model->relax_local(seeds, ra);
            b.model->relax_local(seeds, rb);
            // Strengths differ (lower bounds in the stiffness-only trial), displacements do not.
            CHECK(same_positions(*a.model, *b.model));
            bool lower = true;
            for (std::size_t f = faces0; f < a.model->mesh().num_faces(); ++f)
                lower = lower
                        && a.model->material(mesh::face_id(f)).threshold_stress
                               <= b.model->material(mesh::face_id(f)).threshold_stress;
            CHECK(lower);
            a.model->rollback();
            b.model->rollback();
            CHECK(a.model->mesh().num_faces() == faces0);
            CHECK(Eigen::MatrixXd(a.model->stiffness()) == K0);
            // The rows come back as they were stored, not with zeros where the trial added.
            CHECK(a.model->stiffness().nonZeros() == stored0);
            CHECK(same_positions(*a.model, *b.model));
            // The matrix cut back in place grows again for the next change, and equals a full
            // reassembly then.
            for (mesh::FaceId f : faces)
                a.model->subdivide(f);
            const Eigen::MatrixXd full(a.model->assemble_from_scratch());
            CHECK((Eigen::MatrixXd(a.model->stiffness()) - full).cwiseAbs().maxCoeff()
                  <= 1e-12 * full.cwiseAbs().maxCoeff());
        }
    }

    TEST_CASE("fem fast paths: a local solve does not depend on explicit zeros earlier edits left in K, on every "
              "surface") {
        for (SurfaceKind kind : {SurfaceKind::Plane, SurfaceKind::Cylinder, SurfaceKind::Sphere}) {
            CAPTURE(name(kind));
            Layer a(loaded(kind)), b(loaded(kind));
            load(*a.model);
            load(*b.model);
            // Bisecting one by one joins vertices that a later bisection parts again: their
            // entries stay behind as stored zeros. Deferred, those rows are built once.
            const std::vector<mesh::FaceId> faces = some_faces(*a.model, 30);
            for (mesh::FaceId f : faces)
                for (int round = 0; round < 3; ++round)
                    a.model->subdivide(f);
            b.model->defer_updates();
            for (mesh::FaceId f : faces)
                for (int round = 0; round < 3; ++round)
                    b.model->subdivide(f);
            b.model->flush_updates();
            CHECK(a.model->stiffness().nonZeros() > b.model->stiffness().nonZeros());
            CHECK(Eigen::MatrixXd(a.model->stiffness()) == Eigen::MatrixXd(b.model->stiffness()));
            const std::vector<std::size_t> seeds = vertices_of(*a.model, faces);
            double ra = 3, rb = 3;
            a.model->relax_local(seeds, ra);
            b.model->relax_local(seeds, rb);
            CHECK(same_positions(*a.model, *b.model));
            CHECK(ra == rb);
        }
    }
}
