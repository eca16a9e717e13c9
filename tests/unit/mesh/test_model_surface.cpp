// The artist's model as a surface (issue 30): closest points, smooth normals and the UV layout
// on it, and the simulation's mesh remeshed from it: the element count asked for, on the model,
// borders and topology kept, well-shaped triangles, a different mesh for every seed.
#include "core/error.hpp"
#include "core/rng.hpp"
#include "io/model_file.hpp"
#include "mesh/model_surface.hpp"
#include "mesh/remesh_model.hpp"
#include "mesh/surface.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <memory>

using namespace crackle;

namespace {

/// An open cylinder around y (radius r, height h), welded (no seam), wound outward.
mesh::TriangleModel cylinder(int around, int rows, double r, double h) {
    mesh::TriangleModel m;
    for (int j = 0; j <= rows; ++j)
        for (int i = 0; i < around; ++i) {
            const double a = TWO_PI * i / around;
            m.positions.emplace_back(r * std::cos(a), h * j / rows, -r * std::sin(a));
        }
    auto id = [&](int i, int j) { return j * around + (i % around); };
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < around; ++i) {
            m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return m;
}

/// A closed octahedron pushed out to a sphere of radius r, each face split n × n.
mesh::TriangleModel sphere(int n, double r) {
    mesh::TriangleModel m;
    const Vec3 axes[6] = {Vec3::UnitX(), -Vec3::UnitX(), Vec3::UnitY(), -Vec3::UnitY(), Vec3::UnitZ(), -Vec3::UnitZ()};
    const int faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (const auto& f : faces) {
        const Vec3 a = axes[f[0]], b = axes[f[1]], c = axes[f[2]];
        auto at = [&](int i, int j) {
            const Vec3 p = a + (b - a) * i / n + (c - a) * j / n;
            m.positions.push_back(r * p.normalized());
            return static_cast<int>(m.positions.size() - 1);
        };
        for (int i = 0; i < n; ++i)
            for (int j = 0; i + j < n; ++j) {
                m.triangles.push_back({at(i, j), at(i + 1, j), at(i, j + 1)});
                if (i + j + 1 < n) m.triangles.push_back({at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
            }
    }
    // Weld the corners the faces share.
    std::vector<Vec3> welded;
    std::vector<int> index;
    for (const Vec3& p : m.positions) {
        int found = -1;
        for (std::size_t k = 0; k < welded.size() && found < 0; ++k)
            if ((welded[k] - p).norm() < 1e-9) found = static_cast<int>(k);
        if (found < 0) {
            found = static_cast<int>(welded.size());
            welded.push_back(p);
        }
        index.push_back(found);
    }
    for (auto& t : m.triangles)
        for (int& v : t)
            v = index[static_cast<std::size_t>(v)];
    m.positions = welded;
    return m;
}

struct Measured {
    double max_distance = 0; ///< of a vertex from the model (m)
    double area = 0;
    mesh::MeshQuality quality;
};

Measured measure(const mesh::SurfaceMesh& out, const mesh::ModelSurface& model) {
    Measured r;
    for (std::size_t v = 0; v < out.num_vertices(); ++v)
        r.max_distance = std::max(r.max_distance, model.closest(out.positions[mesh::vertex_id(v)]).distance);
    r.area = out.total_area();
    r.quality = mesh::mesh_quality(out);
    return r;
}

} // namespace

TEST_SUITE("mesh") {
    TEST_CASE("model surface: the closest point, the smooth normal and the UV layout at it") {
        mesh::TriangleModel square;
        square.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
        square.triangles = {{0, 1, 2}, {0, 2, 3}};
        square.corner_uv = {{Vec2(0, 0), Vec2(1, 0), Vec2(1, 1)}, {Vec2(0, 0), Vec2(1, 1), Vec2(0, 1)}};
        const mesh::ModelSurface s(square);
        CHECK(s.area() == doctest::Approx(1.0));
        const auto hit = s.closest(Vec3(0.7, 0.2, 0.5));
        CHECK((hit.point - Vec3(0.7, 0.2, 0)).norm() < 1e-12);
        CHECK(hit.distance == doctest::Approx(0.5));
        CHECK((s.normal(hit) - Vec3::UnitZ()).norm() < 1e-12);
        CHECK((s.uv(hit) - Vec2(0.7, 0.2)).norm() < 1e-12);
        // Off the edge: the closest point is on the border.
        CHECK((s.closest(Vec3(2, 0.5, 0)).point - Vec3(1, 0.5, 0)).norm() < 1e-12);
        // On a sphere the smooth normal is the radial direction (within the facets' error).
        const mesh::ModelSurface ball(sphere(8, 0.2));
        const Vec3 q = Vec3(0.3, 0.1, -0.25);
        CHECK(ball.normal(ball.closest(q)).dot(q.normalized()) > 0.995);
    }

    TEST_CASE("model surface: a mesh surface's tangent frame follows the UV layout's u, else the projected x axis") {
        // A unit square in the xy plane whose layout turns u along +y.
        mesh::TriangleModel square;
        square.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
        square.triangles = {{0, 1, 2}, {0, 2, 3}};
        square.corner_uv = {{Vec2(0, 1), Vec2(0, 0), Vec2(1, 0)}, {Vec2(0, 1), Vec2(1, 0), Vec2(1, 1)}};
        mesh::SurfaceOptions options;
        options.kind = mesh::SurfaceKind::Mesh;
        options.model = std::make_shared<const mesh::ModelSurface>(square);
        const mesh::Surface turned(options);
        CHECK(!turned.periodic());
        CHECK(turned.area() == doctest::Approx(1.0));
        for (const Vec3& p : {Vec3(0.2, 0.3, 0.1), Vec3(0.8, 0.6, -0.2)}) {
            const mesh::TangentFrame f = turned.frame(p);
            CHECK((f.e_u - Vec3::UnitY()).norm() < 1e-12);
            CHECK((f.e_v + Vec3::UnitX()).norm() < 1e-12); // n × e_u
            CHECK((f.n - Vec3::UnitZ()).norm() < 1e-12);
            CHECK((turned.uv(p) - Vec2(p.y(), 1.0 - p.x())).norm() < 1e-12);
            CHECK((turned.project(p) - Vec3(p.x(), p.y(), 0)).norm() < 1e-12);
        }
        // Without a layout: the x axis projected into the tangent plane (here a plane tilted about y).
        mesh::TriangleModel tilted;
        tilted.positions = {Vec3(0, 0, 0), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 0)};
        tilted.triangles = {{0, 1, 2}, {0, 2, 3}};
        options.model = std::make_shared<const mesh::ModelSurface>(tilted);
        const mesh::TangentFrame f = mesh::Surface(options).frame(Vec3(0.5, 0.5, 0.5));
        CHECK((f.e_u - Vec3(1, 0, 1).normalized()).norm() < 1e-12);
        CHECK(std::abs(f.e_u.dot(f.n)) < 1e-12);
    }

    TEST_CASE("remesh model: the count asked for, on the model, borders and topology kept, well-shaped, seeded") {
        struct Case {
            const char* name;
            mesh::TriangleModel model;
            long euler;
        };
        for (Case c : {Case{"open cylinder", cylinder(32, 8, 0.1, 0.3), 0}, Case{"sphere", sphere(10, 0.15), 2}}) {
            CAPTURE(c.name);
            const mesh::ModelSurface model(c.model);
            mesh::RemeshOptions options;
            options.elements = 3000;
            Rng rng(1, RngStream::Sampling);
            const mesh::SurfaceMesh out = mesh::remesh_model(model, options, rng);
            CHECK(out.validate() == "");
            CHECK(double(out.num_faces()) == doctest::Approx(3000.0).epsilon(0.06));
            CHECK(out.euler_characteristic() == c.euler);
            const Measured m = measure(out, model);
            const double edge = mesh::target_edge_length(model.area(), options.elements);
            CHECK(m.max_distance < 1e-6 * edge);
            CHECK(m.area == doctest::Approx(model.area()).epsilon(0.01));
            MESSAGE(std::string(c.name) << ": " << out.num_faces() << " faces, min angle " << m.quality.min_angle_deg
                                        << "°, mean min " << m.quality.mean_min_angle_deg << "°, edge CV "
                                        << m.quality.edge_std / m.quality.edge_mean);
            CHECK(m.quality.min_angle_deg > 15.0);
            CHECK(m.quality.mean_min_angle_deg > 40.0);
            CHECK(m.quality.edge_std / m.quality.edge_mean < 0.3);
            CHECK(m.quality.edge_mean == doctest::Approx(edge).epsilon(0.2));
            // The borders stay where the model has them (the cylinder's rims at y = 0 and 0.3).
            if (c.euler == 0) CHECK(out.num_boundary_edges() > 0);
            // Seeded: the same seed the same mesh, another seed another.
            Rng same(1, RngStream::Sampling), other(2, RngStream::Sampling);
            const mesh::SurfaceMesh again = mesh::remesh_model(model, options, same);
            const mesh::SurfaceMesh moved = mesh::remesh_model(model, options, other);
            REQUIRE(again.num_vertices() == out.num_vertices());
            double same_shift = 0, other_shift = 0;
            for (std::size_t v = 0; v < out.num_vertices(); ++v) {
                const mesh::VertexId id = mesh::vertex_id(v);
                same_shift = std::max(same_shift, (again.positions[id] - out.positions[id]).norm());
                if (v < moved.num_vertices())
                    other_shift = std::max(other_shift, (moved.positions[id] - out.positions[id]).norm());
            }
            CHECK(same_shift == 0.0);
            CHECK(other_shift > 0.01 * edge);
        }
    }

    TEST_CASE("remesh model: a real model keeps its shape and topology (the COLLADA duck)") {
        const std::filesystem::path file = "/usr/share/assimp/models/Collada/duck.dae";
        REQUIRE_MESSAGE(std::filesystem::is_regular_file(file), "run scripts/setup (assimp-testmodels)");
        const mesh::ModelSurface model(io::read_model(file));
        mesh::RemeshOptions options;
        options.elements = 4000;
        Rng rng(7, RngStream::Sampling);
        const mesh::SurfaceMesh out = mesh::remesh_model(model, options, rng);
        CHECK(out.validate() == "");
        CHECK(out.num_boundary_edges() == 0);
        CHECK(out.euler_characteristic() == 2); // closed, genus 0 like the input
        CHECK(double(out.num_faces()) == doctest::Approx(4000.0).epsilon(0.06));
        const Measured m = measure(out, model);
        CHECK(m.area == doctest::Approx(model.area()).epsilon(0.03));
        MESSAGE("duck: " << out.num_faces() << " faces, min angle " << m.quality.min_angle_deg << "°, mean min "
                         << m.quality.mean_min_angle_deg << "°, edge CV " << m.quality.edge_std / m.quality.edge_mean);
        CHECK(m.quality.mean_min_angle_deg > 35.0);
    }

    TEST_CASE("remesh model: faces wound against their neighbours are refused with what to do") {
        mesh::TriangleModel m = cylinder(8, 2, 0.1, 0.2);
        std::swap(m.triangles[3][1], m.triangles[3][2]);
        const mesh::ModelSurface model(m);
        Rng rng(1, RngStream::Sampling);
        CHECK_THROWS_WITH_AS(mesh::remesh_model(model, {}, rng), doctest::Contains("Recalculate Outside"), InputError);
    }
}
