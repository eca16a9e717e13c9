#include "core/error.hpp"
#include "io/mesh_export.hpp"
#include "io/mesh_files.hpp"
#include "support/export_fixtures.hpp"

#include <doctest/doctest.h>

#include <map>
#include <set>
#include <sstream>

using namespace crackle;
namespace fs = std::filesystem;

namespace {

Vec3 vec(const std::vector<float>& v, std::size_t i) {
    return {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
}

/// Twice-halved cross product: the triangle's area times its geometric unit normal.
Vec3 area_vector(const io::ImportedMesh& m, std::size_t f) {
    const Vec3 a = vec(m.positions, m.indices[3 * f]), b = vec(m.positions, m.indices[3 * f + 1]),
               c = vec(m.positions, m.indices[3 * f + 2]);
    return 0.5 * (b - a).cross(c - a);
}

/// Writes the export of `pieces` into `dir` as base.<format>; returns the mesh file.
fs::path export_to(const fs::path& dir, const post::PieceMesh& pieces, const std::string& format, bool split) {
    const render::TextureSet maps = test::small_maps();
    const auto files = io::mesh_files(pieces, maps, io::encode_texture_set(maps, false), dir / "base", {format, split});
    test::write_files(files);
    return files.front().path;
}

/// Every node's triangles of a glTF read back by hand.
std::vector<io::ImportedMesh> gltf_meshes(const test::GltfDoc& doc) {
    std::vector<io::ImportedMesh> out;
    for (const Json& node : doc.json.find("nodes")->elements()) {
        const Json& prim = doc.at("meshes", node.find("mesh")->as_number()).find("primitives")->elements()[0];
        io::ImportedMesh m;
        m.node = node.find("name")->as_string();
        m.positions = doc.accessor(prim.find("attributes")->find("POSITION")->as_number());
        m.normals = doc.accessor(prim.find("attributes")->find("NORMAL")->as_number());
        for (float i : doc.accessor(prim.find("indices")->as_number()))
            m.indices.push_back(static_cast<std::uint32_t>(i));
        out.push_back(std::move(m));
    }
    return out;
}

/// The meshes of an exported file: glTF parsed by hand, OBJ through assimp.
std::vector<io::ImportedMesh> read_back(const fs::path& file) {
    return file.extension() == ".obj" ? io::import_meshes(file.string()) : gltf_meshes(test::read_gltf(file));
}

std::set<std::string> file_names(const std::vector<io::OutputFile>& files) {
    std::set<std::string> names;
    for (const io::OutputFile& f : files)
        names.insert(f.path.filename().string());
    return names;
}

/// Triangles per fragment (a triangle's first corner decides, as export_meshes does).
std::map<int, std::size_t> triangles_per_fragment(const post::PieceMesh& pieces) {
    std::map<int, std::size_t> count;
    for (const auto& tri : pieces.triangles)
        ++count[pieces.vertices[tri[0]].fragment];
    return count;
}

} // namespace

TEST_SUITE("io") {
    TEST_CASE("mesh files: a flat plate's faces point +Y or sideways, never down, read back from glTF, GLB and OBJ") {
        const post::PieceMesh pieces = test::plate_pieces(0.0);
        const auto dir = test::scratch_dir("mesh-files-flat");
        for (const std::string format : {"gltf", "glb", "obj"}) {
            CAPTURE(format);
            const fs::path file = export_to(dir / format, pieces, format, false);
            std::vector<std::vector<io::ImportedMesh>> readers = {read_back(file)};
            if (format != "obj") readers.push_back(io::import_meshes(file.string())); // assimp too
            for (const auto& meshes : readers) {
                double up = 0;
                std::size_t faces = 0, bad = 0;
                for (const io::ImportedMesh& m : meshes)
                    for (std::size_t f = 0; f < m.indices.size() / 3; ++f, ++faces) {
                        const Vec3 a = area_vector(m, f);
                        if (a.norm() < 1e-12) continue;
                        const double ny = a.normalized().y();
                        // Tops and floor face +Y, walls stand within 0.6° of vertical: nothing faces down.
                        if (!(ny > 1 - 1e-5 || std::abs(ny) < 1e-2)) ++bad;
                        if (ny > 0.5) up += a.norm();
                    }
                CHECK(faces == pieces.triangles.size());
                CHECK(bad == 0);
                // Tops and floor cover the 0.2 m × 0.2 m tile once.
                CHECK(up == doctest::Approx(0.04).epsilon(1e-4));
            }
        }
    }

    TEST_CASE("mesh files: the trunk's axis comes out along Y, its faces turned outwards") {
        const post::PieceMesh pieces = test::trunk_pieces();
        const auto dir = test::scratch_dir("mesh-files-trunk");
        for (const std::string format : {"glb", "obj"}) {
            CAPTURE(format);
            Vec3 lo = Vec3::Constant(1e9), hi = Vec3::Constant(-1e9);
            double area = 0, outward = 0;
            for (const io::ImportedMesh& m : read_back(export_to(dir / format, pieces, format, false))) {
                for (std::size_t v = 0; v < m.positions.size() / 3; ++v) {
                    lo = lo.cwiseMin(vec(m.positions, v));
                    hi = hi.cwiseMax(vec(m.positions, v));
                }
                for (std::size_t f = 0; f < m.indices.size() / 3; ++f) {
                    const Vec3 a = area_vector(m, f);
                    const Vec3 centre = (vec(m.positions, m.indices[3 * f]) + vec(m.positions, m.indices[3 * f + 1])
                                         + vec(m.positions, m.indices[3 * f + 2]))
                                        / 3.0;
                    const Vec3 radial = Vec3(centre.x(), 0, centre.z()).normalized();
                    area += a.norm();
                    outward += a.dot(radial);
                }
            }
            const Vec3 extent = hi - lo, middle = 0.5 * (hi + lo);
            CAPTURE(extent.transpose());
            // 0.3 m tall and 0.3 / π ≈ 0.095 m across (plus the bark's thickness), round, on the axis.
            CHECK(extent.y() > 2.5 * std::max(extent.x(), extent.z()));
            CHECK(std::abs(extent.x() - extent.z()) < 0.1 * extent.x());
            CHECK(std::abs(middle.x()) < 0.05 * extent.x());
            CHECK(std::abs(middle.z()) < 0.05 * extent.z());
            CHECK(outward > 0.7 * area); // walls face sideways; tops and floor face out
        }
    }

    TEST_CASE("mesh files: every triangle winds counter-clockwise around its stored normals, split or not") {
        const auto dir = test::scratch_dir("mesh-files-winding");
        int n = 0;
        for (const post::PieceMesh& pieces : {test::plate_pieces(0.05), test::trunk_pieces()})
            for (bool split : {false, true}) {
                CAPTURE(split);
                std::size_t checked = 0, wrong = 0;
                for (const io::ImportedMesh& m : read_back(export_to(dir / std::to_string(n++), pieces, "glb", split)))
                    for (std::size_t f = 0; f < m.indices.size() / 3; ++f) {
                        const Vec3 a = area_vector(m, f);
                        if (a.norm() < 1e-14) continue;
                        const Vec3 stored = vec(m.normals, m.indices[3 * f]) + vec(m.normals, m.indices[3 * f + 1])
                                            + vec(m.normals, m.indices[3 * f + 2]);
                        ++checked;
                        if (a.dot(stored) <= 0) ++wrong;
                    }
                CHECK(checked > 0);
                CHECK(wrong == 0);
            }
    }

    TEST_CASE(
        "mesh files: split pieces keep unit tangents orthogonal to the normals, along +u with the right handedness") {
        const test::GltfDoc doc =
            test::read_gltf(export_to(test::scratch_dir("mesh-files-tangents"), test::plate_pieces(0.05), "glb", true));
        std::size_t pairs = 0, along_u = 0, handed = 0;
        for (const Json& mesh : doc.json.find("meshes")->elements()) {
            const Json& attributes = *mesh.find("primitives")->elements()[0].find("attributes");
            const auto P = doc.accessor(attributes.find("POSITION")->as_number());
            const auto N = doc.accessor(attributes.find("NORMAL")->as_number());
            const auto T = doc.accessor(attributes.find("TANGENT")->as_number());
            const auto UV = doc.accessor(attributes.find("TEXCOORD_0")->as_number());
            const auto I = doc.accessor(mesh.find("primitives")->elements()[0].find("indices")->as_number());
            for (std::size_t v = 0; v < P.size() / 3; ++v) {
                const Vec3 t(T[4 * v], T[4 * v + 1], T[4 * v + 2]);
                REQUIRE(t.norm() == doctest::Approx(1.0).epsilon(1e-5));
                REQUIRE(std::abs(t.dot(vec(N, v))) < 1e-4);
                REQUIRE(std::abs(T[4 * v + 3]) == 1.0f);
            }
            for (std::size_t f = 0; f < I.size() / 3; ++f) {
                std::array<std::size_t, 3> c{};
                for (std::size_t k = 0; k < 3; ++k)
                    c[k] = static_cast<std::size_t>(I[3 * f + k]);
                const Vec3 e1 = vec(P, c[1]) - vec(P, c[0]), e2 = vec(P, c[2]) - vec(P, c[0]);
                const Vec2 d1(UV[2 * c[1]] - UV[2 * c[0]], UV[2 * c[1] + 1] - UV[2 * c[0] + 1]);
                const Vec2 d2(UV[2 * c[2]] - UV[2 * c[0]], UV[2 * c[2] + 1] - UV[2 * c[0] + 1]);
                const double det = d1.x() * d2.y() - d2.x() * d1.y();
                if (std::abs(det) < 1e-12) continue;
                const Vec3 dP_du = (e1 * d2.y() - e2 * d1.y()) / det, dP_dv = (e2 * d1.x() - e1 * d2.x()) / det;
                for (std::size_t v : c) {
                    const Vec3 t(T[4 * v], T[4 * v + 1], T[4 * v + 2]);
                    const Vec3 bitangent = vec(N, v).cross(t) * T[4 * v + 3];
                    ++pairs;
                    along_u += t.dot(dP_du) > 0;
                    // glTF's v runs down the image, the NormalGL map's green up it.
                    handed += bitangent.dot(dP_dv) < 0;
                }
            }
        }
        REQUIRE(pairs > 1000);
        CHECK(double(along_u) > 0.99 * double(pairs));
        CHECK(double(handed) > 0.99 * double(pairs));
    }

    TEST_CASE(
        "mesh files: .gltf comes with its .bin and the Color, NormalGL and ORM maps only, with the bake's bytes") {
        const post::PieceMesh pieces = test::plate_pieces(0.05);
        const render::TextureSet maps = test::small_maps();
        const std::vector<io::EncodedMap> encoded = io::encode_texture_set(maps, false);
        const auto dir = test::scratch_dir("mesh-files-sets");
        auto files = [&](const std::string& format) {
            return io::mesh_files(pieces, maps, encoded, dir / "mud.any", {format, false});
        };
        const auto gltf = files("gltf");
        CHECK(file_names(gltf)
              == std::set<std::string>{"mud.gltf", "mud.bin", "mud_Color.png", "mud_NormalGL.png", "mud_ORM.png"});
        CHECK(file_names(files("glb")) == std::set<std::string>{"mud.glb"});
        CHECK(file_names(files("obj"))
              == std::set<std::string>{"mud.obj", "mud.mtl", "mud_Color.png", "mud_NormalGL.png", "mud_Roughness.png"});
        CHECK_THROWS_AS(files("fbx"), InputError);
        // The maps are the bake's files, byte for byte and by name; ORM is encoded here.
        for (const io::OutputFile& f : gltf) {
            if (f.path.extension() != ".png") continue;
            CAPTURE(f.path);
            const io::EncodedMap orm = io::encode_orm(maps);
            const io::EncodedMap* same = f.path == io::map_path(dir, "mud", orm) ? &orm : nullptr;
            for (const io::EncodedMap& m : encoded)
                if (f.path == io::map_path(dir, "mud", m)) same = &m;
            REQUIRE(same != nullptr);
            CHECK(f.bytes == same->bytes);
        }
        test::write_files(gltf);
        const std::string text = test::slurp(dir / "mud.gltf");
        CHECK(text.find("data:") == std::string::npos);
        const test::GltfDoc doc = test::read_gltf(dir / "mud.gltf");
        CHECK(doc.at("buffers", 0).find("uri")->as_string() == "mud.bin");
        CHECK(doc.at("buffers", 0).find("byteLength")->as_number() == double(fs::file_size(dir / "mud.bin")));
        std::set<std::string> uris;
        for (const Json& image : doc.json.find("images")->elements())
            uris.insert(image.find("uri")->as_string());
        CHECK(uris == std::set<std::string>{"mud_Color.png", "mud_NormalGL.png", "mud_ORM.png"});
    }

    TEST_CASE("mesh files: the MTL names colour, roughness and normal maps with the PBR extension keys") {
        const post::PieceMesh pieces = test::plate_pieces(0.05);
        const auto dir = test::scratch_dir("mesh-files-mtl");
        const fs::path obj = export_to(dir, pieces, "obj", false);
        std::set<std::string> lines, keys;
        std::istringstream mtl(test::slurp(dir / "base.mtl"));
        for (std::string line; std::getline(mtl, line);) {
            lines.insert(line);
            keys.insert(line.substr(0, line.find(' ')));
        }
        for (const char* line : {"map_Kd base_Color.png", "map_Pr base_Roughness.png", "norm base_NormalGL.png",
                                 "map_bump -bm 1 base_NormalGL.png", "Pr 1", "Pm 0"})
            CHECK_MESSAGE(lines.count(line) == 1, line);
        for (const char* legacy : {"map_Ns", "bump", "map_Ka", "map_Ks", "map_Bump"})
            CHECK_MESSAGE(keys.count(legacy) == 0, legacy);
        // assimp reads the PBR keys into their slots.
        io::ImportedSummary s = io::import_summary(obj.string());
        CHECK(s.textures["diffuse"] == "base_Color.png");
        CHECK(s.textures["normals"] == "base_NormalGL.png");
        CHECK(s.textures["roughness"] == "base_Roughness.png");
        // vt keeps OBJ's origin at the bottom: the pieces' own (u, v).
        std::vector<std::pair<float, float>> vt, uv;
        std::istringstream text(test::slurp(obj));
        for (std::string line; std::getline(text, line);)
            if (line.rfind("vt ", 0) == 0) {
                std::istringstream in(line.substr(3));
                float u = 0, v = 0;
                in >> u >> v;
                vt.emplace_back(u, v);
            }
        for (const post::PieceVertex& v : pieces.vertices)
            uv.emplace_back(static_cast<float>(v.uv.x()), static_cast<float>(v.uv.y()));
        std::sort(vt.begin(), vt.end());
        std::sort(uv.begin(), uv.end());
        REQUIRE(vt.size() == uv.size());
        std::size_t off = 0; // v goes through the float (1 − v) of glTF and back: 1e-7 of round-off
        for (std::size_t i = 0; i < vt.size(); ++i)
            off += std::abs(vt[i].first - uv[i].first) > 1e-6f || std::abs(vt[i].second - uv[i].second) > 1e-6f;
        CHECK(off == 0);
    }

    TEST_CASE("mesh files: split pieces give one node per fragment plus the crack floor, tagged, every triangle once") {
        const post::PieceMesh pieces = test::plate_pieces(0.05);
        const std::map<int, std::size_t> expected = triangles_per_fragment(pieces);
        REQUIRE(expected.size() > 3);
        REQUIRE(expected.count(-1) == 1);
        auto name_of = [](int id) { return id < 0 ? std::string("crack_floor") : "piece_" + std::to_string(id); };
        const auto dir = test::scratch_dir("mesh-files-split");
        for (const std::string format : {"gltf", "glb", "obj"}) {
            CAPTURE(format);
            const fs::path file = export_to(dir / format, pieces, format, true);
            std::map<std::string, std::size_t> got;
            for (const io::ImportedMesh& m : read_back(file))
                got[m.node] += m.indices.size() / 3;
            std::map<std::string, std::size_t> want;
            for (const auto& [id, count] : expected)
                want[name_of(id)] = count;
            CHECK(got == want);
            if (format == "obj") continue;
            const test::GltfDoc doc = test::read_gltf(file);
            for (const Json& node : doc.json.find("nodes")->elements()) {
                const Json* extras = node.find("extras");
                REQUIRE(extras != nullptr);
                CHECK(name_of(int(extras->find("fragment")->as_number())) == node.find("name")->as_string());
            }
            CHECK(doc.at("scenes", 0).find("nodes")->elements().size() == expected.size());
        }
        // Not split: one node named after the file, without extras.
        const test::GltfDoc whole = test::read_gltf(export_to(dir / "whole", pieces, "glb", false));
        REQUIRE(whole.json.find("nodes")->elements().size() == 1);
        CHECK(whole.at("nodes", 0).find("name")->as_string() == "base");
        CHECK(whole.at("nodes", 0).find("extras") == nullptr);
    }

    TEST_CASE("mesh files: the Khronos validator reports no errors and no warnings on .gltf and .glb, split or not") {
        const post::PieceMesh pieces = test::plate_pieces(0.05);
        const auto dir = test::scratch_dir("mesh-files-validator");
        for (const char* format : {"gltf", "glb"})
            for (bool split : {false, true}) {
                CAPTURE(split);
                const fs::path file =
                    export_to(dir / (std::string(format) + (split ? "-split" : "")), pieces, format, split);
                if (!test::check_validator(file)) return;
            }
    }
}
