// The layer against the world through its thickness: a shrinkage gradient against the laminate
// and thick-shell solutions (tests/support/thick_shell.hpp), a bonded film's first crack on the
// cylinder and the sphere against the thick shell's top stress, and the energy a straight channel
// crack releases against an independent plane-strain solve of the cross-section
// (tests/support/cross_section.hpp). The thesis' wedge is linear through the thickness (§5.3):
// its thickness strain is constant, so it misses all three; the through-thickness modes of
// sim/wedge_modes.hpp are what these tests ask for.

#include "core/image.hpp"
#include "fracture/fem_split/fem_split.hpp"
#include "mesh/triangulate.hpp"
#include "support/accuracy.hpp"
#include "support/cross_section.hpp"
#include "support/fracture_fixture.hpp"
#include "support/thick_shell.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

using namespace crackle;
using test::LayerSpec;

namespace {

constexpr double H = 0.01; // layer thickness (m)

/// The surfaces: a plane, a cylinder of radius 3.2 cm and a sphere of radius 6 cm (h/R = 0.31
/// and 0.17: strongly curved), with elements about 1 cm across.
struct Surface {
    const char* name;
    mesh::SurfaceKind kind;
    test::Shell shell;
    Vec2 size;
    std::size_t elements;
    double radius;
};
const std::vector<Surface> SURFACES = {
    {"plane", mesh::SurfaceKind::Plane, test::Shell::Plane, Vec2(0.2, 0.2), 800, 0.0},
    {"cylinder", mesh::SurfaceKind::Cylinder, test::Shell::Cylinder, Vec2(0.2, 0.1), 400, 0.2 / TWO_PI},
    {"sphere", mesh::SurfaceKind::Sphere, test::Shell::Sphere, Vec2(0.06, 0.06), 1000, 0.06},
};

/// The first crack: a cylinder and a sphere of radius 10 h, elements about h across (on the
/// strongly curved shells above, a first crack reads the largest nodal stress, which the
/// facets of a coarse polygonal shell scatter by ±3 % at the top face).
const std::vector<Surface> ONSET_SURFACES = {
    {"cylinder", mesh::SurfaceKind::Cylinder, test::Shell::Cylinder, Vec2(0.1 * TWO_PI, 0.05), 1500, 0.1},
    {"sphere", mesh::SurfaceKind::Sphere, test::Shell::Sphere, Vec2(0.1, 0.1), 2900, 0.1},
};

LayerSpec layer_on(const Surface& s, double nu, int order) {
    LayerSpec spec;
    spec.kind = s.kind;
    spec.size = s.size;
    spec.elements = s.elements;
    spec.young = 1e9;
    spec.poisson = nu;
    spec.thickness = H;
    spec.threshold = 1e5;
    spec.fem.thickness_order = order;
    spec.fem.stiffness_refresh = 0; // the stiffness of the shrunk shapes: strains s/(1 − s)
    return spec;
}

/// Mean over the nodes of the largest in-surface principal stress at the top (Pa) at time t:
/// what the fracture criterion reads (§5.7.1).
double top_stress(const LayerSpec& spec, double t) {
    test::Layer layer(spec);
    sim::FemModel& m = *layer.model;
    m.set_time(t);
    m.relax();
    double sum = 0;
    for (std::size_t v = 0; v < m.mesh().num_vertices(); ++v)
        sum += fracture::nodal_stress(m, v).ratio * spec.threshold;
    return sum / double(m.mesh().num_vertices());
}

/// The model's strain for a shrinkage s: linear elasticity about the shrunk rest shape.
double strain(double s) {
    return s / (1 - s);
}

/// The oracle's top stress (the depth the order's criterion reads: the linear wedge reads the
/// Gauss points nearest the top, at 0.887 h; with modes, the top face).
double oracle_top(const Surface& s, double nu, int order, double s_top, double s_bottom) {
    const double depth = order == 1 ? 0.5 * (1 + std::sqrt(0.6)) : 1.0;
    return test::thick_shell_stress(s.shell, 1e9, nu, s.radius, H, strain(s_bottom), strain(s_top), depth).largest();
}

} // namespace

TEST_SUITE("claims") {
    TEST_CASE("oracle thickness: the thick-shell solutions approach the laminate's as the radius grows") {
        // The oracle itself, against the plane: at R = 1000 h a cylinder's and a sphere's top
        // stresses are the laminate's to O(h/R).
        for (test::Shell shell : {test::Shell::Cylinder, test::Shell::Sphere}) {
            const auto flat = test::thick_shell_stress(test::Shell::Plane, 1e9, 0.3, 0, H, 1e-3, 3e-3, 1.0);
            const auto far = test::thick_shell_stress(shell, 1e9, 0.3, 1000 * H, H, 1e-3, 3e-3, 1.0);
            CHECK(std::abs(far.largest() / flat.largest() - 1) < 3e-3);
            CHECK(std::abs(far.hoop / flat.hoop - 1) < 3e-3);
        }
        // Uniform shrinkage on a cylinder: the hoop stress at the top is Lamé's; the axial one is
        // larger (curvature relieves only the hoop direction).
        const auto cyl = test::thick_shell_stress(test::Shell::Cylinder, 1e9, 0.3, 3 * H, H, 1e-3, 1e-3, 1.0);
        CHECK(cyl.hoop < cyl.axial);
        CHECK(cyl.axial < 1e9 / 0.7 * 1e-3);
    }

    TEST_CASE(
        "oracle thickness: a layer shrinking faster at its top has the laminate's top stress on the plane and the "
        "thick shell's on the cylinder and the sphere, at nu = 0.3 and 0.45 (order 3 within 2 %, the linear "
        "wedge misses it)") {
        double worst_linear = 0, worst_order3 = 0;
        for (const Surface& surface : SURFACES)
            for (double nu : {0.3, 0.45})
                for (bool gradient : {false, true})
                    for (int order : {1, 2, 3}) {
                        CAPTURE(std::string(surface.name));
                        CAPTURE(nu);
                        CAPTURE(gradient);
                        CAPTURE(order);
                        LayerSpec spec = layer_on(surface, nu, order);
                        const double s_top = 2e-3, s_bottom = gradient ? 0.0 : 2e-3;
                        spec.shrinkage = {s_top, s_bottom};
                        const double error =
                            top_stress(spec, 1.0) / oracle_top(surface, nu, order, s_top, s_bottom) - 1;
                        CAPTURE(error);
                        const std::string what = std::string(surface.name) + ", nu = " + (nu < 0.4 ? "0.3" : "0.45")
                                                 + (gradient ? ", shrinkage 0.2 % top, 0 bottom" : ", uniform 0.2 %")
                                                 + ", order " + std::to_string(order);
                        test::record_claim(
                            "oracle thickness", "top stress of a shrinking layer = laminate / thick shell",
                            "model / oracle - 1, " + what, error, order == 3 ? "|.| < 0.02" : "recorded");
                        if (order == 3) {
                            CHECK(std::abs(error) < 0.02);
                            worst_order3 = std::max(worst_order3, std::abs(error));
                        }
                        if (order == 1) worst_linear = std::max(worst_linear, std::abs(error));
                    }
        // The thesis' wedge: a constant thickness strain locks the Poisson contraction a gradient
        // needs, and the curvature's too (+97 % on a plane at ν = 0.45).
        CHECK(worst_linear > 0.5);
        test::record_claim("oracle thickness", "the linear wedge misses the through-thickness stress",
                           "largest |model / oracle - 1| of the linear wedge (order 1)", worst_linear, "> 0.5");
        test::record_claim("oracle thickness", "top stress of a shrinking layer = laminate / thick shell",
                           "largest |model / oracle - 1| at order 3 (12 cases)", worst_order3, "< 0.02");
    }

    TEST_CASE("oracle curvature: a bonded film starts cracking on a cylinder and a sphere when the thick shell's top "
              "stress reaches the threshold (within 2 % at order 3)") {
        // fem-split on a uniformly shrinking film with a uniform threshold: the first crack comes
        // when the largest in-surface principal stress at the top reaches it. The oracle's
        // stress is linear in the strain e = s/(1 − s): e* = σ_th / σ(e = 1), s* = e*/(1 + e*).
        for (const Surface& surface : ONSET_SURFACES) {
            for (int order : {1, 3}) {
                CAPTURE(std::string(surface.name));
                CAPTURE(order);
                LayerSpec spec = layer_on(surface, 0.3, order);
                const double rate = 4e-3; // shrinkage per unit time
                spec.shrinkage = {rate, rate};
                const double depth = order == 1 ? 0.5 * (1 + std::sqrt(0.6)) : 1.0;
                const double per_strain =
                    test::thick_shell_stress(surface.shell, 1e9, 0.3, surface.radius, H, 1.0, 1.0, depth).largest();
                const double e_star = spec.threshold / per_strain, s_star = e_star / (1 + e_star);
                const double predicted = s_star / rate;
                // Only the first crack's time is asked: the run stops after it (the cascade that
                // follows in a uniform film would be most of the cost).
                fracture::FractureOptions first_only;
                first_only.max_events = 1;
                const auto run = test::run_split(spec, 2 * predicted, {}, first_only, false);
                REQUIRE(!run.pattern.events.empty());
                const double error = run.pattern.events.front().time / predicted - 1;
                CAPTURE(error);
                test::record_claim("oracle curvature", "bonded film's first crack at the thick shell's onset",
                                   std::string("first crack time / thick-shell onset - 1, ") + surface.name + ", order "
                                       + std::to_string(order),
                                   error, order == 3 ? "|.| < 0.02" : "recorded");
                if (order == 3) CHECK(std::abs(error) < 0.02);
            }
        }
    }

    TEST_CASE("oracle Griffith: a straight channel crack through a bonded film releases the energy of an independent "
              "plane-strain cross-section solve (within 5 % at order 3 with elements h/8 across the crack), "
              "converging under refinement") {
        // A periodic tile 20 h across the crack and 2 h along it, on a staggered grid of points
        // spacing dx (a column of them on the crack line, so the crack is a chain of mesh
        // edges), uniform shrinkage, a direct solve. The crack is opened along the whole column
        // (a channel through the tile), and G = ΔU / (h·L): the steady-state channelling release
        // (Hutchinson & Suo 1992), whose Z = G·Ē/(σ²h) the oracle computes for the same spacing.
        const double W = 20 * H, L = 2 * H, E = 1e9, s = 1e-3;
        for (double nu : {0.3, 0.45}) {
            const double z_oracle = test::oracle::channel_z_rigid(nu, W / H);
            double previous_error = 1;
            for (int order : {1, 2, 3}) {
                std::vector<double> errors;
                for (double dx : {H / 2, H / 4, H / 8}) {
                    CAPTURE(nu);
                    CAPTURE(order);
                    CAPTURE(dx);
                    const mesh::Surface surface = test::make_surface(mesh::SurfaceKind::Plane, W, L);
                    const int nx = static_cast<int>(std::lround(W / dx)), ny = static_cast<int>(std::lround(L / dx));
                    std::vector<Vec2> points;
                    for (int a = 0; a < nx; ++a)
                        for (int b = 0; b < ny; ++b)
                            points.emplace_back((a + 0.5) * W / nx, (b + 0.5 + 0.5 * (a % 2)) * L / ny);
                    sim::PropertyField thickness(H, {}, surface, 1, 1), young(E, {}, surface, 1, 2),
                        threshold(1e6, {}, surface, 1, 3), toughness(1e5, {}, surface, 1, 4);
                    sim::FemOptions fem;
                    fem.thickness_order = order;
                    fem.stiffness_refresh = 0;
                    fem.solver = sim::SolverKind::Direct;
                    sim::FemModel model(mesh::triangulate_periodic(points, surface), surface,
                                        sim::GrowthField({sim::GrowthKind::None, 0, 0, 0}, mesh::SurfaceKind::Plane),
                                        sim::ShrinkageOptions{s, s},
                                        sim::LayerFields{&thickness, &young, &threshold, &toughness, nu}, fem);
                    model.set_time(1.0);
                    model.relax();
                    const double before = model.strain_energy();
                    const double x0 = (nx / 2 + 0.5) * W / nx;
                    std::vector<std::pair<mesh::FaceId, int>> crack;
                    std::set<std::pair<std::size_t, std::size_t>> seen;
                    const mesh::SurfaceMesh& m = model.mesh();
                    for (std::size_t f = 0; f < m.num_faces(); ++f)
                        for (int k = 0; k < 3; ++k) {
                            const mesh::VertexId a = m.faces[mesh::face_id(f)].v[static_cast<std::size_t>(k)];
                            const mesh::VertexId b = m.faces[mesh::face_id(f)].v[static_cast<std::size_t>((k + 1) % 3)];
                            if (std::abs(m.domain[a].x() - x0) > 1e-9 || std::abs(m.domain[b].x() - x0) > 1e-9)
                                continue;
                            if (seen.insert({std::min(mesh::ix(a), mesh::ix(b)), std::max(mesh::ix(a), mesh::ix(b))})
                                    .second)
                                crack.emplace_back(mesh::face_id(f), k);
                        }
                    REQUIRE(crack.size() == static_cast<std::size_t>(ny));
                    model.cut(crack);
                    model.relax();
                    const double G = (before - model.strain_energy()) / (H * L);
                    const double sigma = E * strain(s) / (1 - nu), E_bar = E / (1 - nu * nu);
                    const double error = G * E_bar / (sigma * sigma * H) / z_oracle - 1;
                    CAPTURE(error);
                    errors.push_back(error);
                    test::record_claim("oracle Griffith", "channel crack's energy release = plane-strain cross-section",
                                       "G / G_oracle - 1, nu = " + std::string(nu < 0.4 ? "0.3" : "0.45") + ", order "
                                           + std::to_string(order) + ", elements h/"
                                           + std::to_string(static_cast<int>(std::lround(H / dx))),
                                       error, order == 3 && dx < H / 6 ? "|.| < 0.05" : "recorded");
                }
                // Refinement converges towards the oracle from below: each halving gets closer.
                CHECK(errors[0] < errors[1]);
                CHECK(errors[1] < errors[2]);
                CHECK(errors[2] < 0.01);
                if (order == 3) CHECK(std::abs(errors[2]) < 0.05);
                // Each order releases more (a stiff linear wedge releases too little).
                CHECK(std::abs(errors[2]) < std::abs(previous_error));
                previous_error = errors[2];
            }
        }
    }
    TEST_CASE("oracle Griffith: the tips of the Fig. 5.21 scene stop where a channel crack's released energy meets "
              "G_c (order 2 within 5 % at 800 to 3200 elements, the linear wedge late)") {
        // The scene of the Griffith arrest claim (test_fem_split.cpp): E a tent over v, 1.8 GPa
        // on the middle line and 0.2 GPa at the edges, stretched across v by ε = r·t. A channel
        // crack releases G_ss = Z·σ²h/Ē with σ = Eε/(1 − ν²) (the crack-normal stress of the
        // bonded film) and Z from the cross-section solve, and its wall costs G_c = (1 − ν²)K²/E:
        // a tip stops where E·ε = (1 − ν²)K/√(Z·h), so E(tip)·t(arrest) = (1 − ν²)K/(r√(Zh)) for
        // every tip, absolutely, and the distance of the arrest from the middle line follows.
        auto tent = std::make_shared<GrayImage>();
        tent->width = 1;
        tent->height = 64;
        for (int j = 0; j < 64; ++j)
            tent->pixels.push_back(float(1.0 - std::abs(2.0 * (j + 0.5) / 64 - 1.0)));
        const double K = 6000, r = 8e-5, nu = 0.3, E0 = 1e9, amplitude = 0.8;
        const double Z = test::oracle::channel_z_rigid(nu, 20.0);
        const double balance = (1 - nu * nu) * K / (r * std::sqrt(Z * H));
        for (int order : {1, 2})
            for (std::size_t elements : {800u, 1600u, 3200u}) {
                CAPTURE(order);
                CAPTURE(elements);
                LayerSpec s;
                s.size = Vec2(0.2, 0.2);
                s.elements = elements;
                s.growth = {sim::GrowthKind::Anisotropic, r, 0.0, 0.0};
                s.toughness = K;
                s.young_variation.pattern = sim::PatternKind::Image;
                s.young_variation.image = tent;
                s.young_variation.amplitude = amplitude;
                s.fem.thickness_order = order;
                const auto run = test::run_split(s, 1.0, {}, {}, false);
                test::Layer layer(s);
                REQUIRE(run.split.arrests_at.size() >= 8);
                double ratio = 0, actual_sum = 0, predicted_sum = 0, scatter = 0;
                for (const auto& a : run.split.arrests_at) {
                    const Vec2 uv = layer.surface.uv(a.position);
                    ratio += layer.young.at(a.position, uv) * a.time / balance;
                    // Where E takes the value the balance asks for at that time: E = E0·(1 + a(2g − 1)),
                    // g the tent = 1 − 2|v − ½|, so the distance from the middle line is (1 − g)/2.
                    const double g = ((balance / a.time / E0 - 1) / amplitude + 1) / 2;
                    const double predicted = (1 - g) / 2, actual = std::abs(uv.y() - 0.5);
                    actual_sum += actual;
                    predicted_sum += predicted;
                    scatter += std::abs(actual - predicted);
                }
                const double n = double(run.split.arrests_at.size());
                ratio /= n;
                const double height = actual_sum / predicted_sum - 1; // tile heights: the tile is 1 in v
                scatter /= n;
                CAPTURE(ratio);
                CAPTURE(height);
                CAPTURE(scatter);
                const std::string what =
                    "order " + std::to_string(order) + ", " + std::to_string(elements) + " elements";
                test::record_claim("5.21", "Griffith arrest absolute: E(tip)·t(arrest) = (1 − ν²)K/(r√(Z h))",
                                   "mean E·t / the channel-crack balance, " + what, ratio,
                                   order == 2 ? "|. - 1| < 0.05" : "> 1.05 (arrests early)");
                test::record_claim("5.21", "Griffith arrest absolute: arrest height where G_ss(σ) = G_c",
                                   "mean distance of the arrests from the start line / predicted - 1, " + what, height,
                                   order == 2 ? "|.| < 0.05" : "recorded");
                test::record_claim("5.21", "Griffith arrest absolute: arrest height where G_ss(σ) = G_c",
                                   "mean |arrest - predicted| per tip [tile heights] (a step is an element), " + what,
                                   scatter, "recorded");
                if (order == 2) {
                    CHECK(std::abs(ratio - 1) < 0.05);
                    CHECK(std::abs(height) < 0.05);
                } else {
                    CHECK(ratio > 1.05); // the linear wedge releases too little: tips stop early
                }
            }
        // graph-fem's Griffith test on the same scene (its edge damage softens the elements on
        // a broken edge instead of separating them, and the wall it pays for runs along the
        // dual path): recorded, not met (docs/accuracy.md).
        for (std::size_t elements : {800u, 3200u}) {
            LayerSpec s;
            s.size = Vec2(0.2, 0.2);
            s.elements = elements;
            s.growth = {sim::GrowthKind::Anisotropic, r, 0.0, 0.0};
            s.toughness = K;
            s.young_variation.pattern = sim::PatternKind::Image;
            s.young_variation.image = tent;
            s.young_variation.amplitude = amplitude;
            s.fem.thickness_order = 2;
            const auto run = test::run_graph(s);
            test::Layer layer(s);
            REQUIRE(!run.graph.arrests_at.empty());
            double ratio = 0;
            for (const auto& a : run.graph.arrests_at)
                ratio += layer.young.at(a.position, layer.surface.uv(a.position)) * a.time / balance;
            ratio /= double(run.graph.arrests_at.size());
            test::record_claim("5.21", "Griffith arrest absolute: E(tip)·t(arrest) = (1 − ν²)K/(r√(Z h))",
                               "mean E·t / the channel-crack balance, graph-fem, order 2, " + std::to_string(elements)
                                   + " elements",
                               ratio, "recorded (not met: 1.5-1.7)");
        }
    }
}
