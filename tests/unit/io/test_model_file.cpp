// The artist's model read through assimp (issue 30): seams welded for the simulation with the
// UV layout kept, node transforms and units applied, one node picked, the same model in three
// formats read alike, and every kind of bad model refused with exit 2 and what to do.
#include "core/error.hpp"
#include "core/math.hpp"
#include "io/model_file.hpp"
#include "support/cli_runner.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <fstream>
#include <sstream>

using namespace crackle;
namespace fs = std::filesystem;

namespace {

/// Where Debian's assimp-testmodels puts its models (scripts/setup installs it).
const fs::path MODELS = "/usr/share/assimp/models";

fs::path write(const std::string& name, const std::string& text) {
    const fs::path file = test::scratch_dir("model-file") / name;
    std::ofstream(file) << text;
    return file;
}

/// An open cylinder (radius r, height h) as OBJ with its UV seam split: the vertices at u = 0 and
/// u = 1 are separate, as every exporter writes them.
std::string cylinder_obj(int around, int rows, double r, double h) {
    std::ostringstream o;
    for (int j = 0; j <= rows; ++j)
        for (int i = 0; i <= around; ++i) { // i = around repeats i = 0's position
            const double a = TWO_PI * (i % around) / around;
            o << "v " << r * std::cos(a) << " " << h * j / rows << " " << -r * std::sin(a) << "\n";
            o << "vt " << double(i) / around << " " << double(j) / rows << "\n";
        }
    auto id = [&](int i, int j) { return j * (around + 1) + i + 1; };
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < around; ++i) {
            const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
            o << "f " << a << "/" << a << " " << b << "/" << b << " " << c << "/" << c << "\n";
            o << "f " << a << "/" << a << " " << c << "/" << c << " " << d << "/" << d << "\n";
        }
    return o.str();
}

/// A COLLADA scene: one unit quad in the xy plane (two triangles), instanced by the named nodes,
/// each translated along x by its offset and scaled by its scale; `unit` metres per unit.
std::string quads_dae(const std::vector<std::tuple<std::string, double, double>>& nodes, double unit) {
    std::ostringstream o;
    o << R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="u" meter=")"
      << unit << R"("/><up_axis>Y_UP</up_axis></asset>
  <library_geometries><geometry id="quad" name="quad"><mesh>
    <source id="p"><float_array id="pa" count="12">0 0 0 1 0 0 1 1 0 0 1 0</float_array>
      <technique_common><accessor source="#pa" count="4" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles count="2"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2 0 2 3</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s">
)";
    for (const auto& [name, offset, scale] : nodes)
        o << "    <node id=\"" << name << "\" name=\"" << name << "\"><translate>" << offset << " 0 0</translate>"
          << "<scale>" << scale << " 1 1</scale><instance_geometry url=\"#quad\"/></node>\n";
    o << R"(  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
)";
    return o.str();
}

Vec3 face_normal(const io::ModelMesh& m, std::size_t t) {
    const auto& f = m.triangles[t];
    const Vec3& a = m.positions[static_cast<std::size_t>(f[0])];
    return (m.positions[static_cast<std::size_t>(f[1])] - a).cross(m.positions[static_cast<std::size_t>(f[2])] - a);
}

fs::path model(const std::string& relative) {
    const fs::path file = MODELS / relative;
    REQUIRE_MESSAGE(fs::is_regular_file(file), file.string() << " is missing: run scripts/setup (assimp-testmodels)");
    return file;
}

} // namespace

TEST_SUITE("io") {
    TEST_CASE("model file: a cylinder's UV seam is welded for the simulation and kept in the UV layout") {
        const int around = 24, rows = 6;
        const double r = 0.1, h = 0.3;
        const io::ModelMesh m = io::read_model(write("cylinder.obj", cylinder_obj(around, rows, r, h)));
        CHECK(m.summary.file_vertices >= std::size_t((around + 1) * (rows + 1)));
        CHECK(m.positions.size() == std::size_t(around * (rows + 1))); // the seam's copies merged
        CHECK(m.triangles.size() == std::size_t(2 * around * rows));
        CHECK(m.summary.components == 1);
        CHECK(m.summary.boundary_loops == 2); // the two rims; no border along the seam
        CHECK(m.summary.boundary_edges == std::size_t(2 * around));
        // The prism's area: around chords × height.
        CHECK(m.summary.area
              == doctest::Approx(around * 2 * r * std::sin(PI / around) * h).epsilon(1e-5)); // OBJ keeps 6 digits
        CHECK(m.summary.scale == 1.0);
        // The layout keeps both sides of the seam: some corners at u = 1, none welded to u = 0.
        REQUIRE(m.corner_uv.size() == m.triangles.size());
        CHECK(m.summary.uv_sets == 1);
        int at_one = 0;
        for (const auto& corners : m.corner_uv)
            for (const Vec2& uv : corners)
                at_one += std::abs(uv.x() - 1.0) < 1e-12;
        CHECK(at_one == 3 * rows);
        CHECK(m.summary.uv_corners_outside == 0);
        // Faces wound outward as written: the normal points away from the axis.
        for (std::size_t t = 0; t < m.triangles.size(); ++t) {
            const auto& f = m.triangles[t];
            Vec3 c =
                (m.positions[std::size_t(f[0])] + m.positions[std::size_t(f[1])] + m.positions[std::size_t(f[2])]) / 3;
            c.y() = 0;
            CHECK(face_normal(m, t).dot(c) > 0);
        }
    }

    TEST_CASE("model file: node transforms and the file's unit are applied, a node is picked by name, a mirror "
              "keeps the winding") {
        const fs::path two = write("two.dae", quads_dae({{"left", 0.0, 1.0}, {"right", 3.0, 1.0}}, 1.0));
        const io::ModelMesh all = io::read_model(two);
        CHECK(all.triangles.size() == 4);
        CHECK(all.summary.components == 2);
        CHECK(all.summary.nodes.size() == 2);
        CHECK(all.summary.box_min.x() == doctest::Approx(0.0));
        CHECK(all.summary.box_max.x() == doctest::Approx(4.0));

        io::ModelOptions right;
        right.node = "right";
        const io::ModelMesh one = io::read_model(two, right);
        CHECK(one.triangles.size() == 2);
        CHECK(one.summary.box_min.x() == doctest::Approx(3.0));
        CHECK(one.summary.area == doctest::Approx(1.0));

        io::ModelOptions none;
        none.node = "middle";
        CHECK_THROWS_WITH_AS(io::read_model(two, none), doctest::Contains("\"left\", \"right\""), InputError);

        // Centimetres: COLLADA's <unit> reaches the coordinates through the root transform.
        const io::ModelMesh cm = io::read_model(write("cm.dae", quads_dae({{"q", 0.0, 1.0}}, 0.01)));
        CHECK(cm.summary.area == doctest::Approx(1e-4));
        io::ModelOptions scaled;
        scaled.scale = 2.0; // surface.scale overrides what the file says
        CHECK(io::read_model(write("m.dae", quads_dae({{"q", 0.0, 1.0}}, 1.0)), scaled).summary.area
              == doctest::Approx(4.0));

        // A mirrored node (scale −1) would turn its faces inside out: the winding is turned back.
        const io::ModelMesh mirrored = io::read_model(write("mirror.dae", quads_dae({{"q", 0.0, -1.0}}, 1.0)));
        REQUIRE(mirrored.triangles.size() == 2);
        CHECK(face_normal(mirrored, 0).z() > 0);
        CHECK(face_normal(all, 0).z() > 0);
    }

    TEST_CASE("model file: bad models are refused with what to do") {
        auto refused = [](const fs::path& file, const std::string& says, io::ModelOptions options = {}) {
            CAPTURE(file);
            CHECK_THROWS_WITH_AS(io::read_model(file, options), doctest::Contains(says.c_str()), InputError);
        };
        refused(test::scratch_dir("model-file") / "absent.glb", "no such file");
        refused(write("garbage.glb", "this is not a model"), "assimp could not read it");
        refused(write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\np 1 2 3\n"), "no triangles");
        refused(write("lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\n"), "no triangles");
        // Three faces on one edge.
        refused(write("fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n"),
                "shared by more than two faces");
        // A face with no area (three points on a line).
        refused(write("sliver.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n"), "have no area");
        refused(write("inf.obj", "v 0 0 0\nv 1e999 0 0\nv 0 1 0\nf 1 2 3\n"), "not numbers");
        // A face whose two corners are one point once welded is dropped, not refused.
        const io::ModelMesh fan =
            io::read_model(write("fan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 0 0\nf 1 2 3\nf 2 4 3\n"));
        CHECK(fan.triangles.size() == 1);
        CHECK(fan.summary.collapsed_faces == 1);
        io::ModelOptions second;
        second.uv_set = 1;
        refused(write("cyl.obj", cylinder_obj(8, 2, 0.1, 0.2)), "no UV set 1", second);
    }

    TEST_CASE("model file: real models crackle did not make read alike in every format (assimp-testmodels)") {
        // The same model as OBJ, PLY and STL: the same surface once welded.
        const io::ModelMesh obj = io::read_model(model("OBJ/WusonOBJ.obj"));
        for (const char* other : {"PLY/Wuson.ply", "STL/Wuson.stl"}) {
            CAPTURE(other);
            const io::ModelMesh m = io::read_model(model(other));
            CHECK(m.triangles.size() == obj.triangles.size());
            CHECK(m.positions.size() == obj.positions.size());
            CHECK(m.summary.area == doctest::Approx(obj.summary.area).epsilon(1e-4));
            CHECK((m.summary.box_max - obj.summary.box_max).norm()
                  < 1e-4 * (obj.summary.box_max - obj.summary.box_min).norm());
            CHECK(m.summary.components == obj.summary.components);
        }
        CHECK(io::read_model(model("STL/Wuson.stl")).corner_uv.empty()); // STL has no UVs

        // A textured box in three glTF flavours: 24 file vertices welded to 8 corners, closed.
        for (const char* box :
             {"glTF2/BoxTextured-glTF/BoxTextured.gltf", "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb",
              "glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf"}) {
            CAPTURE(box);
            const io::ModelMesh m = io::read_model(model(box));
            CHECK(m.triangles.size() == 12);
            CHECK(m.positions.size() == 8);
            CHECK(m.summary.boundary_edges == 0);
            CHECK(m.summary.components == 1);
            CHECK(m.corner_uv.size() == 12);
        }
        // An open surface: one hole, one boundary loop.
        const io::ModelMesh holed = io::read_model(model("STL/sphereWithHole.stl"));
        CHECK(holed.summary.boundary_loops == 1);
        // FBX keeps its coordinates in its own unit (the spider: centimetres, UnitScaleFactor 1): in
        // metres it is the OBJ spider, whose numbers are metres.
        const io::ModelMesh spider_obj = io::read_model(model("OBJ/spider.obj"));
        const io::ModelMesh spider_fbx = io::read_model(model("FBX/spider.fbx"));
        CHECK(spider_fbx.summary.scale == doctest::Approx(0.01));
        CHECK(spider_fbx.summary.area == doctest::Approx(spider_obj.summary.area).epsilon(1e-4));
        CHECK(spider_fbx.triangles.size() == spider_obj.triangles.size());
        CHECK(spider_obj.summary.nodes.size() == 19);
        // Its legs' 56 faces collapse to slivers once welded: dropped, counted, not refused.
        CHECK(spider_obj.summary.collapsed_faces == 56);
        CHECK(spider_fbx.summary.collapsed_faces == 56);
        // The duck: closed, with its texture layout.
        const io::ModelMesh duck = io::read_model(model("Collada/duck.dae"));
        CHECK(duck.summary.boundary_edges == 0);
        CHECK(duck.summary.components == 1);
        CHECK(duck.corner_uv.size() == duck.triangles.size());
        // Refused: points only, infinite coordinates, a CAD model with fins (non-manifold edges).
        CHECK_THROWS_AS(io::read_model(model("OBJ/testpoints.obj")), InputError);
        CHECK_THROWS_WITH_AS(io::read_model(model("glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb")),
                             doctest::Contains("not numbers"), InputError);
        CHECK_THROWS_WITH_AS(io::read_model(model("glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb")),
                             doctest::Contains("more than two faces"), InputError);
    }
}
