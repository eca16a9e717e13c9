#include "fracture/fem_remove/fem_remove.hpp"
#include "post/pieces.hpp"
#include "support/accuracy.hpp"
#include "support/fem_fixture.hpp"
#include "support/mass_spring_fixture.hpp"

#include <doctest/doctest.h>

#include <map>
#include <tuple>

using namespace crackle;

namespace {

/// A cracked mud-like layer (element removal), shared by the tests below.
fracture::CrackPattern make_cracked(double thickness) {
    test::LayerSpec spec;
    spec.size = Vec2(0.2, 0.2);
    spec.elements = 700;
    spec.thickness = thickness;
    spec.shrinkage = {3e-4, 3e-4};
    test::Layer layer(spec);
    Rng rng(3, RngStream::Fracture);
    return fracture::run_fem_remove(*layer.model, fracture::FractureOptions{}, rng);
}

const fracture::CrackPattern& cracked() {
    static const fracture::CrackPattern pattern = make_cracked(0.01);
    return pattern;
}

/// Triangles whose corners wind clockwise seen from where their world normals point (of those
/// with an area: a wall of an unopened crack on a flat lip may have none).
std::size_t wound_inwards(const post::PieceMesh& pieces) {
    std::size_t wrong = 0;
    for (const auto& tri : pieces.triangles) {
        const post::PieceVertex &a = pieces.vertices[tri[0]], &b = pieces.vertices[tri[1]],
                                &c = pieces.vertices[tri[2]];
        const Vec3 face = (b.position - a.position).cross(c.position - a.position);
        if (face.norm() < 1e-14) continue;
        wrong += face.dot(a.world_normal + b.world_normal + c.world_normal) < 0;
    }
    return wrong;
}

/// Crack walls whose normal (their corners' winding and their stored normal alike) points into
/// their own piece: towards the third corner of the top triangle on the wall's lip.
std::size_t walls_facing_in(const post::PieceMesh& pieces) {
    // The top triangles by their edges' end points (vertex ids are per piece and offset).
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> third;
    for (std::size_t t = 0; t < pieces.top_triangles; ++t)
        for (std::size_t k = 0; k < 3; ++k)
            third[{pieces.triangles[t][k], pieces.triangles[t][(k + 1) % 3]}] = pieces.triangles[t][(k + 2) % 3];
    // A wall's top corners are copies of the top's vertices: find them by texture position and
    // piece (on the cylinder a vertex and its copy one period over share a world position).
    std::map<std::tuple<double, double, int>, std::uint32_t> top_vertex;
    for (std::size_t t = 0; t < pieces.top_triangles; ++t)
        for (std::uint32_t v : pieces.triangles[t])
            top_vertex[{pieces.vertices[v].uv.x(), pieces.vertices[v].uv.y(), pieces.vertices[v].fragment}] = v;
    auto top_of = [&](std::uint32_t v) {
        return top_vertex.at({pieces.vertices[v].uv.x(), pieces.vertices[v].uv.y(), pieces.vertices[v].fragment});
    };
    std::size_t wrong = 0, checked = 0;
    for (const auto& lip : pieces.lips) {
        const std::uint32_t base = lip[0];
        const std::uint32_t a = top_of(base), b = top_of(base + 1);
        const auto it = third.find({a, b});
        REQUIRE(it != third.end());
        const Vec3 mid = 0.5 * (pieces.vertices[a].position + pieces.vertices[b].position);
        const Vec3 inward = pieces.vertices[it->second].position - mid;
        for (const auto& tri : pieces.triangles) {
            if (tri[0] != base || tri[1] < base || tri[1] > base + 3 || tri[2] < base || tri[2] > base + 3) continue;
            const Vec3 face = (pieces.vertices[tri[1]].position - pieces.vertices[tri[0]].position)
                                  .cross(pieces.vertices[tri[2]].position - pieces.vertices[tri[0]].position);
            if (face.norm() < 1e-14) continue;
            ++checked;
            wrong += face.dot(inward) > 0 || pieces.vertices[base].world_normal.dot(inward) > 0;
        }
    }
    CHECK(checked > pieces.lips.size()); // most walls have an area
    return wrong;
}

} // namespace

TEST_SUITE("post") {
    TEST_CASE("pieces: one solid per fragment with walls down to the background at every crack") {
        const auto& p = cracked();
        REQUIRE(p.num_fragments > 5);
        const post::PieceMesh pieces = post::build_pieces(p, post::PostOptions{});
        CHECK(pieces.fragments == p.num_fragments);
        CHECK(pieces.top_triangles
              == p.mesh.num_faces() - std::size_t(std::count(p.removed.begin(), p.removed.end(), 1)));
        CHECK(pieces.wall_triangles == 2 * p.cracks.size());
        CHECK(pieces.floor_triangles == std::size_t(std::count(p.removed.begin(), p.removed.end(), 1)));
        // Glued: wall bottoms sit on the background; tops at the layer thickness.
        for (const auto& v : pieces.vertices) {
            if (v.crack > 0.5f && v.fragment >= 0) REQUIRE((v.height < 1e-9 || v.height > 0.009));
            if (v.crack < 0.5f) REQUIRE(v.height == doctest::Approx(0.01).epsilon(1e-3));
        }
        for (const auto& tri : pieces.triangles)
            for (std::uint32_t i : tri)
                REQUIRE(i < pieces.vertices.size());
    }

    TEST_CASE("pieces: every triangle winds counter-clockwise seen from outside, every wall faces out of its piece "
              "(plane, cylinder, sphere, glued and curled)") {
        for (const mesh::SurfaceKind kind :
             {mesh::SurfaceKind::Plane, mesh::SurfaceKind::Cylinder, mesh::SurfaceKind::Sphere}) {
            const std::string surface = mesh::to_string(kind);
            CAPTURE(surface);
            test::LayerSpec spec;
            spec.kind = kind;
            spec.size = kind == mesh::SurfaceKind::Sphere ? Vec2(0.08, 0.08) : Vec2(0.3, 0.2);
            spec.elements = 700;
            spec.shrinkage = {3e-4, 3e-4};
            test::Layer layer(spec);
            Rng rng(5, RngStream::Fracture);
            const fracture::CrackPattern p = fracture::run_fem_remove(*layer.model, fracture::FractureOptions{}, rng);
            REQUIRE(p.cracks.size() > 20);
            for (const double curl : {0.0, 1.5}) {
                CAPTURE(curl);
                post::PostOptions o;
                o.curl = curl;
                const post::PieceMesh pieces = post::build_pieces(p, o);
                CHECK(wound_inwards(pieces) == 0);
                CHECK(walls_facing_in(pieces) == 0);
            }
        }
    }

    TEST_CASE("pieces: a crack that stops inside the layer has walls down to its depth and a floor there (§4.3)") {
        test::SpringSpec s;
        s.layer.size = Vec2(0.2, 0.2);
        s.layer.thickness = 0.02;
        s.layer.young = 1e7;
        s.layer.threshold = 2e4;
        s.masses = 500;
        s.options.break_jitter = 0.05;
        s.options.layers = 3;
        s.layer.shrinkage.top_rate = 3e-3; // the top dries first: some cracks stay shallow
        s.layer.shrinkage.bottom_rate = 0.5e-3;
        const auto r = test::run_springs(s);
        const double layer = 0.02 / 3;
        std::size_t shallow = 0;
        for (const auto& c : r.pattern.cracks)
            shallow += c.depth < 0.02 - 1e-9 && c.opening > 0;
        REQUIRE(shallow > 5);
        const post::PieceMesh pieces = post::build_pieces(r.pattern, post::PostOptions{});
        CHECK(wound_inwards(pieces) == 0); // the ledges too
        // Heights of crack geometry are whole numbers of layers below the top (0.02 m): the
        // background (0), or the floor of a one- or two-layer crack (1/3 or 2/3 of the way up).
        std::size_t floors = 0;
        for (const auto& v : pieces.vertices) {
            if (v.crack < 0.5f) continue;
            const double in_layers = v.height / layer;
            CHECK(std::abs(in_layers - std::round(in_layers)) < 0.05);
            floors += v.fragment < 0 && v.height > 0.5 * layer;
        }
        CHECK(floors > 0); // ledges at the depth of shallow cracks
        CHECK(pieces.floor_triangles > 0);
        CHECK(pieces.wall_triangles == 2 * r.pattern.cracks.size());
    }

    TEST_CASE("pieces: further drying opens the cracks at the top while the bottoms stay glued") {
        const auto& p = cracked();
        post::PostOptions o;
        o.shrink_top = 0.1;
        const post::PieceMesh dry = post::build_pieces(p, o);
        const post::PieceMesh wet = post::build_pieces(p, post::PostOptions{});
        // Each wall quad: top a, top b, bottom b, bottom a. The top lip moves into its piece, away
        // from the bottom lip; the bottom lip does not move.
        const std::size_t first_wall_dry = dry.top_triangles, first_wall_wet = wet.top_triangles;
        double opening = 0, bottom_moved = 0;
        for (std::size_t t = 0; t < dry.wall_triangles; t += 2) {
            const auto& td = dry.triangles[first_wall_dry + t];
            const auto& tw = wet.triangles[first_wall_wet + t];
            const post::PieceVertex& top_a = dry.vertices[td[0]];
            const post::PieceVertex& bottom_a = dry.vertices[td[0] + 3];
            const post::PieceVertex& bottom_b = dry.vertices[td[0] + 2];
            const post::PieceVertex& bottom_b_wet = wet.vertices[tw[0] + 2];
            REQUIRE((bottom_b.uv - bottom_b_wet.uv).norm() < 1e-12);
            bottom_moved = std::max(bottom_moved, (bottom_b.uv - bottom_b_wet.uv).norm());
            REQUIRE(bottom_b.height == 0.0);
            REQUIRE(bottom_a.height == 0.0);
            opening += (top_a.uv - bottom_a.uv).norm();
        }
        CHECK(opening / (dry.wall_triangles / 2) * dry.tile_size.x() > 1e-4); // ≥ 0.1 mm on average
        test::record_claim("4.10/4.11", "broken walls open at the top", "mean top-lip opening [m], 10 % top shrinkage",
                           opening / double(dry.wall_triangles / 2) * dry.tile_size.x(), "> 1e-4");
        test::record_claim("4.10/4.11", "glued walls stay closed at the bottom",
                           "largest bottom-lip move [fraction of the tile]", bottom_moved, "< 1e-12");
    }

    TEST_CASE("pieces: in curl mode the rims of cracked pieces end higher than their centres (Fig. 4.11)") {
        // A thicker layer: fewer, larger plates with centres well away from their rims.
        const fracture::CrackPattern p = make_cracked(0.025);
        post::PostOptions o;
        o.curl = 0.5;
        o.curl_width = 1.0;
        const post::PieceMesh curled = post::build_pieces(p, o);
        // Per fragment big enough to have a centre: the highest top vertex (a rim) against the
        // lowest (the centre, farthest from every lip).
        std::map<int, std::pair<double, double>> range; // fragment → (min, max) top height
        std::map<int, int> triangles;
        for (std::size_t t = 0; t < curled.top_triangles; ++t) {
            ++triangles[curled.vertices[curled.triangles[t][0]].fragment];
            for (std::uint32_t i : curled.triangles[t]) {
                const auto& v = curled.vertices[i];
                auto [it, fresh] = range.emplace(v.fragment, std::make_pair(v.height, v.height));
                it->second.first = std::min(it->second.first, v.height);
                it->second.second = std::max(it->second.second, v.height);
            }
        }
        int big = 0, lifted = 0;
        for (const auto& [frag, mm] : range) {
            if (triangles[frag] < 12) continue;
            ++big;
            lifted += mm.second > mm.first + 0.005;
        }
        REQUIRE(big > 3);
        CHECK(lifted == big);
        test::record_claim("4.10/4.11", "curl mode lifts plate edges",
                           "share of plates (≥ 12 triangles) with rim > centre + 5 mm", double(lifted) / double(big),
                           "= 1");
        // Rim vertices (on walls' top edges) average higher than the plain layer.
        double rim = 0;
        int n = 0;
        for (std::size_t t = curled.top_triangles; t < curled.top_triangles + curled.wall_triangles; t += 2) {
            rim += curled.vertices[curled.triangles[t][0]].height;
            ++n;
        }
        CHECK(rim / n > 0.025 + 0.01);
        test::record_claim("4.10/4.11", "curl mode lifts plate edges", "mean rim height [m], layer 0.025 m", rim / n,
                           "> 0.035");
    }

    TEST_CASE("pieces: a bevel lowers the lips and leaves the interior") {
        const auto& p = cracked();
        post::PostOptions o;
        o.bevel = 0.004;
        const post::PieceMesh b = post::build_pieces(p, o);
        double lowest = 1, highest = 0;
        for (std::size_t t = 0; t < b.top_triangles; ++t)
            for (std::uint32_t i : b.triangles[t]) {
                lowest = std::min(lowest, b.vertices[i].height);
                highest = std::max(highest, b.vertices[i].height);
            }
        // (The simulation's own shrinkage thinned the layer by 3e-4·½·2 of its height.)
        CHECK(lowest == doctest::Approx(0.01 - 0.004).epsilon(2e-3));
        CHECK(highest == doctest::Approx(0.01).epsilon(1e-3));
    }
}
