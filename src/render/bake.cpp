#include "render/bake.hpp"

#include "core/log.hpp"
#include "core/timer.hpp"
#include "render/ao.hpp"
#include "render/raster.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::render {

TextureSet bake(const post::PieceMesh& pieces, const BakeOptions& o, GlContext& context) {
    Timer timer;
    RasterOptions raster;
    raster.width = o.width;
    raster.height = o.height;
    // The curves' grooves are cut analytically and read the raster's heights only on the plates,
    // away from their edges: multisampling them changed the mud's 4096² height by at most 2.7 µm
    // (99.9 % of pixels by one 16-bit step or none) and cost 0.3 s. Only the raster grooves use it.
    raster.samples = o.relief.curves ? 1 : o.samples;
    raster.tile = o.tile;
    raster.crack_age = o.crack_age;
    raster.seed = o.seed;
    raster.shader_dir = o.shader_dir;
    RasterLayers layers = rasterize(pieces, raster, context);

    // The crack network smoothed into curves at this map's pixel size (render/crack_curves.hpp).
    CurveOptions curve_options;
    curve_options.wander = o.relief.wander;
    curve_options.wander_wavelength = o.relief.wander_wavelength;
    curve_options.tip_length = o.relief.tip_length;
    curve_options.crack_age = o.crack_age;
    curve_options.metres_per_px =
        std::max(layers.grid.metres_v, layers.grid.metres_u[static_cast<std::size_t>(o.height / 2)]);
    curve_options.seed = o.seed;
    const std::vector<CrackCurve> curves =
        o.relief.curves ? crack_curves(pieces, curve_options) : std::vector<CrackCurve>{};

    ReliefOptions relief_options = o.relief;
    relief_options.bevel = pieces.post_bevel;
    relief_options.curl = pieces.post_curl;
    relief_options.curl_width = pieces.post_curl_width;
    relief_options.element_size = pieces.element_size;
    relief_options.seed = o.seed;
    Timer relief_timer;
    Relief relief;
    if (relief_options.curves) {
        relief = shape_relief_curves(layers, curves, relief_options);
        relabel_cracks(layers, relief);
    } else {
        relief = shape_relief(layers, relief_options);
    }

    TextureSet set;
    set.width = o.width;
    set.height_px = o.height;
    set.height = relief.height;
    set.height_scale = std::max(1e-6, static_cast<double>(*std::max_element(set.height.begin(), set.height.end())));
    set.normal = normals_from_height(layers.grid, set.height);
    const double relief_seconds = relief_timer.seconds();

    Timer ao_timer;
    AoOptions ao;
    ao.radius = o.ao_radius > 0 ? o.ao_radius : 2.0 * std::max(pieces.max_height, 1e-6);
    ao.strength = o.ao_strength;
    ao.tile = o.tile;
    ao.shader_dir = o.shader_dir;
    set.ao = ambient_occlusion(layers.grid, set.height, ao);
    set.ao_seconds = ao_timer.seconds();

    Timer shade_timer;
    ShadingOptions shading = o.shading;
    shading.seed = o.seed;
    Shading s = shade(layers, relief, set.ao, shading);
    set.color = std::move(s.color);
    set.roughness = std::move(s.roughness);
    set.mask = std::move(s.mask);
    set.id = layers.id;
    set.render_seconds = layers.render_seconds + relief_seconds + shade_timer.seconds();
    set.readback_seconds = layers.readback_seconds;
    log::debug("bake ", o.width, "×", o.height, ": raster ", layers.render_seconds, " s, read-back ",
               layers.readback_seconds, " s, relief ", relief_seconds, " s, AO ", set.ao_seconds, " s, shading ",
               shade_timer.seconds(), " s (total ", timer.seconds(), " s)");
    return set;
}

} // namespace crackle::render
