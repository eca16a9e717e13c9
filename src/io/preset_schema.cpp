#include "io/preset_schema.hpp"

#include "fracture/method.hpp"
#include "io/map_set.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <sstream>

namespace crackle::io {
namespace {

using keys::array;
using keys::boolean;
using keys::choice;
using keys::integer;
using keys::integer_or_auto;
using keys::number;
using keys::text;

/// The properties that may vary over the surface (§5.9), each with a [variation.*] section.
const char* const VARYING[] = {"thickness", "young_modulus", "threshold_stress", "toughness"};

std::vector<KeySpec> build_schema() {
    std::vector<KeySpec> s;
    // === [surface]
    s.push_back(choice("surface", "kind", "cylinder", {"plane", "cylinder", "sphere", "mesh"},
                       "Shape of the background: a plane or a tree trunk (both tile seamlessly), a closed sphere, "
                       "or your own model (surface.file; `crackle mesh` remeshes it, simulating and baking on a "
                       "model are not in this version yet)."));
    s.push_back(text("surface", "file", "",
                     "kind = \"mesh\": the model, any format assimp reads (glTF/GLB, OBJ, FBX, COLLADA, PLY, 3DS, "
                     "STL, ...), relative to the preset file."));
    s.push_back(
        text("surface", "node", "",
             "kind = \"mesh\": the node whose meshes to take (with its children); empty = every mesh, merged."));
    s.push_back(integer("surface", "uv_set", 0, "", 0.0, 7.0,
                        "kind = \"mesh\": the texture-coordinate set that is the bake's UV layout."));
    s.push_back(number("surface", "scale", 0.0, "m/unit", 0.0, 1e6,
                       "kind = \"mesh\": metres per model unit; 0 = what the file says (FBX's unit, COLLADA's "
                       "<unit>, glTF's metres), else 1."));
    s.push_back(array("surface", "size", {0.5, 0.5}, 1, 2, "m", 0.0, 1000.0,
                      "plane: [width, height]; cylinder: [circumference, height]; sphere: [radius]. "
                      "The texture covers this area, so cracks look finer on a larger surface.",
                      true));
    // === [growth]
    s.push_back(choice("growth", "kind", "anisotropic", {"isogonic", "anisotropic", "none"},
                       "Background growth (§3.3.1): isogonic = the same rate in every direction (isotropic "
                       "networks); anisotropic = rates r1, r2 (cracks run perpendicular to r1); none = static "
                       "background (mud)."));
    s.push_back(array("growth", "rate", {1.0, 0.0}, 2, 2, "1/time", -10.0, 100.0,
                      "Principal rates [r1, r2]; a rate of 1 doubles a length at t = 1. Isogonic uses r1 only. "
                      "A trunk grows r1 around and r2 = 0 along its axis."));
    s.push_back(number("growth", "angle_deg", 0.0, "deg", -360.0, 360.0,
                       "Direction of r1, degrees from the u axis. Plane: any angle; cylinder and sphere: 0 (r1 "
                       "around the axis) or 90 (r1 along it)."));
    // === [material]
    s.push_back(number("material", "young_modulus", 1.0e10, "Pa", 0.0, 1.0e13,
                       "Stiffness E of the material layer. Scales all stresses; with the threshold it sets how "
                       "much stretch the layer takes before it cracks.",
                       true));
    s.push_back(number("material", "poisson_ratio", 0.3, "", -0.99, 0.5,
                       "Poisson's ratio ν (must stay below 0.5, the incompressible limit).", false, true));
    s.push_back(number("material", "threshold_stress", 2.0e5, "Pa", 0.0, 1.0e12,
                       "Tensile stress at which the layer cracks. Lower = cracks start earlier and the network "
                       "is denser.",
                       true));
    s.push_back(number("material", "toughness", 200.0, "", 0.0, 1.0e12,
                       "Fracture toughness K_IC of the Griffith test (G_IC = (1 − ν²)K_IC²/E, thesis Alg. 11; "
                       "a calibration knob, see docs). Higher = cracks stop sooner: shorter, more separate "
                       "fissures.",
                       true));
    s.push_back(keys::number_or_auto(
        "material", "initiation_length", "m", 0.0, 100.0,
        "The stress that starts a new crack is the top stress averaged over a disc of this radius (quartic "
        "bell weight, along the surface, not across cracks): a crack opens through the whole layer, so a "
        "peak narrower than about the layer cannot start one (the material's critical distance). In "
        "metres, so refining the mesh keeps the physics; where elements are larger than it, a node "
        "averages over its own elements, as the thesis does. \"auto\" = the local layer thickness; 0 = "
        "the thesis' nodal stress (§5.7.1), which sees higher peaks at crack tips on finer meshes "
        "(docs/accuracy.md). fem-split."));
    s.push_back(array("material", "thickness", {0.01, 0.01}, 2, 2, "m", 0.0, 100.0,
                      "Layer thickness [start, end], linear along v (the trunk's axis). Thicker layers give "
                      "fewer, wider cracks and larger plates (Fig. 5.29).",
                      true));
    s.push_back(number("material", "pattern_scale", 0.0, "m", 0.0, 100.0,
                       "Artist control: the typical plate or fissure spacing, in metres ((2 − anisotropy) / crack "
                       "density: 2/ρ for a network, 1/ρ for parallel fissures). When above 0 it sets "
                       "material.thickness (which it overrides) to this spacing over the ratio measured on the "
                       "default presets: 2.73 thicknesses on a plane (mud), 2.11 on a cylinder (bark), 4.8 "
                       "on a sphere (the isogonic skin); a thickness ramp keeps its shape, scaled to that mean. "
                       "Other materials (threshold, shrinkage, toughness) space their cracks differently, so "
                       "treat it as a starting point. 0 = off: material.thickness applies."));
    s.push_back(array("material", "shrinkage", {0.0, 0.0}, 2, 2, "1/time", -10.0, 10.0,
                      "Shrinkage rates [top, bottom] of the layer (§3.3.2), s(t) = rate·t; negative = expansion. "
                      "Drying mud shrinks faster at the top."));
    // === [variation.*]
    for (const char* prop : VARYING) {
        const std::string sec = std::string("variation.") + prop;
        s.push_back(choice(sec, "pattern", "none", {"none", "gradient", "noise", "image"},
                           std::string("How ") + prop
                               + " varies over the surface (§5.9): p = p0·(1 + amplitude·(2g − 1)) with g from a "
                                 "linear gradient, seeded smooth noise, or a grayscale PNG (white = high)."));
        s.push_back(number(sec, "amplitude", 0.3, "", 0.0, 0.95,
                           "Relative variation: values span p0·(1 − amplitude) … p0·(1 + amplitude)."));
        s.push_back(number(sec, "scale", 0.05, "m", 0.0, 1000.0,
                           "Noise feature size. Features of this size make cracks wander and cluster.", true));
        s.push_back(
            integer(sec, "octaves", 3, "", 1, 8, "Noise octaves, each half the size and strength of the last."));
        s.push_back(
            number(sec, "angle_deg", 0.0, "deg", -360.0, 360.0,
                   "Gradient direction in texture space, degrees from u (90 = along v). Gradients do not tile."));
        s.push_back(text(sec, "image", "",
                         "Grayscale PNG mapped over texture space (relative to the preset file). Needs pattern = "
                         "\"image\"."));
    }
    // === [simulation]
    {
        // The methods and their own keys come from the registry (fracture/method.cpp).
        std::string about = "Fracture model: ";
        for (const fracture::MethodInfo& m : fracture::methods())
            about += (&m == &fracture::methods().front() ? "" : ", ") + m.description;
        s.push_back(choice("simulation", "method", "fem-split", fracture::method_names(), about + "."));
    }
    s.push_back(integer_or_auto(
        "simulation", "elements", "", 32, 2.0e6,
        "Triangle count of the starting mesh. \"auto\" = as many as the crack spacing needs: "
        "simulation.elements_per_h2 per square of the thinnest layer thickness over the surface (the "
        "speed-vs-accuracy study's rule, docs/benchmarks.md), capped at one per 8 texture pixels (bake.size), at "
        "least 400 and what a curved surface needs. A number = exactly that many (more = finer crack detail and "
        "slower); a cylinder or sphere needs about six triangles around at least, and fewer is refused, naming "
        "the minimum."));
    s.push_back(number("simulation", "elements_per_h2", 2.0, "", 0.1, 100.0,
                       "Elements per square of the thinnest layer thickness when simulation.elements = \"auto\". "
                       "2 = the default for a preset that has not measured its own; the shipped presets set what "
                       "their converged patterns need: mud's and fruit's T-junctions 4, bark's crack density and "
                       "the isogonic sphere's T-junctions 8, the Siberian elm's 16 (docs/benchmarks.md). "
                       "Lower = faster and coarser (fewer, straighter cracks), higher = slower and closer to "
                       "converged."));
    s.push_back(number("simulation", "duration", 1.0, "time", 0.0, 1000.0,
                       "Simulated time. Growth and shrinkage rates are per unit of it; longer = more, wider cracks.",
                       true));
    s.push_back(integer("simulation", "seed", 1, "", 0, 9.0e18,
                        "Seed of every random choice (points, noise, tie breaks). Same preset + seed = same output."));
    s.push_back(number("simulation", "jitter", 0.25, "", 0.0, 0.5,
                       "Random perturbation δ of the repulsion radii (§5.2.1). 0 tends to a hexagonal lattice; "
                       "0.2–0.3 gives semi-random triangles."));
    s.push_back(integer("simulation", "repulsion_iterations", 100, "", 0, 1000,
                        "Particle-repulsion iterations at most (0 = uniformly random points, poor triangles)."));
    s.push_back(number("simulation", "min_element_size", 0.0, "m", 0.0, 1000.0,
                       "Dynamic subdivision (§5.6.4): an element over threshold but longer than this is "
                       "subdivided instead of cracked, so fine elements appear only where cracks run. 0 = off "
                       "(every element starts at its final size)."));
    s.push_back(choice("simulation", "solver", "cg", {"cg", "direct"},
                       "Equilibrium solver: cg = conjugate gradient warm-started from the last solution (the "
                       "default, fastest per crack event); direct = sparse Cholesky (CHOLMOD)."));
    s.push_back(number("simulation", "solver_tolerance", 1e-9, "", 1e-14, 1e-4,
                       "FEM methods: CG residual relative to the growth/shrinkage load. Looser = faster, less exact "
                       "stresses. At most 1e-4: at 1e-3 a crack event's local change can lie below the tolerance, "
                       "so re-solves stop early and fem-remove's bark pattern lost half its cracks "
                       "(docs/benchmarks.md, stability envelope)."));
    s.push_back(integer("simulation", "thickness_order", 1, "", 1, 3,
                        "FEM methods: polynomial order of the displacement through the layer's thickness. 1 = the "
                        "thesis' linear wedge (constant thickness strain: on the plane a shrinkage gradient's top "
                        "stress comes out high, +16 % at ν = 0.3 and +123 % at ν = 0.45, and a channel crack "
                        "releases 17 % (ν = 0.3) to 34 % (0.45) too little energy); 2 and 3 add through-thickness "
                        "modes (2 or 3 times the unknowns, 3-15 times the time: the laminate stress within 1 % and "
                        "a channel crack's energy within 5 % (order 2, ν = 0.3) on fine meshes; docs/accuracy.md)."));
    s.push_back(integer("simulation", "solver_max_iterations", 20000, "", 1, 1.0e7,
                        "FEM methods: CG iterations before the run fails with exit code 3."));
    s.push_back(integer("simulation", "max_events", 1000000, "", 1, 1.0e8,
                        "Stop after this many fracture events (a safety net; the report says when it was hit)."));
    s.push_back(choice("simulation", "relaxation", "local", {"local", "global"},
                       "FEM methods: after each fracture event re-solve only around it (local, §5.8: grown along "
                       "intact elements until the leftover force is simulation.local_tolerance of the change) or the "
                       "whole layer (global: "
                       "slower, for checking)."));
    s.push_back(number("simulation", "local_tolerance", 1e-2, "", 1e-6, 0.5,
                       "FEM methods, local relaxation: the relaxed set grows until the force left at its edge is "
                       "below this share of the change's own. Smaller = closer to a global solve, slower (a crack's "
                       "effect decays over about 1.6 layer thicknesses; docs/benchmarks.md)."));
    s.push_back(number("simulation", "drift_tolerance", 1e-2, "", 1e-6, 1.0,
                       "FEM methods, local relaxation: after each local re-solve the residual of the whole layer "
                       "is checked (§5.8.3), and past this share of a threshold-level nodal force the layer is "
                       "re-solved globally, so long cascades of cracks cannot drift from the global solution (the "
                       "stress error stays within a few times this share of the threshold; docs/accuracy.md)."));
    s.push_back(choice("simulation", "density", "uniform", {"uniform", "thickness"},
                       "Element density: uniform, or thickness = element size proportional to the local layer "
                       "thickness (fine elements where cracks are dense)."));
    for (const fracture::MethodInfo& m : fracture::methods())
        s.insert(s.end(), m.keys.begin(), m.keys.end());
    // === [post]
    s.push_back(number("post", "curl", 0.0, "", 0.0, 10.0,
                       "0 = pieces stay glued to the background; > 0 = cracked pieces detach and their rims lift, "
                       "by this many layer thicknesses at the edge (Fig. 4.11 bottom, peeling paint)."));
    s.push_back(number("post", "curl_width", 3.0, "", 0.1, 100.0,
                       "How far in from a crack the curl reaches, in layer thicknesses."));
    s.push_back(array("post", "shrinkage", {0.0, 0.0}, 2, 2, "", -0.5, 0.5,
                      "Further shrinkage [top, bottom] after the pattern has formed (drying, weathering): the "
                      "tops pull back from the cracks, which open into V-shaped grooves. Solved with the wedge FEM."));
    s.push_back(number("post", "bevel", 0.0, "m", 0.0, 1.0, "Radius of the rounding of crack lips; 0 = sharp edges."));
    // === [bake]
    s.push_back(integer("bake", "size", 2048, "px", 16, 16384,
                        "Texture size in pixels: the longer side; the other side follows the surface's shape in "
                        "metres, so texels are square (a sphere bakes 2:1 equirectangular). With bake.size_v set, "
                        "the width."));
    s.push_back(integer("bake", "size_v", 0, "px", 0, 16384,
                        "Pixels along v (rows) when set; 0 = follow the surface's shape. `--size 2048x512` sets "
                        "both."));
    s.push_back(integer("bake", "samples", 4, "", 1, 16,
                        "Anti-aliasing samples per pixel (MSAA) of the raster grooves (bake.grooves = raster); 1 = "
                        "none. The curves' grooves are anti-aliased by their own profile and ignore it."));
    s.push_back(
        boolean("bake", "exr", false, "Also write the displacement as a 32-bit float OpenEXR file, in metres."));
    s.push_back(
        array("bake", "color", {0.55, 0.45, 0.35}, 3, 3, "sRGB", 0.0, 1.0,
              "Albedo of the top surface (ridges, plates), sRGB [r, g, b] in 0..1; a little darker lower down."));
    s.push_back(array("bake", "crack_color", {0.12, 0.1, 0.08}, 3, 3, "sRGB", 0.0, 1.0,
                      "Albedo of crack walls and floors, sRGB [r, g, b] in 0..1; darker with depth."));
    s.push_back(number("bake", "color_variation", 0.3, "", 0.0, 1.0,
                       "How much each piece's brightness (and, slightly, hue) varies."));
    s.push_back(number("bake", "grain", 0.15, "", 0.0, 1.0,
                       "Strength of a tiling fine-grain variation in the albedo (0 = flat colour per piece)."));
    s.push_back(number("bake", "grain_size", 0.02, "m", 1e-4, 10.0, "Feature size of the grain across u."));
    s.push_back(number("bake", "grain_stretch", 1.0, "", 0.1, 50.0,
                       "How many times longer grain features are along v than along u (bark fibres: 4–8)."));
    s.push_back(
        number("bake", "roughness", 0.85, "", 0.0, 1.0, "Roughness of the top surface (cracks a little rougher)."));
    s.push_back(number("bake", "roughness_variation", 0.1, "", 0.0, 1.0, "Per-piece roughness variation."));
    s.push_back(number("bake", "ao_radius", 0.0, "m", 0.0, 10.0,
                       "Reach of the ambient occlusion; 0 = twice the layer's height."));
    s.push_back(number("bake", "ao_strength", 1.0, "", 0.0, 4.0, "Darkening of the ambient occlusion map."));
    // Relief: crack grooves and micro-relief (render/relief.cpp)
    s.push_back(number("bake", "crack_width", 0.0, "m", 0.0, 1.0,
                       "How far the first (widest) cracks round down into the plates: the width of a furrow's "
                       "side. Later cracks get less (bake.crack_age). 0 = only post.bevel. Bark: 0.005–0.02."));
    s.push_back(number("bake", "crack_depth", 0.0, "", 0.0, 1.0,
                       "How deep the first cracks cut at the lip, as a share of the layer's height: 1 = furrows "
                       "down to the ground, 0 = as simulated (closed cracks only post.bevel, opened ones to the "
                       "ground)."));
    s.push_back(number("bake", "crack_shape", 0.0, "", 0.0, 1.0,
                       "Profile of the plates' edges: 0 = V-shaped grooves (the lip slopes gently down), 1 = "
                       "rounded ridges (the plate stays high and drops steeply into the furrow, as on bark)."));
    s.push_back(choice("bake", "grooves", "raster", {"raster", "curves"},
                       "Where the grooves are cut from: \"raster\" = the rendered crack pixels (element-scale "
                       "polylines); \"curves\" = the crack network smoothed into curves, with profiles whose "
                       "normals are continuous and tapered tips (in progress: docs/user-guide.md)."));
    s.push_back(number("bake", "crack_wander", 0.0, "m", 0.0, 0.1,
                       "Amplitude of the crack paths' wander below the element size (the bake smooths the "
                       "simulated polylines into curves and lets them wander by this much); 0 = smooth curves "
                       "only. At most a twelfth of the wavelength."));
    s.push_back(number("bake", "crack_wander_wavelength", 0.0, "m", 0.0, 1.0,
                       "Wavelength of the crack paths' wander; 0 = four element lengths."));
    s.push_back(integer("bake", "shape_size", 2048, "px", 256, 16384,
                        "With grooves = \"curves\": the map size (pixels across u) the groove shapes are sized "
                        "for, their slopes turning by at most 9° per pixel there. The shapes are the same in "
                        "metres at every map size (smoother per pixel on larger maps, crisper on smaller ones); "
                        "raise it for crisper grooves when baking larger maps."));
    s.push_back(number("bake", "tip_length", 0.0, "m", 0.0, 1.0,
                       "Over how much of its length a crack's groove narrows and shallows towards a tip, "
                       "closing to a hairline; 0 = grooves keep their width to the tip."));
    s.push_back(number("bake", "crack_age", 0.6, "", 0.0, 1.0,
                       "How much finer the last cracks are than the first (0 = all alike; 1 = the last are "
                       "hairlines). Cracks keep opening after they form, so early ones are wide."));
    s.push_back(number("bake", "fibre_depth", 0.0, "m", 0.0, 0.1,
                       "Height of fibrous streaks along v (bark fibres); 0 = none."));
    s.push_back(number("bake", "fibre_size", 0.004, "m", 1e-4, 1.0, "Spacing of the fibres across u."));
    s.push_back(
        number("bake", "fibre_stretch", 8.0, "", 0.1, 100.0, "How many times longer fibres are along v than across."));
    s.push_back(number("bake", "flake_depth", 0.0, "m", 0.0, 0.1,
                       "Height of flaky scales (cells of random height with sunken edges); 0 = none."));
    s.push_back(number("bake", "flake_size", 0.02, "m", 1e-4, 1.0, "Size of the flakes across u."));
    s.push_back(
        number("bake", "flake_stretch", 1.0, "", 0.1, 100.0, "How many times longer flakes are along v than across."));
    s.push_back(number("bake", "grit_depth", 0.0, "m", 0.0, 0.1,
                       "Height of fine isotropic grit (sand in mud, glaze pitting); 0 = none."));
    s.push_back(number("bake", "grit_size", 0.002, "m", 1e-4, 1.0, "Feature size of the grit."));
    s.push_back(number("bake", "cavity", 0.5, "", 0.0, 1.0,
                       "How much crevices darken the colour map (the occlusion baked into the albedo, as in "
                       "scanned textures)."));
    s.push_back(text("bake", "name", "",
                     "Output name pattern: fields {preset}, {seed}, {variant} and {map} (the map's suffix; without "
                     "it, _{map} is appended: <name>_Color.png); '/' makes subfolders of --out. Empty = {preset} "
                     "(seed lists and batches: {preset}_{seed})."));
    s.push_back(text("bake", "maps", default_maps(),
                     "The maps to write, comma-separated: Color, NormalGL, NormalDX, Displacement, AmbientOcclusion, "
                     "Roughness, Mask, ID, ORM (glTF: occlusion, roughness, metallic) and MaskMap (Unity HDRP/URP: "
                     "metallic, occlusion, detail mask, smoothness)."));
    s.push_back(text("bake", "bit_depth", default_bit_depths(),
                     "Bits per channel of chosen maps, e.g. \"Displacement=16,NormalGL=16\"; the rest are 8-bit. Data "
                     "maps take 8 or 16; Color, ID and MaskMap are 8-bit."));
    return s;
}

} // namespace

const std::vector<KeySpec>& preset_schema() {
    // Rebuilt when the method registry changes (a test's own method): its keys and its name.
    static std::mutex mutex;
    static std::vector<KeySpec> schema;
    static int built_for = -1;
    const std::lock_guard lock(mutex);
    if (built_for != fracture::methods_generation()) {
        schema = build_schema();
        built_for = fracture::methods_generation();
    }
    return schema;
}

const KeySpec* find_key(const std::string& full_name) {
    for (const KeySpec& k : preset_schema())
        if (k.name() == full_name) return &k;
    return nullptr;
}

const std::vector<std::pair<std::string, std::string>>& preset_sections() {
    static const std::vector<std::pair<std::string, std::string>> sections = [] {
        std::vector<std::pair<std::string, std::string>> v = {
            {"surface", "The background surface and its size (thesis Ch. 3)."},
            {"growth", "Background growth, a linear velocity field (§3.3.1)."},
            {"material", "The cracking layer (§3.2, §5.3)."},
        };
        for (const char* prop : VARYING)
            v.emplace_back(std::string("variation.") + prop,
                           std::string("How the layer's ") + prop + " varies over the surface (§5.9).");
        v.emplace_back("simulation", "Discretization and the fracture model (§5.2, Ch. 4–5).");
        v.emplace_back("post", "Post-processing of the crack pattern into pieces (§4.5).");
        v.emplace_back("bake", "Texture baking: maps, colours, anti-aliasing (`crackle bake`, `crackle export`).");
        return v;
    }();
    return sections;
}

namespace {
std::string fmt_number(double x) {
    char buf[32];
    if (x != 0 && (std::abs(x) >= 1e6 || std::abs(x) < 1e-3))
        std::snprintf(buf, sizeof buf, "%.6g", x);
    else
        std::snprintf(buf, sizeof buf, "%.10g", x);
    std::string s = buf;
    // Keep floats recognisable as floats in TOML.
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
    return s;
}
} // namespace

std::string to_toml(const Value& value) {
    if (const auto* d = std::get_if<double>(&value)) return fmt_number(*d);
    if (const auto* i = std::get_if<std::int64_t>(&value)) return std::to_string(*i);
    if (const auto* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
    if (const auto* s = std::get_if<std::string>(&value)) {
        std::string out = "\"";
        for (char c : *s) {
            if (c == '"' || c == '\\') out += '\\';
            out += c;
        }
        return out + "\"";
    }
    const auto& a = std::get<std::vector<double>>(value);
    std::string out = "[";
    for (std::size_t k = 0; k < a.size(); ++k)
        out += (k ? ", " : "") + fmt_number(a[k]);
    return out + "]";
}

std::string range_text(const KeySpec& spec) {
    switch (spec.type) {
    case ValueType::Enum: {
        std::string out;
        for (std::size_t k = 0; k < spec.choices.size(); ++k)
            out += (k ? " | " : "") + spec.choices[k];
        return out;
    }
    case ValueType::String:
        return "text";
    case ValueType::Bool:
        return "true | false";
    default:
        break;
    }
    auto bound = [&](double v) {
        if (spec.type == ValueType::Int) {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.0f", v);
            return std::string(buf);
        }
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", v);
        return std::string(buf);
    };
    std::string r = std::string(spec.min_exclusive ? "(" : "[") + bound(spec.min) + ", " + bound(spec.max)
                    + (spec.max_exclusive ? ")" : "]");
    if (spec.allows_auto) r = "auto | " + r;
    if (spec.type == ValueType::FloatArray) {
        const std::string len = spec.min_length == spec.max_length
                                    ? std::to_string(spec.min_length)
                                    : std::to_string(spec.min_length) + "–" + std::to_string(spec.max_length);
        r = len + " × " + r;
    }
    return r;
}

std::string check_value(const KeySpec& spec, const Value& value) {
    auto in_range = [&](double x) {
        if (!std::isfinite(x)) return false;
        if (spec.min_exclusive ? x <= spec.min : x < spec.min) return false;
        if (spec.max_exclusive ? x >= spec.max : x > spec.max) return false;
        return true;
    };
    std::ostringstream os;
    switch (spec.type) {
    case ValueType::Float:
        if (spec.allows_auto && std::holds_alternative<std::string>(value)) {
            if (std::get<std::string>(value) != "auto") os << "must be \"auto\" or a number";
            break;
        }
        if (!in_range(std::get<double>(value))) os << "must be in " << range_text(spec);
        break;
    case ValueType::Int:
        if (spec.allows_auto && std::holds_alternative<std::string>(value)) {
            if (std::get<std::string>(value) != "auto") os << "must be \"auto\" or a whole number";
            break;
        }
        {
            // Compared as integers: through a double, 9000000000000000001 passes a bound of 9e18.
            const std::int64_t v = std::get<std::int64_t>(value);
            const auto bound = [](double b) {
                return b >= 9.2e18 ? INT64_MAX : b <= -9.2e18 ? INT64_MIN : static_cast<std::int64_t>(b);
            };
            const std::int64_t lo = bound(spec.min), hi = bound(spec.max);
            const bool below = spec.min_exclusive ? v <= lo : v < lo;
            const bool above = spec.max_exclusive ? v >= hi : v > hi;
            if (below || above || !in_range(static_cast<double>(v))) os << "must be in " << range_text(spec);
        }
        break;
    case ValueType::Enum: {
        const auto& s = std::get<std::string>(value);
        bool found = false;
        for (const auto& c : spec.choices)
            found = found || c == s;
        if (!found) os << "must be one of " << range_text(spec);
        break;
    }
    case ValueType::FloatArray: {
        const auto& a = std::get<std::vector<double>>(value);
        const int n = static_cast<int>(a.size());
        if (n < spec.min_length || n > spec.max_length) {
            os << "must have "
               << (spec.min_length == spec.max_length
                       ? std::to_string(spec.min_length)
                       : std::to_string(spec.min_length) + " to " + std::to_string(spec.max_length))
               << " elements, not " << n;
            break;
        }
        for (double x : a)
            if (!in_range(x)) {
                os << "each element must be in " << range_text(spec).substr(range_text(spec).find("× ") + 3);
                break;
            }
        break;
    }
    case ValueType::Bool:
    case ValueType::String:
        break;
    }
    return os.str();
}

std::string schema_markdown() {
    std::ostringstream md;
    md << "# Preset reference\n\n"
       << "Generated by `crackle presets doc` from the schema in `src/io/preset_schema.cpp`; do not edit by hand.\n"
       << "A test checks that this file matches the schema.\n\n"
       << "Presets are TOML files. `extends = \"NAME\"` at the top inherits every key of another preset\n"
       << "(a built-in name such as `bark`, or a path relative to this file, without `.toml`);\n"
       << "keys set here override it. Unset keys take the defaults below. On the command line,\n"
       << "`--set section.key=value` overrides any key with the same type checks, and `--seed N` sets\n"
       << "`simulation.seed`. Unknown keys, wrong types and out-of-range values are errors (exit code 2)\n"
       << "naming the file and line.\n\n"
       << "`crackle presets show NAME` prints a preset fully resolved, defaults included.\n";
    for (const auto& [section, about] : preset_sections()) {
        md << "\n## [" << section << "]\n\n" << about << "\n\n";
        md << "| key | type | default | unit | range | description |\n|---|---|---|---|---|---|\n";
        std::string group; // keys one fracture method reads come last, in a table of their own
        for (const KeySpec& k : preset_schema()) {
            if (k.section != section) continue;
            if (k.group != group) {
                group = k.group;
                md << "\n### [" << section << "] keys of " << group << "\n\n"
                   << "| key | type | default | unit | range | description |\n|---|---|---|---|---|---|\n";
            }
            const char* type = "";
            switch (k.type) {
            case ValueType::Float:
                type = "float";
                break;
            case ValueType::Int:
                type = "integer";
                break;
            case ValueType::Bool:
                type = "bool";
                break;
            case ValueType::String:
                type = "string";
                break;
            case ValueType::Enum:
                type = "choice";
                break;
            case ValueType::FloatArray:
                type = "float array";
                break;
            }
            std::string range = range_text(k);
            for (std::size_t p = range.find('|'); p != std::string::npos; p = range.find('|', p + 2))
                range.replace(p, 1, "\\|");
            md << "| `" << k.key << "` | " << type << " | `" << to_toml(k.default_value) << "` | " << k.unit << " | "
               << range << " | " << k.description << " |\n";
        }
    }
    return md.str();
}

} // namespace crackle::io
