#include "core/error.hpp"
#include "io/mesh_export.hpp"
#include "io/png.hpp"
#include "io/texture_set.hpp"
#include "support/export_fixtures.hpp"

#include <doctest/doctest.h>

#include <limits>

using namespace crackle;
namespace fs = std::filesystem;

namespace {

post::PieceMesh small_pieces() {
    return test::plate_pieces(0.05);
}

io::MaterialMaps tiny_maps(const std::string& base) {
    std::vector<std::uint8_t> rgb(3 * 64, 128);
    io::MaterialMaps m;
    m.name = base;
    m.color = {"Color", "png", io::encode_png_rgb8(8, 8, 3, rgb)};
    m.normal = {"NormalGL", "png", io::encode_png_rgb8(8, 8, 3, rgb)};
    m.orm = {"ORM", "png", io::encode_png_rgb8(8, 8, 3, rgb)};
    m.color_uri = base + "_Color.png";
    m.normal_uri = base + "_NormalGL.png";
    m.orm_uri = base + "_ORM.png";
    return m;
}

/// 16 × 8 pixels (2:1, like the sphere's equirectangular maps) with a height ramp.
render::TextureSet ramp_set() {
    render::TextureSet set;
    set.width = 16;
    set.height_px = 8;
    set.height_scale = 0.02;
    const std::size_t px = set.pixels();
    for (std::size_t i = 0; i < px; ++i)
        set.height.push_back(static_cast<float>(0.02 * double(i * 37 % 256) / 255.0));
    set.normal.assign(3 * px, 0.0f);
    for (std::size_t i = 0; i < px; ++i)
        set.normal[3 * i + 2] = 1.0f;
    set.color.assign(3 * px, 100);
    set.ao.assign(px, 1.0f);
    set.roughness.assign(px, 0.5f);
    set.mask.assign(px, 0.0f);
    set.id.assign(3 * px, 7);
    return set;
}

void write_bytes(const fs::path& p, const std::vector<std::uint8_t>& b) {
    write_file_atomically(p, std::string_view(reinterpret_cast<const char*>(b.data()), b.size()));
}

} // namespace

TEST_SUITE("io") {
    TEST_CASE("export: tangents are unit, orthogonal to the normals and carry a handedness") {
        const io::ExportMesh m = io::export_mesh(small_pieces());
        const std::size_t n = m.positions.size() / 3;
        REQUIRE(m.tangents.size() == 4 * n);
        for (std::size_t i = 0; i < n; ++i) {
            const Vec3 t(m.tangents[4 * i], m.tangents[4 * i + 1], m.tangents[4 * i + 2]);
            const Vec3 nn(m.normals[3 * i], m.normals[3 * i + 1], m.normals[3 * i + 2]);
            REQUIRE(t.norm() == doctest::Approx(1.0).epsilon(1e-5));
            REQUIRE(nn.norm() == doctest::Approx(1.0).epsilon(1e-5));
            REQUIRE(std::abs(t.dot(nn)) < 1e-4);
            REQUIRE(std::abs(std::abs(m.tangents[4 * i + 3]) - 1.0f) < 1e-6f);
        }
    }

    TEST_CASE("export: OBJ and glTF and GLB read back through assimp with the same counts and bounds") {
        const io::ExportMesh m = io::export_mesh(small_pieces());
        const auto dir = test::scratch_dir("export-roundtrip");
        const io::MaterialMaps maps = tiny_maps("piece");
        for (const char* name : {"piece_Color.png", "piece_NormalGL.png", "piece_ORM.png"})
            write_bytes(dir / name, maps.color.bytes);
        write_bytes(dir / "piece.gltf", io::gltf_bytes(m, maps, false));
        write_bytes(dir / "piece.glb", io::gltf_bytes(m, maps, true));
        const auto [obj, mtl] = io::obj_files(m, maps, "piece.mtl");
        write_file_atomically(dir / "piece.obj", obj);
        write_file_atomically(dir / "piece.mtl", mtl);
        const std::size_t vertices = m.positions.size() / 3, faces = m.indices.size() / 3;
        for (const char* file : {"piece.gltf", "piece.glb", "piece.obj"}) {
            CAPTURE(file);
            const io::ImportedSummary s = io::import_summary((dir / file).string());
            CHECK(s.meshes == 1);
            CHECK(s.faces == faces);
            CHECK(s.has_normals);
            CHECK(s.has_uvs);
            if (std::string(file) != "piece.obj") CHECK(s.vertices == vertices); // OBJ re-indexes corners
            for (int c = 0; c < 3; ++c) {
                const auto k = static_cast<std::size_t>(c);
                const double span = std::max(1e-3, double(m.max[k] - m.min[k]));
                CHECK(std::abs(s.min[k] - m.min[k]) <= 1e-6 * span + 1e-7);
                CHECK(std::abs(s.max[k] - m.max[k]) <= 1e-6 * span + 1e-7);
            }
        }
        CHECK(mtl.find("map_Kd piece_Color.png") != std::string::npos);
        CHECK(obj.find("mtllib piece.mtl") != std::string::npos);
    }

    TEST_CASE("export: the Khronos glTF validator reports no errors and no warnings on one mesh") {
        const io::ExportMesh m = io::export_mesh(small_pieces());
        const auto dir = test::scratch_dir("export-validator");
        const io::MaterialMaps maps = tiny_maps("piece");
        for (const char* name : {"piece_Color.png", "piece_NormalGL.png", "piece_ORM.png"})
            write_bytes(dir / name, maps.color.bytes);
        write_bytes(dir / "piece.gltf", io::gltf_bytes(m, maps, false));
        write_bytes(dir / "piece.glb", io::gltf_bytes(m, maps, true));
        for (const char* file : {"piece.gltf", "piece.glb"})
            if (!test::check_validator(dir / file)) return;
    }

    TEST_CASE("export: 16-bit displacement PNGs and float EXRs read back exactly, non-square too") {
        const render::TextureSet set = ramp_set();
        const std::size_t px = set.pixels();
        const auto maps = io::encode_texture_set(set, true);
        bool png = false, exr = false;
        for (const auto& m : maps) {
            if (m.suffix != "Displacement") continue;
            if (m.extension == "png") {
                const GrayImage back = io::decode_png_gray16(m.bytes);
                for (std::size_t i = 0; i < px; ++i) {
                    const long stored = std::lround(set.height[i] / set.height_scale * 65535.0);
                    REQUIRE(std::lround(double(back.pixels[i]) * 65535.0) == stored);
                }
                png = true;
            } else {
                int size = 0, rows = 0;
                const std::vector<float> back = io::decode_exr_gray(m.bytes, size, &rows);
                REQUIRE(size == 16);
                REQUIRE(rows == 8);
                for (std::size_t i = 0; i < px; ++i)
                    REQUIRE(back[i] == set.height[i]);
                exr = true;
            }
        }
        CHECK(png);
        CHECK(exr);
        // Every ambientCG map is there.
        std::vector<std::string> suffixes;
        for (const auto& m : maps)
            suffixes.push_back(m.suffix + "." + m.extension);
        for (const char* s : {"Color.png", "NormalGL.png", "NormalDX.png", "Displacement.png", "AmbientOcclusion.png",
                              "Roughness.png", "Mask.png", "ID.png", "Displacement.exr"})
            CHECK(std::find(suffixes.begin(), suffixes.end(), s) != suffixes.end());
    }

    TEST_CASE("export: a texture set holding NaN or an infinity is a numeric failure naming the map and pixel") {
        const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
        struct Case {
            std::vector<float> render::TextureSet::*channel;
            std::size_t index;
            float value;
            const char* expect;
        };
        // Pixel 37 of a 16-wide map is (5, 2); the normal has three values per pixel.
        for (const Case& c : {Case{&render::TextureSet::height, 37, nan, "height holds NaN at pixel (5, 2)"},
                              Case{&render::TextureSet::normal, 3 * 37 + 1, -inf, "normal holds -inf at pixel (5, 2)"},
                              Case{&render::TextureSet::ao, 127, inf, "occlusion holds +inf at pixel (15, 7)"},
                              Case{&render::TextureSet::roughness, 0, nan, "roughness holds NaN at pixel (0, 0)"},
                              Case{&render::TextureSet::mask, 16, nan, "mask holds NaN at pixel (0, 1)"}}) {
            render::TextureSet set = ramp_set();
            REQUIRE_NOTHROW(io::encode_texture_set(set, true));
            (set.*c.channel)[c.index] = c.value;
            CAPTURE(c.expect);
            bool thrown = false;
            try {
                (void)io::encode_texture_set(set, true);
            } catch (const NumericError& e) {
                thrown = true;
                CHECK(std::string(e.what()).find(c.expect) != std::string::npos);
            }
            CHECK(thrown);
            CHECK_THROWS_AS(io::encode_map(set, "NormalGL"), NumericError);
        }
    }
}
