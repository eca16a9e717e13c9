#include "app/run/options.hpp"

#include "core/error.hpp"
#include "io/model_file.hpp"
#include "io/png.hpp"
#include "io/resolution.hpp"

#include <cmath>

namespace crackle::app {

// === [surface], [growth], [variation.*]

mesh::SurfaceOptions surface_options(const io::Preset& preset) {
    mesh::SurfaceOptions o;
    const std::string kind = preset.text("surface.kind");
    o.kind = kind == "plane"    ? mesh::SurfaceKind::Plane
             : kind == "sphere" ? mesh::SurfaceKind::Sphere
             : kind == "mesh"   ? mesh::SurfaceKind::Mesh
                                : mesh::SurfaceKind::Cylinder;
    const auto& size = preset.numbers("surface.size");
    o.size = Vec2(size[0], size.size() > 1 ? size[1] : size[0]);
    if (o.kind == mesh::SurfaceKind::Mesh) {
        io::ModelOptions m;
        m.node = preset.text("surface.node");
        m.uv_set = static_cast<int>(preset.integer("surface.uv_set"));
        m.scale = preset.number("surface.scale");
        m.where = preset.entry("surface.file").source.text() + ": surface.file";
        o.model = std::make_shared<const mesh::ModelSurface>(io::read_model(preset.path("surface.file"), m));
    }
    return o;
}

sim::GrowthOptions growth_options(const io::Preset& preset) {
    sim::GrowthOptions o;
    const std::string kind = preset.text("growth.kind");
    o.kind = kind == "none"       ? sim::GrowthKind::None
             : kind == "isogonic" ? sim::GrowthKind::Isogonic
                                  : sim::GrowthKind::Anisotropic;
    const auto& rate = preset.numbers("growth.rate");
    o.r1 = rate[0];
    o.r2 = rate[1];
    o.angle_deg = preset.number("growth.angle_deg");
    return o;
}

sim::VariationOptions variation_options(const io::Preset& preset, const std::string& property) {
    const std::string sec = "variation." + property + ".";
    sim::VariationOptions o;
    const std::string pattern = preset.text(sec + "pattern");
    o.pattern = pattern == "gradient" ? sim::PatternKind::Gradient
                : pattern == "noise"  ? sim::PatternKind::Noise
                : pattern == "image"  ? sim::PatternKind::Image
                                      : sim::PatternKind::None;
    o.amplitude = preset.number(sec + "amplitude");
    o.scale = preset.number(sec + "scale");
    o.octaves = static_cast<int>(preset.integer(sec + "octaves"));
    o.angle_deg = preset.number(sec + "angle_deg");
    if (o.pattern == sim::PatternKind::Image) {
        try {
            o.image = std::make_shared<GrayImage>(io::read_png_gray(preset.path(sec + "image")));
        } catch (const InputError& e) {
            throw InputError(preset.entry(sec + "image").source.text() + ": " + e.what());
        }
    }
    return o;
}

// === [simulation]: the keys every method reads (each method maps its own, in its folder)

sim::FemOptions fem_options(const io::Preset& preset) {
    sim::FemOptions o;
    o.solver = preset.text("simulation.solver") == "direct" ? sim::SolverKind::Direct : sim::SolverKind::Cg;
    o.tolerance = preset.number("simulation.solver_tolerance");
    o.max_iterations = static_cast<int>(preset.integer("simulation.solver_max_iterations"));
    o.thickness_order = static_cast<int>(preset.integer("simulation.thickness_order"));
    return o;
}

fracture::FractureOptions fracture_options(const io::Preset& preset) {
    fracture::FractureOptions o;
    o.duration = preset.number("simulation.duration");
    o.min_element_size = preset.number("simulation.min_element_size");
    o.max_events = static_cast<std::size_t>(preset.integer("simulation.max_events"));
    o.local_relaxation = preset.text("simulation.relaxation") == "local";
    o.local_tolerance = preset.number("simulation.local_tolerance");
    o.drift_tolerance = preset.number("simulation.drift_tolerance");
    return o;
}

// === [post], [bake]

post::PostOptions post_options(const io::Preset& preset) {
    post::PostOptions o;
    o.curl = preset.number("post.curl");
    o.curl_width = preset.number("post.curl_width");
    const auto& s = preset.numbers("post.shrinkage");
    o.shrink_top = s[0];
    o.shrink_bottom = s[1];
    o.bevel = preset.number("post.bevel");
    return o;
}

namespace {
/// sRGB → linear (the shaders work in linear light; the colour target encodes back).
Vec3 linear_from_srgb(const std::vector<double>& c) {
    auto f = [](double x) { return x <= 0.04045 ? x / 12.92 : std::pow((x + 0.055) / 1.055, 2.4); };
    return Vec3(f(c[0]), f(c[1]), f(c[2]));
}
} // namespace

render::BakeOptions bake_options(const io::Preset& preset) {
    render::BakeOptions o;
    const io::MapSize map = io::map_size(preset);
    o.width = map.width;
    o.height = map.height;
    o.samples = static_cast<int>(preset.integer("bake.samples"));
    render::ShadingOptions& s = o.shading;
    s.color = linear_from_srgb(preset.numbers("bake.color"));
    s.crack_color = linear_from_srgb(preset.numbers("bake.crack_color"));
    s.color_variation = preset.number("bake.color_variation");
    s.grain = preset.number("bake.grain");
    s.grain_size = preset.number("bake.grain_size");
    s.grain_stretch = preset.number("bake.grain_stretch");
    s.roughness = preset.number("bake.roughness");
    s.roughness_variation = preset.number("bake.roughness_variation");
    s.cavity = preset.number("bake.cavity");
    render::ReliefOptions& r = o.relief;
    r.crack_width = preset.number("bake.crack_width");
    r.crack_depth = preset.number("bake.crack_depth");
    r.crack_shape = preset.number("bake.crack_shape");
    r.curves = preset.text("bake.grooves") == "curves";
    r.wander = preset.number("bake.crack_wander");
    r.wander_wavelength = preset.number("bake.crack_wander_wavelength");
    r.tip_length = preset.number("bake.tip_length");
    r.shape_size = static_cast<int>(preset.integer("bake.shape_size"));
    r.fibre = {preset.number("bake.fibre_depth"), preset.number("bake.fibre_size"),
               preset.number("bake.fibre_stretch")};
    r.flake = {preset.number("bake.flake_depth"), preset.number("bake.flake_size"),
               preset.number("bake.flake_stretch")};
    r.grit = {preset.number("bake.grit_depth"), preset.number("bake.grit_size"), 1.0};
    o.crack_age = preset.number("bake.crack_age");
    o.ao_radius = preset.number("bake.ao_radius");
    o.ao_strength = preset.number("bake.ao_strength");
    o.seed = static_cast<std::uint32_t>(preset.integer("simulation.seed") & 0xffffffff);
    return o;
}

render::BakeOptions bake_options(const io::Preset& preset, const post::PieceMesh& pieces) {
    render::BakeOptions o = bake_options(preset);
    const io::MapSize map = io::map_request(preset).on(pieces.tile_size);
    o.width = map.width;
    o.height = map.height;
    return o;
}

} // namespace crackle::app
